/* The scene format's entry points and its top level: files, includes, the
 * second pass that resolves names and builds the scene (loader.h). */
#include "loader.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/array.h"
#include "scene/settings.h"

/* ---- files ------------------------------------------------------------ */

static const char *const top_keys[] = {"image",    "camera",    "ambient", "fog",
                                       "lights",   "textures",  "materials", "objects",
                                       "include",  "animation", NULL};


static glint_rc load_text(loader *L, const char *text, size_t len, char *data, const char *name,
                          const char *key, const char *dir);
static glint_rc read_fd(int fd, char **data, size_t *size, glint_error *err);

static glint_rc load_include(loader *L, uint32_t v)
{
    glint_rc rc = load_path_key(L, v, "include");
    if (rc != GLINT_OK)
        return rc;
    const char *written = ydoc_text(load_doc(L), load_node(L, v));
    char *path = path_join(L->files[L->cur].dir, written);
    char *dir = path ? path_dir(path) : NULL;
    char *name = path ? path_printable(path) : NULL;
    char *data = NULL;
    if (!path || !dir || !name) {
        rc = err_nomem(L->err);
        goto out;
    }
    L->via[L->depth - 1] = v;
    for (int k = 0; k < L->depth; k++) {
        if (strcmp(L->files[L->chain[k]].key, path) != 0)
            continue;
        char cycle[800];
        size_t o = 0;
        for (int j = k; j < L->depth && o < sizeof cycle; j++)
            o += (size_t)snprintf(cycle + o, sizeof cycle - o, "%s -> ",
                                  L->files[L->chain[j]].name);
        if (o < sizeof cycle)
            snprintf(cycle + o, sizeof cycle - o, "%s", name);
        rc = load_fail_in(L, L->chain[k], L->via[k], "include cycle: %s", cycle);
        goto out;
    }
    if (L->depth >= LOAD_MAX_INCLUDE_DEPTH) {
        rc = load_fail(L, v, "includes nested more than %d deep", LOAD_MAX_INCLUDE_DEPTH);
        goto out;
    }
    if (L->nfiles >= LOAD_MAX_FILES) {
        rc = load_fail(L, v, "more than %d files included", LOAD_MAX_FILES);
        goto out;
    }
    size_t size;
    rc = load_named_file(L, v, written, path, "include", &data, &size);
    if (rc != GLINT_OK)
        goto out;
    int from = L->cur;
    rc = load_text(L, data, size, data, name, path, dir);
    data = NULL; /* owned by the loader now */
    L->cur = from;
out:
    free(data);
    free(path);
    free(dir);
    free(name);
    return rc;
}

/* Reads one file's top level, then its includes. */
static glint_rc load_top(loader *L, uint32_t root)
{
    const ydoc *d = load_doc(L);
    if (root == YDOC_NONE || load_node(L, root)->kind == YNODE_NULL) {
        uint32_t line = root == YDOC_NONE ? 1 : load_node(L, root)->line;
        uint32_t col = root == YDOC_NONE ? 1 : load_node(L, root)->col;
        return err_set(L->err, GLINT_ERR_INPUT,
                       "%s:%u:%u: the scene is empty (expected a mapping with keys such as "
                       "camera, lights and objects)",
                       L->files[L->cur].name, line, col);
    }
    if (load_node(L, root)->kind != YNODE_MAP) {
        char got[SHOWN + 32];
        ydoc_describe(d, load_node(L, root), got, sizeof got);
        return load_fail(L, root, "expected a mapping at the top of the scene, got %s", got);
    }
    glint_rc rc = load_check_keys(L, root, top_keys, "at the top level");
    const ynode *m = load_node(L, root);
    uint32_t include = YDOC_NONE;
    for (uint32_t i = 0; rc == GLINT_OK && i < m->count; i++) {
        const ynode *k = load_node(L, ydoc_key(d, m, i));
        const char *key = ydoc_text(d, k);
        uint32_t v = ydoc_value(d, m, i);
        vec3 c;
        if (strcmp(key, "image") == 0) {
            rc = load_image_settings(L, v);
        } else if (strcmp(key, "camera") == 0) {
            rc = load_camera(L, v);
        } else if (strcmp(key, "animation") == 0) {
            rc = load_animation(L, v);
        } else if (strcmp(key, "ambient") == 0) {
            rc = load_color(L, v, "ambient", &c);
            if (rc == GLINT_OK && load_claim(L, SET_AMBIENT))
                L->ambient = c;
        } else if (strcmp(key, "fog") == 0) {
            rc = load_fog(L, v);
        } else if (strcmp(key, "lights") == 0) {
            rc = load_list(L, v, "lights", load_light);
        } else if (strcmp(key, "textures") == 0) {
            rc = load_named(L, v, true);
        } else if (strcmp(key, "materials") == 0) {
            rc = load_named(L, v, false);
        } else if (strcmp(key, "objects") == 0) {
            /* most items are one object with one transform */
            if (load_node(L, v)->kind == YNODE_SEQ && load_node(L, v)->count <= INT_MAX)
                scene_reserve_objects(L->s, (int)load_node(L, v)->count);
            rc = load_list(L, v, "objects", load_object);
        } else {
            include = v;
        }
    }
    if (rc != GLINT_OK || include == YDOC_NONE)
        return rc;
    /* Included files add to what this one has, after it. */
    if (load_node(L, include)->kind == YNODE_SEQ)
        return load_list(L, include, "include", load_include);
    if (load_node(L, include)->kind != YNODE_STRING)
        return load_expected(L, include, "a file path or a list of them", "include");
    return load_include(L, include);
}

/* Parses a file's text (data, when non-null, is handed over to the loader)
 * and reads it; name is shown in messages, key identifies it for include
 * cycles, dir is where its relative paths start. */
static glint_rc load_text(loader *L, const char *text, size_t len, char *data, const char *name,
                          const char *key, const char *dir)
{
    int f = array_push((void **)&L->files, &L->nfiles, &L->cap_files, sizeof *L->files);
    if (f < 0) {
        free(data);
        return err_nomem(L->err);
    }
    lfile *lf = &L->files[f];
    lf->data = data;
    lf->name = strdup(name);
    lf->key = strdup(key);
    lf->dir = strdup(dir ? dir : "");
    if (!lf->name || !lf->key || !lf->dir)
        return err_nomem(L->err);
    glint_rc rc = ydoc_parse(text, len, name, &lf->doc, L->err);
    /* The tree holds copies of every scalar: the text is done with. */
    free(lf->data);
    lf->data = NULL;
    if (rc != GLINT_OK)
        return rc;
    L->cur = f;
    L->chain[L->depth++] = f;
    rc = load_top(L, lf->doc->root);
    L->depth--;
    return rc;
}

/* ---- after every file ------------------------------------------------- */

static glint_rc set_texture(loader *L, const ref *r, int index)
{
    scene_set_material_texture(L->s, r->index, index);
    return GLINT_OK;
}

/* A bump pattern is a function of a point in space: its gradient is taken
 * there (texture.h). */
static glint_rc set_bump(loader *L, const ref *r, int index)
{
    if (L->s->textures[index].space == SPACE_UV)
        return load_fail_in(L, r->file, r->node,
                            "a bump pattern must be in space object or world (its gradient "
                            "is taken in space), not on (u, v)");
    scene_set_material_bump(L->s, r->index, index);
    return GLINT_OK;
}

static glint_rc set_material(loader *L, const ref *r, int index)
{
    scene_set_object_material(L->s, r->index, index);
    return GLINT_OK;
}

static glint_rc set_csg_material(loader *L, const ref *r, int index)
{
    scene_set_csg_material(L->s, r->index, r->leaf, index);
    return GLINT_OK;
}

/* Resolves the names materials give textures (and bump patterns), or
 * objects (and csg operands) materials, through set. */
static glint_rc resolve(loader *L, const ref *refs, int n, const names *table, const char *what,
                        glint_rc (*set)(loader *, const ref *, int))
{
    for (int i = 0; i < n; i++) {
        const ydoc *d = L->files[refs[i].file].doc;
        const ynode *nn = ydoc_node(d, refs[i].node);
        const char *name = ydoc_text(d, nn);
        int at = names_find(table, name, nn->count);
        if (at >= 0) {
            glint_rc rc = set(L, &refs[i], L->defs[at].index);
            if (rc != GLINT_OK)
                return rc;
            continue;
        }
        char buf[SHOWN], hint[SHOWN + 32] = "";
        ydoc_show(name, nn->count, buf, sizeof buf);
        const char *near = names_suggest(table, name, nn->count);
        if (near) {
            char nb[SHOWN];
            ydoc_show(near, strlen(near), nb, sizeof nb);
            snprintf(hint, sizeof hint, " (did you mean '%s'?)", nb);
        } else if (table->count == 0) {
            snprintf(hint, sizeof hint, " (no %ss are defined)", what);
        }
        return load_fail_in(L, refs[i].file, refs[i].node, "unknown %s '%s'%s", what, buf, hint);
    }
    return GLINT_OK;
}

/* What the projection needs of the rest of the camera. */
static glint_rc check_projection(loader *L)
{
    const camera *c = &L->camera;
    if (c->projection == CAMERA_PERSPECTIVE && !(c->hfov < 180.0f))
        return load_fail_in(L, L->fov_file, L->fov_node,
                            "fov must be > 0 and < 180 degrees (got %g)", (double)c->hfov);
    if (c->projection == CAMERA_ORTHOGRAPHIC && L->width_node == YDOC_NONE)
        return load_fail_in(L, L->camera_file, L->camera_node,
                            "an orthographic camera needs 'width' (of the view, in scene units)");
    return GLINT_OK;
}

static glint_rc finish(loader *L)
{
    glint_rc rc = resolve(L, L->texture_refs, L->ntexture_refs, &L->texture_names, "texture",
                          set_texture);
    if (rc == GLINT_OK)
        rc = resolve(L, L->bump_refs, L->nbump_refs, &L->texture_names, "texture", set_bump);
    if (rc == GLINT_OK)
        rc = resolve(L, L->material_refs, L->nmaterial_refs, &L->material_names, "material",
                     set_material);
    if (rc == GLINT_OK)
        rc = resolve(L, L->csg_refs, L->ncsg_refs, &L->material_names, "material",
                     set_csg_material);
    if (rc != GLINT_OK)
        return rc;
    glint_error serr = {0};
    if (settings_check(&L->settings, &serr) != GLINT_OK) {
        if (L->size_file < 0)
            return err_set(L->err, GLINT_ERR_INPUT, "%s", serr.msg);
        return load_fail_in(L, L->size_file, L->size_node, "%s", serr.msg);
    }
    const camera *c = &L->camera;
    vec3 view = v3_sub(c->target, c->eye);
    if (L->camera_file >= 0 && v3_is_zero(view))
        return load_fail_in(L, L->camera_file, L->camera_node, "camera look_at must differ from eye");
    if (L->camera_file >= 0 && v3_is_zero(v3_cross(view, c->up)))
        return load_fail_in(L, L->camera_file, L->camera_node,
                       "camera up must not be parallel to the view direction");
    rc = check_projection(L);
    if (rc != GLINT_OK)
        return rc;
    scene_set_settings(L->s, &L->settings);
    scene_set_camera(L->s, &L->camera);
    scene_set_background(L->s, L->background);
    scene_set_ambient(L->s, L->ambient);
    scene_set_fog(L->s, &L->fog);
    /* every animated value at the first frame's time (this builds) */
    return scene_set_time(L->s, L->s->anim.start, L->err);
}

static void loader_free(loader *L)
{
    for (int i = 0; i < L->nfiles; i++) {
        free(L->files[i].name);
        free(L->files[i].key);
        free(L->files[i].dir);
        free(L->files[i].data);
        ydoc_free(L->files[i].doc);
    }
    free(L->files);
    names_free(&L->texture_names);
    names_free(&L->material_names);
    names_free(&L->images);
    names_free(&L->meshes);
    free(L->defs);
    free(L->texture_refs);
    free(L->material_refs);
    free(L->pending);
    free(L->step_room);
    free(L->channel_room);
    free(L->image_jobs); /* emptied by load_decode_images */
    free(L->bump_refs);
    free(L->csg_refs);
}

static glint_rc load(const char *text, size_t len, char *data, const char *name, const char *dir,
                     scene_reader reader, void *user, int threads, scene **out, glint_error *err)
{
    loader L = {.reader = reader ? reader : scene_read_file,
                .user = user,
                .err = err,
                .default_material = -1,
                .size_file = -1,
                .camera_file = -1,
                .width_node = YDOC_NONE};
    glint_rc rc = GLINT_OK;
    char *key = path_join(NULL, name);
    L.s = scene_new();
    if (!L.s || !key) {
        free(data);
        rc = err_nomem(err);
        goto out;
    }
    L.s->threads = threads;
    if (L.reader == scene_read_file) {
        int source = scene_add_source(L.s, name);
        if (source < 0) {
            free(data);
            rc = err_nomem(err);
            goto out;
        }
        scene_source_read(L.s, source, text, len);
    }
    L.settings = scene_settings(L.s);
    L.camera = scene_camera(L.s);
    L.background = scene_background(L.s);
    L.ambient = scene_ambient(L.s);
    L.fog = scene_fog(L.s);
    rc = load_text(&L, text, len, data, name, key, dir);
    rc = load_decode_images(&L, rc);
    if (rc == GLINT_OK)
        rc = finish(&L);
out:
    free(key);
    loader_free(&L);
    if (rc != GLINT_OK) {
        scene_free(L.s);
        return rc;
    }
    *out = L.s;
    return GLINT_OK;
}

glint_rc scene_load_text(const char *text, size_t len, const char *name, const char *base_dir,
                         scene_reader reader, void *user, scene **out, glint_error *err)
{
    return scene_load_text_threads(text, len, name, base_dir, reader, user, 0, out, err);
}

glint_rc scene_load_text_threads(const char *text, size_t len, const char *name,
                                 const char *base_dir, scene_reader reader, void *user,
                                 int threads, scene **out, glint_error *err)
{
    return load(text, len, NULL, name, base_dir, reader, user, threads, out, err);
}

/* The scene file named "-" (or "/dev/stdin") is standard input, read to
 * its end whatever it is (a pipe, a terminal); its includes and textures
 * are relative to the current folder, and messages call it <stdin>. */
static bool is_stdin(const char *path)
{
    return strcmp(path, "-") == 0 || strcmp(path, "/dev/stdin") == 0;
}

glint_rc scene_load_file(const char *path, scene **out, glint_error *err)
{
    return scene_load_file_threads(path, 0, out, err);
}

glint_rc scene_load_file_threads(const char *path, int threads, scene **out, glint_error *err)
{
    bool in = is_stdin(path);
    const char *name = in ? "<stdin>" : path;
    char *data = NULL, *dir = path_dir(in ? "" : path);
    size_t size = 0;
    glint_error rerr = {0};
    if (!dir)
        return err_nomem(err);
    glint_rc rc = in ? read_fd(STDIN_FILENO, &data, &size, &rerr)
                     : scene_read_file(NULL, path, &data, &size, &rerr);
    if (rc == GLINT_ERR_NOMEM)
        rc = err_nomem(err);
    else if (rc != GLINT_OK)
        rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot read scene: %s", name, rerr.msg);
    if (rc == GLINT_OK)
        rc = load(data, size, data, name, dir, scene_read_file, NULL, threads, out, err);
    free(dir);
    return rc;
}

/* Reads fd to its end, at most LOAD_MAX_FILE_BYTES. The text is freed with free(). */
static glint_rc read_fd(int fd, char **data, size_t *size, glint_error *err)
{
    size_t n = 0, cap = 1 << 16;
    /* a regular file in one block of its size and a byte (which the end's
     * read of 0 needs), rather than doubled up to it */
    struct stat st;
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0)
        cap = (uint64_t)st.st_size < LOAD_MAX_FILE_BYTES ? (size_t)st.st_size + 1
                                                         : (size_t)LOAD_MAX_FILE_BYTES + 1;
    char *buf = array_realloc(NULL, 0, cap);
    if (!buf)
        return err_nomem(err);
    for (;;) {
        ssize_t k = read(fd, buf + n, cap - n);
        if (k < 0 && errno == EINTR)
            continue;
        if (k < 0) {
            free(buf);
            return err_set(err, GLINT_ERR_IO, "%s", strerror(errno));
        }
        if (k == 0)
            break; /* end of file */
        n += (size_t)k;
        if (n < cap)
            continue;
        if (n > LOAD_MAX_FILE_BYTES) {
            free(buf);
            return err_set(err, GLINT_ERR_INPUT, "the file is larger than the %u-byte limit",
                           LOAD_MAX_FILE_BYTES);
        }
        /* One byte past the limit tells a file of exactly the limit from a larger one. */
        size_t ncap = cap * 2 > (size_t)LOAD_MAX_FILE_BYTES + 1 ? (size_t)LOAD_MAX_FILE_BYTES + 1
                                                                : cap * 2;
        char *bigger = array_realloc(buf, n, ncap);
        if (!bigger) {
            free(buf);
            return err_nomem(err);
        }
        buf = bigger;
        cap = ncap;
    }
    *data = buf;
    *size = n;
    return GLINT_OK;
}

glint_rc load_open_regular(const char *path, int *fd, glint_error *err)
{
    /* Without blocking: a FIFO would wait for a writer for ever. */
    *fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (*fd < 0)
        return err_set(err, GLINT_ERR_IO, "%s", strerror(errno));
    struct stat st;
    glint_rc rc = GLINT_OK;
    if (fstat(*fd, &st) != 0)
        rc = err_set(err, GLINT_ERR_IO, "%s", strerror(errno));
    else if (!S_ISREG(st.st_mode))
        rc = err_set(err, GLINT_ERR_INPUT, "%s",
                     S_ISDIR(st.st_mode) ? strerror(EISDIR) : "not a regular file");
    if (rc != GLINT_OK) {
        close(*fd);
        *fd = -1;
        return rc;
    }
    /* A regular file never blocks; reads go on as usual. */
    fcntl(*fd, F_SETFL, fcntl(*fd, F_GETFL) & ~O_NONBLOCK);
    return GLINT_OK;
}

/* Files on disk: regular files only, refused at once otherwise (a FIFO,
 * /dev/zero, a folder), before a byte is read. */
glint_rc scene_read_file(void *user, const char *path, char **data, size_t *size,
                         glint_error *err)
{
    (void)user;
    int fd;
    glint_rc rc = load_open_regular(path, &fd, err);
    if (rc != GLINT_OK)
        return rc;
    rc = read_fd(fd, data, size, err);
    close(fd);
    return rc;
}
