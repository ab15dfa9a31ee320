/* The scene format's meaning: YAML trees (yaml_doc.h) into a scene.
 *
 * A load runs in two passes. The first walks the scene file, then each of
 * its includes in turn (depth first), adding lights, textures, images,
 * materials, transforms and objects to the scene as it meets them; names
 * used before they are known are noted as references. The second resolves
 * those references, checks the settings as a whole and builds the scene.
 * Every tree stays alive until the end so that late errors can still point
 * at the node they are about. */
#include "load.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/array.h"
#include "core/error.h"
#include "load/names.h"
#include "scene/scene.h"
#include "scene/settings.h"
#include "load/mesh_import.h"
#include "load/yaml_doc.h"

/* Room for a user string in a message, escaped (ydoc_show). */
#define SHOWN (YDOC_SHOW_MAX * 4 + 8)

typedef struct lfile {
    char *name; /* shown in messages */
    char *key;  /* tidied path, for finding include cycles */
    char *dir;  /* folder that relative paths resolve against; "" for none */
    char *data; /* the text while it is parsed, when the loader read it */
    ydoc *doc;
} lfile;

/* A name used by a material (for a texture) or an object (for a material),
 * to be resolved once every file has been read. */
typedef struct ref {
    int index; /* the material or object */
    int file;
    uint32_t node; /* the name */
} ref;

/* Where a texture or material name was defined, and what it names. */
typedef struct def {
    int file;
    uint32_t node;
    int index;
} def;

/* Settings a file may set; the first file to set one wins (includers are
 * read before what they include). */
enum {
    SET_WIDTH = 1 << 0,
    SET_HEIGHT = 1 << 1,
    SET_SAMPLES = 1 << 2,
    SET_DEPTH = 1 << 3,
    SET_BACKGROUND = 1 << 4,
    SET_TRANSFER = 1 << 5,
    SET_EYE = 1 << 6,
    SET_LOOK_AT = 1 << 7,
    SET_UP = 1 << 8,
    SET_FOV = 1 << 9,
    SET_AMBIENT = 1 << 10,
};

typedef struct loader {
    scene *s;
    scene_reader reader;
    void *user;
    glint_error *err;
    lfile *files;
    int nfiles, cap_files;
    int cur; /* the file being read */
    /* The include chain: files open inside one another, and in each the
     * include entry being followed. */
    int chain[LOAD_MAX_INCLUDE_DEPTH];
    uint32_t via[LOAD_MAX_INCLUDE_DEPTH];
    int depth;
    names texture_names, material_names; /* name -> index into defs */
    def *defs;
    int ndefs, cap_defs;
    names images; /* resolved path -> index into the scene's images */
    names meshes; /* resolved path -> index into the scene's meshes */
    ref *texture_refs, *material_refs;
    int ntexture_refs, cap_texture_refs, nmaterial_refs, cap_material_refs;
    int default_material; /* -1 until an object needs it */
    unsigned set;
    int size_file, camera_file; /* where the image size and camera were set; -1: nowhere */
    uint32_t size_node, camera_node;
} loader;

/* ---- messages --------------------------------------------------------- */

static glint_rc vfail_at(loader *L, int file, uint32_t line, uint32_t col, const char *fmt,
                         va_list ap)
{
    char msg[900];
    vsnprintf(msg, sizeof msg, fmt, ap);
    return err_set(L->err, GLINT_ERR_INPUT, "%s:%u:%u: %s", L->files[file].name, line, col, msg);
}

/* Fails with "FILE:LINE:COL: message" at node at of file. */
GLINT_PRINTF(4, 5)
static glint_rc fail_in(loader *L, int file, uint32_t at, const char *fmt, ...)
{
    const ynode *n = ydoc_node(L->files[file].doc, at);
    va_list ap;
    va_start(ap, fmt);
    glint_rc rc = vfail_at(L, file, n->line, n->col, fmt, ap);
    va_end(ap);
    return rc;
}

/* The same in the file being read. */
GLINT_PRINTF(3, 4)
static glint_rc fail(loader *L, uint32_t at, const char *fmt, ...)
{
    const ynode *n = ydoc_node(L->files[L->cur].doc, at);
    va_list ap;
    va_start(ap, fmt);
    glint_rc rc = vfail_at(L, L->cur, n->line, n->col, fmt, ap);
    va_end(ap);
    return rc;
}

static const ydoc *doc(const loader *L) { return L->files[L->cur].doc; }
static const ynode *node(const loader *L, uint32_t i) { return ydoc_node(doc(L), i); }

/* A scalar's text made printable, into buf (SHOWN bytes). */
static const char *shown(const loader *L, uint32_t i, char *buf)
{
    const ynode *n = node(L, i);
    ydoc_show(ydoc_text(doc(L), n), n->count, buf, SHOWN);
    return buf;
}

static glint_rc expected(loader *L, uint32_t v, const char *what, const char *key)
{
    char got[SHOWN + 32];
    ydoc_describe(doc(L), node(L, v), got, sizeof got);
    return fail(L, v, "expected %s for '%s', got %s", what, key, got);
}

/* " (did you mean 'x'?)" or, with no near candidate, " (valid: a, b, c)". */
static void suggestion(const char *const *valid, const char *word, size_t len, char *buf,
                       size_t cap)
{
    const char *near = names_suggest_list(valid, word, len);
    if (near) {
        snprintf(buf, cap, " (did you mean '%s'?)", near);
        return;
    }
    size_t o = (size_t)snprintf(buf, cap, " (valid: ");
    for (const char *const *k = valid; *k && o < cap; k++)
        o += (size_t)snprintf(buf + o, cap - o, "%s%s", *k, k[1] ? ", " : ")");
}

/* ---- keys of a mapping ------------------------------------------------ */

/* Refuses the first key of map that is not in valid; where says where the
 * mapping is ("in sphere", "at the top level"). */
static glint_rc check_keys(loader *L, uint32_t map, const char *const *valid, const char *where)
{
    const ynode *m = node(L, map);
    for (uint32_t i = 0; i < m->count; i++) {
        uint32_t k = ydoc_key(doc(L), m, i);
        const ynode *kn = node(L, k);
        const char *text = ydoc_text(doc(L), kn);
        bool known = false;
        for (const char *const *v = valid; *v && !known; v++)
            known = strlen(*v) == kn->count && memcmp(*v, text, kn->count) == 0;
        if (!known) {
            char buf[SHOWN], hint[512];
            suggestion(valid, text, kn->count, hint, sizeof hint);
            return fail(L, k, "unknown key '%s' %s%s", shown(L, k, buf), where, hint);
        }
    }
    return GLINT_OK;
}

static uint32_t get(const loader *L, uint32_t map, const char *key)
{
    return ydoc_get(doc(L), node(L, map), key);
}

/* The value under key, which must be there; what names the mapping. */
static glint_rc need(loader *L, uint32_t map, const char *key, const char *what, uint32_t *v)
{
    *v = get(L, map, key);
    if (*v == YDOC_NONE)
        return fail(L, map, "%s needs '%s'", what, key);
    return GLINT_OK;
}

static glint_rc want_map(loader *L, uint32_t v, const char *key)
{
    return node(L, v)->kind == YNODE_MAP ? GLINT_OK : expected(L, v, "a mapping", key);
}

/* ---- values ----------------------------------------------------------- */

static glint_rc read_number(loader *L, uint32_t v, const char *key, float *out)
{
    if (node(L, v)->kind != YNODE_NUMBER)
        return expected(L, v, "a number", key);
    char buf[SHOWN];
    float f = ydoc_float(doc(L), node(L, v));
    if (ydoc_is_special(doc(L), node(L, v)))
        return fail(L, v, "%s must be a finite number (got %s)", key, shown(L, v, buf));
    if (!isfinite(f))
        return fail(L, v, "%s is too large (got %s)", key, shown(L, v, buf));
    *out = f;
    return GLINT_OK;
}

static glint_rc read_positive(loader *L, uint32_t v, const char *key, float *out)
{
    glint_rc rc = read_number(L, v, key, out);
    char buf[SHOWN];
    if (rc == GLINT_OK && !(*out > 0.0f))
        rc = fail(L, v, "%s must be > 0 (got %s)", key, shown(L, v, buf));
    return rc;
}

static glint_rc read_nonneg(loader *L, uint32_t v, const char *key, float *out)
{
    glint_rc rc = read_number(L, v, key, out);
    char buf[SHOWN];
    if (rc == GLINT_OK && !(*out >= 0.0f))
        rc = fail(L, v, "%s must be >= 0 (got %s)", key, shown(L, v, buf));
    return rc;
}

static glint_rc read_unit(loader *L, uint32_t v, const char *key, float *out)
{
    glint_rc rc = read_number(L, v, key, out);
    char buf[SHOWN];
    if (rc == GLINT_OK && !(*out >= 0.0f && *out <= 1.0f))
        rc = fail(L, v, "%s must be between 0 and 1 (got %s)", key, shown(L, v, buf));
    return rc;
}

static glint_rc read_nonzero(loader *L, uint32_t v, const char *key, float *out)
{
    glint_rc rc = read_number(L, v, key, out);
    char buf[SHOWN];
    if (rc == GLINT_OK && *out == 0.0f)
        rc = fail(L, v, "%s must not be 0 (got %s)", key, shown(L, v, buf));
    return rc;
}

static glint_rc read_int(loader *L, uint32_t v, const char *key, int lo, int hi, int *out)
{
    const ynode *n = node(L, v);
    char buf[SHOWN];
    if (n->kind != YNODE_NUMBER)
        return expected(L, v, "a whole number", key);
    if (!ydoc_is_integer(doc(L), n))
        return fail(L, v, "expected a whole number for '%s', got %s", key, shown(L, v, buf));
    long long x;
    if (!ydoc_int(doc(L), n, &x) || x < lo || x > hi)
        return fail(L, v, "%s must be %d to %d (got %s)", key, lo, hi, shown(L, v, buf));
    *out = (int)x;
    return GLINT_OK;
}

static glint_rc read_bool(loader *L, uint32_t v, const char *key, bool *out)
{
    if (node(L, v)->kind != YNODE_BOOL)
        return expected(L, v, "true or false", key);
    *out = node(L, v)->flags & YNODE_TRUE;
    return GLINT_OK;
}

/* n numbers in a sequence; what describes it ("[x, y, z]"). */
static glint_rc read_numbers(loader *L, uint32_t v, const char *key, const char *what, int n,
                             float *out)
{
    const ynode *s = node(L, v);
    if (s->kind != YNODE_SEQ)
        return expected(L, v, what, key);
    if (s->count != (uint32_t)n)
        return fail(L, v, "expected %d numbers for '%s', got %u", n, key, s->count);
    for (int i = 0; i < n; i++) {
        glint_rc rc = read_number(L, ydoc_item(doc(L), s, (uint32_t)i), key, &out[i]);
        if (rc != GLINT_OK)
            return rc;
    }
    return GLINT_OK;
}

static glint_rc read_vec3(loader *L, uint32_t v, const char *key, vec3 *out)
{
    float f[3];
    glint_rc rc = read_numbers(L, v, key, "[x, y, z]", 3, f);
    if (rc == GLINT_OK)
        *out = v3(f[0], f[1], f[2]);
    return rc;
}

static glint_rc read_nonzero_vec3(loader *L, uint32_t v, const char *key, vec3 *out)
{
    glint_rc rc = read_vec3(L, v, key, out);
    if (rc == GLINT_OK && v3_is_zero(*out))
        rc = fail(L, v, "%s must not be [0, 0, 0]", key);
    return rc;
}

/* A colour: a number (grey) or [r, g, b], no component below 0. */
static glint_rc read_color(loader *L, uint32_t v, const char *key, vec3 *out)
{
    const ynode *n = node(L, v);
    char buf[SHOWN];
    if (n->kind == YNODE_NUMBER) {
        float g;
        glint_rc rc = read_nonneg(L, v, key, &g);
        if (rc == GLINT_OK)
            *out = v3s(g);
        return rc;
    }
    if (n->kind != YNODE_SEQ)
        return expected(L, v, "a number or [r, g, b]", key);
    float f[3];
    glint_rc rc = read_numbers(L, v, key, "[r, g, b]", 3, f);
    for (int i = 0; rc == GLINT_OK && i < 3; i++)
        if (!(f[i] >= 0.0f)) {
            uint32_t c = ydoc_item(doc(L), n, (uint32_t)i);
            rc = fail(L, c, "%s components must be >= 0 (got %s)", key, shown(L, c, buf));
        }
    if (rc == GLINT_OK)
        *out = v3(f[0], f[1], f[2]);
    return rc;
}

/* A string out of valid; what names the kind of thing ("object type"). */
static glint_rc read_enum(loader *L, uint32_t v, const char *key, const char *what,
                          const char *const *valid, int *out)
{
    const ynode *n = node(L, v);
    if (n->kind != YNODE_STRING)
        return expected(L, v, "a string", key);
    const char *text = ydoc_text(doc(L), n);
    for (int i = 0; valid[i]; i++)
        if (strlen(valid[i]) == n->count && memcmp(valid[i], text, n->count) == 0) {
            *out = i;
            return GLINT_OK;
        }
    char buf[SHOWN], hint[256];
    suggestion(valid, text, n->count, hint, sizeof hint);
    return fail(L, v, "unknown %s '%s'%s", what, shown(L, v, buf), hint);
}

/* A name (of a material or texture): a non-empty string or a number. */
static glint_rc read_name(loader *L, uint32_t v, const char *what)
{
    const ynode *n = node(L, v);
    char got[SHOWN + 32];
    if (n->kind != YNODE_STRING && n->kind != YNODE_NUMBER) {
        ydoc_describe(doc(L), n, got, sizeof got);
        return fail(L, v, "a %s name must be a string, got %s", what, got);
    }
    if (n->count == 0)
        return fail(L, v, "a %s name must not be empty", what);
    return GLINT_OK;
}

/* A path written in the file: a non-empty string without NUL bytes. */
static glint_rc read_path(loader *L, uint32_t v, const char *key)
{
    const ynode *n = node(L, v);
    if (n->kind != YNODE_STRING)
        return expected(L, v, "a file path", key);
    if (n->count == 0)
        return fail(L, v, "%s must not be empty", key);
    if (memchr(ydoc_text(doc(L), n), '\0', n->count))
        return fail(L, v, "%s must not contain a NUL character", key);
    return GLINT_OK;
}

/* ---- paths ------------------------------------------------------------ */

/* Drops empty and "." segments and folds "name/.." pairs, in place; an
 * empty result is ".". The output never runs ahead of the input. */
static void tidy_path(char *p)
{
    bool absolute = p[0] == '/';
    char *start = p + absolute, *out = start;
    const char *in = start;
    size_t kept = 0; /* segments in the output that ".." may remove */
    while (*in) {
        const char *end = strchr(in, '/');
        size_t len = end ? (size_t)(end - in) : strlen(in);
        bool dot = len == 1 && in[0] == '.';
        bool dotdot = len == 2 && in[0] == '.' && in[1] == '.';
        if (len == 0 || dot || (dotdot && absolute && kept == 0)) {
            /* nothing to keep ("/.." is "/") */
        } else if (dotdot && kept > 0) {
            while (out > start && out[-1] != '/')
                out--;
            if (out > start)
                out--;
            kept--;
        } else {
            if (out > start)
                *out++ = '/';
            memmove(out, in, len);
            out += len;
            kept += !dotdot;
        }
        in += len + (end ? 1 : 0);
    }
    *out = '\0';
    if (!p[0])
        strcpy(p, ".");
}

/* dir joined to rel (unless rel is absolute or dir is empty), tidied. */
static char *join_path(const char *dir, const char *rel)
{
    bool use_dir = dir && dir[0] && rel[0] != '/';
    size_t nd = use_dir ? strlen(dir) : 0, nr = strlen(rel);
    char *p = malloc(nd + nr + 3); /* room for "." in tidy_path */
    if (!p)
        return NULL;
    if (use_dir) {
        memcpy(p, dir, nd);
        p[nd++] = '/';
    }
    memcpy(p + nd, rel, nr + 1);
    tidy_path(p);
    return p;
}

/* The folder part of a path: "a/b.yaml" -> "a", "b.yaml" -> "", "/b" -> "/". */
static char *dir_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    size_t n = !slash ? 0 : slash == path ? 1 : (size_t)(slash - path);
    char *d = malloc(n + 1);
    if (d) {
        memcpy(d, path, n);
        d[n] = '\0';
    }
    return d;
}

/* A copy of a path with control bytes escaped as \xNN, so that messages
 * naming it stay on one line; NULL when out of memory. */
static char *printable(const char *path)
{
    size_t n = 0;
    for (const char *p = path; *p; p++)
        n += (unsigned char)*p < 0x20 || *p == 0x7f ? 4 : 1;
    char *out = malloc(n + 1), *o = out;
    if (!out)
        return NULL;
    for (const char *p = path; *p; p++) {
        unsigned char c = (unsigned char)*p;
        if (c < 0x20 || c == 0x7f) {
            snprintf(o, 5, "\\x%02X", c);
            o += 4;
        } else {
            *o++ = (char)c;
        }
    }
    *o = '\0';
    return out;
}

/* "cannot read KIND 'written' (resolved): reason", or the size-limit
 * message when reason is NULL. */
static glint_rc cannot_read(loader *L, uint32_t at, const char *kind, const char *written,
                            const char *resolved, const char *reason)
{
    glint_rc rc;
    char *w = printable(written), *r = printable(resolved);
    if (!w || !r) {
        rc = err_nomem(L->err);
    } else {
        char also[600] = "";
        if (strcmp(written, resolved) != 0)
            snprintf(also, sizeof also, " (%s)", r);
        if (!reason)
            rc = fail(L, at, "%s '%s'%s is larger than the %u-byte limit", kind, w, also,
                      LOAD_MAX_FILE_BYTES);
        else
            rc = fail(L, at, "cannot read %s '%s'%s: %s", kind, w, also, reason);
    }
    free(w);
    free(r);
    return rc;
}

/* Reads a file named in the scene through the reader. written is the
 * path as written, resolved the path the reader gets; kind says what the
 * file is for ("include", "texture"). */
static glint_rc read_named_file(loader *L, uint32_t at, const char *written, const char *resolved,
                                const char *kind, char **data, size_t *size)
{
    glint_error rerr = {0};
    *data = NULL;
    glint_rc rc = L->reader(L->user, resolved, data, size, &rerr);
    if (rc == GLINT_OK && *size <= LOAD_MAX_FILE_BYTES)
        return GLINT_OK;
    if (rc == GLINT_OK) {
        free(*data);
        *data = NULL;
    }
    if (rc == GLINT_ERR_NOMEM)
        return err_nomem(L->err);
    return cannot_read(L, at, kind, written, resolved, rc == GLINT_OK ? NULL : rerr.msg);
}

/* ---- textures and materials ------------------------------------------- */

static const char *const texture_types[] = {"image", "checker", NULL};
static const char *const image_texture_keys[] = {"type", "file", "wrap", "scale", "offset", NULL};
static const char *const checker_texture_keys[] = {"type", "even", "odd", "scale", "offset", NULL};
static const char *const wrap_modes[] = {"repeat", "clamp", NULL};

/* The image at a path written in the file, read once per resolved path. */
static glint_rc load_image_file(loader *L, uint32_t v, int *index)
{
    const char *written = ydoc_text(doc(L), node(L, v));
    char *resolved = join_path(L->files[L->cur].dir, written);
    char *shown_name = printable(written);
    char *data = NULL;
    glint_rc rc = GLINT_OK;
    if (!resolved || !shown_name) {
        rc = err_nomem(L->err);
        goto out;
    }
    *index = names_find(&L->images, resolved, strlen(resolved));
    if (*index >= 0)
        goto out;
    size_t size;
    rc = read_named_file(L, v, written, resolved, "texture", &data, &size);
    if (rc != GLINT_OK)
        goto out;
    image img;
    glint_error ierr = {0};
    rc = image_load_memory(data, size, shown_name, &img, &ierr);
    if (rc == GLINT_ERR_NOMEM) {
        rc = err_nomem(L->err);
        goto out;
    }
    if (rc != GLINT_OK) {
        rc = fail(L, v, "%s", ierr.msg);
        goto out;
    }
    *index = scene_add_image(L->s, &img);
    if (*index < 0 || !names_put(&L->images, resolved, strlen(resolved), *index)) {
        image_free(&img);
        rc = err_nomem(L->err);
    }
out:
    free(data);
    free(resolved);
    free(shown_name);
    return rc;
}

static glint_rc read_wrap(loader *L, uint32_t v, texture *t)
{
    const ynode *n = node(L, v);
    int u, w;
    glint_rc rc;
    if (n->kind == YNODE_SEQ) {
        if (n->count != 2)
            return fail(L, v, "expected 2 wrap modes for 'wrap' ([u, v]), got %u", n->count);
        rc = read_enum(L, ydoc_item(doc(L), n, 0), "wrap", "wrap mode", wrap_modes, &u);
        if (rc == GLINT_OK)
            rc = read_enum(L, ydoc_item(doc(L), n, 1), "wrap", "wrap mode", wrap_modes, &w);
    } else if (n->kind == YNODE_STRING) {
        rc = read_enum(L, v, "wrap", "wrap mode", wrap_modes, &u);
        w = u;
    } else {
        return expected(L, v, "repeat, clamp or [u, v]", "wrap");
    }
    if (rc == GLINT_OK) {
        t->wrap_u = u == 0 ? WRAP_REPEAT : WRAP_CLAMP;
        t->wrap_v = w == 0 ? WRAP_REPEAT : WRAP_CLAMP;
    }
    return rc;
}

/* scale (a number or [su, sv], not 0) and offset ([ou, ov]). */
static glint_rc read_placement(loader *L, uint32_t map, texture *t)
{
    uint32_t v = get(L, map, "scale");
    glint_rc rc = GLINT_OK;
    if (v != YDOC_NONE) {
        const ynode *n = node(L, v);
        if (n->kind == YNODE_NUMBER) {
            rc = read_nonzero(L, v, "scale", &t->scale_u);
            t->scale_v = t->scale_u;
        } else if (n->kind == YNODE_SEQ) {
            float f[2];
            rc = read_numbers(L, v, "scale", "[su, sv]", 2, f);
            for (int i = 0; rc == GLINT_OK && i < 2; i++)
                rc = read_nonzero(L, ydoc_item(doc(L), n, (uint32_t)i), "scale", &f[i]);
            if (rc == GLINT_OK) {
                t->scale_u = f[0];
                t->scale_v = f[1];
            }
        } else {
            return expected(L, v, "a number or [su, sv]", "scale");
        }
    }
    v = get(L, map, "offset");
    if (rc == GLINT_OK && v != YDOC_NONE) {
        float f[2];
        rc = read_numbers(L, v, "offset", "[ou, ov]", 2, f);
        if (rc == GLINT_OK) {
            t->offset_u = f[0];
            t->offset_v = f[1];
        }
    }
    return rc;
}

/* A texture mapping, added to the scene; its index goes to *index. */
static glint_rc load_texture(loader *L, uint32_t map, int *index)
{
    uint32_t v;
    int type;
    glint_rc rc = need(L, map, "type", "texture", &v);
    if (rc == GLINT_OK)
        rc = read_enum(L, v, "type", "texture type", texture_types, &type);
    if (rc != GLINT_OK)
        return rc;
    texture t;
    if (type == 0) {
        rc = check_keys(L, map, image_texture_keys, "in image texture");
        if (rc == GLINT_OK)
            rc = need(L, map, "file", "image texture", &v);
        if (rc == GLINT_OK)
            rc = read_path(L, v, "file");
        t = texture_image(-1);
        uint32_t w = get(L, map, "wrap");
        if (rc == GLINT_OK && w != YDOC_NONE)
            rc = read_wrap(L, w, &t);
        if (rc == GLINT_OK)
            rc = read_placement(L, map, &t);
        /* The file last: the other fields are cheaper to check. */
        if (rc == GLINT_OK)
            rc = load_image_file(L, v, &t.image);
    } else {
        t = texture_checker(v3s(1.0f), v3s(0.0f), 1.0f, 1.0f);
        rc = check_keys(L, map, checker_texture_keys, "in checker texture");
        if (rc == GLINT_OK && (v = get(L, map, "even")) != YDOC_NONE)
            rc = read_color(L, v, "even", &t.even);
        if (rc == GLINT_OK && (v = get(L, map, "odd")) != YDOC_NONE)
            rc = read_color(L, v, "odd", &t.odd);
        if (rc == GLINT_OK)
            rc = read_placement(L, map, &t);
    }
    if (rc != GLINT_OK)
        return rc;
    *index = scene_add_texture(L->s, &t);
    return *index < 0 ? err_nomem(L->err) : GLINT_OK;
}

static glint_rc add_ref(loader *L, ref **refs, int *n, int *cap, int index, uint32_t name)
{
    int i = array_push((void **)refs, n, cap, sizeof **refs);
    if (i < 0)
        return err_nomem(L->err);
    (*refs)[i] = (ref){index, L->cur, name};
    return GLINT_OK;
}

static const char *const material_keys[] = {"color",   "texture",  "ambient",
                                            "diffuse", "specular", "shininess",
                                            "reflect", "transmit", "ior",
                                            "tint",    NULL};

/* A material mapping, added to the scene; its index goes to *index. */
static glint_rc load_material(loader *L, uint32_t map, int *index)
{
    material m = material_default();
    uint32_t v, tex = YDOC_NONE;
    glint_rc rc = check_keys(L, map, material_keys, "in material");
    if (rc == GLINT_OK && (v = get(L, map, "color")) != YDOC_NONE)
        rc = read_color(L, v, "color", &m.color);
    if (rc == GLINT_OK && (v = get(L, map, "ambient")) != YDOC_NONE)
        rc = read_nonneg(L, v, "ambient", &m.ambient);
    if (rc == GLINT_OK && (v = get(L, map, "diffuse")) != YDOC_NONE)
        rc = read_nonneg(L, v, "diffuse", &m.diffuse);
    if (rc == GLINT_OK && (v = get(L, map, "specular")) != YDOC_NONE)
        rc = read_nonneg(L, v, "specular", &m.specular);
    if (rc == GLINT_OK && (v = get(L, map, "shininess")) != YDOC_NONE)
        rc = read_nonneg(L, v, "shininess", &m.shininess);
    if (rc == GLINT_OK && (v = get(L, map, "reflect")) != YDOC_NONE)
        rc = read_unit(L, v, "reflect", &m.reflect);
    if (rc == GLINT_OK && (v = get(L, map, "transmit")) != YDOC_NONE)
        rc = read_unit(L, v, "transmit", &m.transmit);
    if (rc == GLINT_OK && (v = get(L, map, "ior")) != YDOC_NONE)
        rc = read_positive(L, v, "ior", &m.ior);
    if (rc == GLINT_OK && (v = get(L, map, "tint")) != YDOC_NONE)
        rc = read_color(L, v, "tint", &m.tint);
    if (rc == GLINT_OK && (v = get(L, map, "texture")) != YDOC_NONE) {
        ynode_kind k = (ynode_kind)node(L, v)->kind;
        if (k == YNODE_MAP)
            rc = load_texture(L, v, &m.texture);
        else if (k == YNODE_STRING || k == YNODE_NUMBER)
            tex = v;
        else
            rc = expected(L, v, "a texture name or mapping", "texture");
    }
    if (rc != GLINT_OK)
        return rc;
    *index = scene_add_material(L->s, &m);
    if (*index < 0)
        return err_nomem(L->err);
    if (tex != YDOC_NONE)
        return add_ref(L, &L->texture_refs, &L->ntexture_refs, &L->cap_texture_refs, *index, tex);
    return GLINT_OK;
}

/* textures: or materials: at the top level, a mapping from names to
 * definitions. Names are shared by every file of the scene. */
static glint_rc load_named(loader *L, uint32_t map, bool textures)
{
    const char *what = textures ? "texture" : "material";
    names *table = textures ? &L->texture_names : &L->material_names;
    glint_rc rc = want_map(L, map, textures ? "textures" : "materials");
    const ynode *m = node(L, map);
    for (uint32_t i = 0; rc == GLINT_OK && i < m->count; i++) {
        uint32_t k = ydoc_key(doc(L), m, i), v = ydoc_value(doc(L), m, i);
        const ynode *kn = node(L, k);
        const char *name = ydoc_text(doc(L), kn);
        rc = read_name(L, k, what);
        if (rc != GLINT_OK)
            break;
        int seen = names_find(table, name, kn->count);
        if (seen >= 0) {
            const def *d = &L->defs[seen];
            const ynode *at = ydoc_node(L->files[d->file].doc, d->node);
            char buf[SHOWN];
            rc = fail(L, k, "duplicate %s name '%s' (first defined at %s:%u:%u)", what,
                      shown(L, k, buf), L->files[d->file].name, at->line, at->col);
            break;
        }
        if (node(L, v)->kind != YNODE_MAP) {
            char got[SHOWN + 32];
            ydoc_describe(doc(L), node(L, v), got, sizeof got);
            char buf[SHOWN];
            rc = fail(L, v, "expected a mapping for %s '%s', got %s", what, shown(L, k, buf),
                      got);
            break;
        }
        int index;
        rc = textures ? load_texture(L, v, &index) : load_material(L, v, &index);
        if (rc != GLINT_OK)
            break;
        int d = array_push((void **)&L->defs, &L->ndefs, &L->cap_defs, sizeof *L->defs);
        if (d < 0 || !names_put(table, name, kn->count, d))
            return err_nomem(L->err);
        L->defs[d] = (def){L->cur, k, index};
    }
    return rc;
}

/* ---- transforms ------------------------------------------------------- */

/* In step_kind order. */
static const char *const transform_keys[] = {"translate", "rotate_x", "rotate_y", "rotate_z",
                                             "rotate",    "scale",    "shear",    "matrix",
                                             NULL};

typedef enum step_kind {
    STEP_TRANSLATE,
    STEP_ROTATE_X,
    STEP_ROTATE_Y,
    STEP_ROTATE_Z,
    STEP_ROTATE,
    STEP_SCALE,
    STEP_SHEAR,
    STEP_MATRIX,
} step_kind;
static const char *const rotate_keys[] = {"axis", "angle", NULL};
static const char *const shear_keys[] = {"xy", "xz", "yx", "yz", "zx", "zy", NULL};

static bool xform_is_finite(const xform *x)
{
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            if (!isfinite(x->fwd.m[i][j]) || !isfinite(x->inv.m[i][j]))
                return false;
    return true;
}

static glint_rc load_step(loader *L, uint32_t step, xform *out)
{
    const ynode *m = node(L, step);
    if (m->kind != YNODE_MAP || m->count != 1) {
        char got[SHOWN + 32];
        ydoc_describe(doc(L), m, got, sizeof got);
        if (m->kind == YNODE_MAP)
            snprintf(got, sizeof got, "a mapping with %u keys", m->count);
        return fail(L, step,
                    "a transform step is a mapping with one key, such as {translate: [1, 2, 3]}, "
                    "got %s",
                    got);
    }
    uint32_t k = ydoc_key(doc(L), m, 0), v = ydoc_value(doc(L), m, 0);
    int kind;
    glint_rc rc = read_enum(L, k, "transform", "transform", transform_keys, &kind);
    if (rc != GLINT_OK)
        return rc;
    const char *key = transform_keys[kind];
    float f[16];
    vec3 a;
    switch ((step_kind)kind) {
    case STEP_TRANSLATE:
        rc = read_vec3(L, v, key, &a);
        if (rc == GLINT_OK)
            *out = xform_translate(a);
        break;
    case STEP_ROTATE_X:
    case STEP_ROTATE_Y:
    case STEP_ROTATE_Z:
        rc = read_number(L, v, key, &f[0]);
        if (rc == GLINT_OK)
            *out = xform_rotate(v3(kind == STEP_ROTATE_X, kind == STEP_ROTATE_Y,
                                   kind == STEP_ROTATE_Z),
                                f[0]);
        break;
    case STEP_ROTATE: {
        uint32_t axis, angle;
        rc = want_map(L, v, key);
        if (rc == GLINT_OK)
            rc = check_keys(L, v, rotate_keys, "in rotate");
        if (rc == GLINT_OK)
            rc = need(L, v, "axis", "rotate", &axis);
        if (rc == GLINT_OK)
            rc = need(L, v, "angle", "rotate", &angle);
        if (rc == GLINT_OK)
            rc = read_nonzero_vec3(L, axis, "axis", &a);
        if (rc == GLINT_OK)
            rc = read_number(L, angle, "angle", &f[0]);
        if (rc == GLINT_OK)
            *out = xform_rotate(a, f[0]);
        break;
    }
    case STEP_SCALE:
        if (node(L, v)->kind == YNODE_NUMBER) {
            rc = read_nonzero(L, v, key, &f[0]);
            a = v3s(f[0]);
        } else if (node(L, v)->kind == YNODE_SEQ) {
            rc = read_numbers(L, v, key, "a number or [sx, sy, sz]", 3, f);
            for (int i = 0; rc == GLINT_OK && i < 3; i++)
                rc = read_nonzero(L, ydoc_item(doc(L), node(L, v), (uint32_t)i), key, &f[i]);
            a = v3(f[0], f[1], f[2]);
        } else {
            rc = expected(L, v, "a number or [sx, sy, sz]", key);
        }
        if (rc == GLINT_OK)
            *out = xform_scale(a);
        break;
    case STEP_SHEAR: {
        rc = want_map(L, v, key);
        if (rc == GLINT_OK)
            rc = check_keys(L, v, shear_keys, "in shear");
        mat4 sm = mat4_identity();
        static const int at[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
        for (int i = 0; rc == GLINT_OK && i < 6; i++) {
            uint32_t c = get(L, v, shear_keys[i]);
            if (c != YDOC_NONE)
                rc = read_number(L, c, shear_keys[i], &sm.m[at[i][0]][at[i][1]]);
        }
        if (rc == GLINT_OK && !xform_from_matrix(&sm, out))
            rc = fail(L, v, "shear is not invertible (it flattens space)");
        break;
    }
    case STEP_MATRIX: {
        const ynode *s = node(L, v);
        if (s->kind != YNODE_SEQ)
            return expected(L, v, "12 or 16 numbers", key);
        if (s->count != 12 && s->count != 16)
            return fail(L, v, "expected 12 or 16 numbers for 'matrix', got %u", s->count);
        for (uint32_t i = 0; rc == GLINT_OK && i < s->count; i++)
            rc = read_number(L, ydoc_item(doc(L), s, i), key, &f[i]);
        if (rc != GLINT_OK)
            break;
        if (s->count == 16 && !(f[12] == 0.0f && f[13] == 0.0f && f[14] == 0.0f && f[15] == 1.0f))
            return fail(L, ydoc_item(doc(L), s, 12),
                        "the last row of a 16-number matrix must be 0, 0, 0, 1 (transforms are "
                        "affine)");
        mat4 mm = mat4_identity();
        for (int i = 0; i < 12; i++)
            mm.m[i / 4][i % 4] = f[i];
        if (!xform_from_matrix(&mm, out))
            rc = fail(L, v, "matrix is not invertible");
        break;
    }
    }
    if (rc == GLINT_OK && !xform_is_finite(out))
        rc = fail(L, v, "%s makes the transform degenerate (not invertible in floats)", key);
    return rc;
}

/* Composes the steps of list onto *acc (*any: whether acc holds any step
 * yet). A step may itself be a list of steps, so that a transform written
 * once under an anchor can be used inside others. */
static glint_rc load_steps(loader *L, uint32_t list, xform *acc, bool *any)
{
    const ynode *s = node(L, list);
    for (uint32_t i = 0; i < s->count; i++) {
        uint32_t item = ydoc_item(doc(L), s, i);
        glint_rc rc;
        if (node(L, item)->kind == YNODE_SEQ) {
            rc = load_steps(L, item, acc, any);
            if (rc != GLINT_OK)
                return rc;
            continue;
        }
        xform step;
        rc = load_step(L, item, &step);
        if (rc != GLINT_OK)
            return rc;
        *acc = *any ? xform_then(acc, &step) : step;
        *any = true;
        if (!xform_is_finite(acc))
            return fail(L, item,
                        "this step makes the transform degenerate (not invertible in floats)");
    }
    return GLINT_OK;
}

/* A list of steps, first applied first; *index gets the scene's xform, or
 * -1 when there are no steps. */
static glint_rc load_transform(loader *L, uint32_t list, int *index)
{
    *index = -1;
    if (node(L, list)->kind != YNODE_SEQ)
        return expected(L, list, "a list of steps", "transform");
    xform acc = xform_identity();
    bool any = false;
    glint_rc rc = load_steps(L, list, &acc, &any);
    if (rc != GLINT_OK || !any)
        return rc;
    *index = scene_add_xform(L->s, &acc);
    return *index < 0 ? err_nomem(L->err) : GLINT_OK;
}

/* ---- objects ---------------------------------------------------------- */

/* In shape_kind order. */
static const char *const object_types[] = {"sphere",   "plane",    "quad", "box",
                                           "cylinder", "triangle", "mesh", NULL};
static const char *const *const object_keys[] = {
    (const char *const[]){"type", "center", "radius", "material", "transform", NULL},
    (const char *const[]){"type", "point", "normal", "material", "transform", NULL},
    (const char *const[]){"type", "origin", "edge_u", "edge_v", "material", "transform", NULL},
    (const char *const[]){"type", "min", "max", "material", "transform", NULL},
    (const char *const[]){"type", "base", "radius", "height", "capped", "material", "transform",
                          NULL},
    (const char *const[]){"type", "p0", "p1", "p2", "uv", "material", "transform", NULL},
    (const char *const[]){"type", "file", "material", "transform", NULL},
};

/* A required vector field of a shape. */
static glint_rc need_vec3(loader *L, uint32_t map, const char *key, const char *what, vec3 *out)
{
    uint32_t v;
    glint_rc rc = need(L, map, key, what, &v);
    return rc == GLINT_OK ? read_vec3(L, v, key, out) : rc;
}

static glint_rc need_positive(loader *L, uint32_t map, const char *key, const char *what,
                              float *out)
{
    uint32_t v;
    glint_rc rc = need(L, map, key, what, &v);
    return rc == GLINT_OK ? read_positive(L, v, key, out) : rc;
}

static glint_rc load_box(loader *L, uint32_t map, shape *out)
{
    vec3 lo, hi;
    glint_rc rc = need_vec3(L, map, "min", "box", &lo);
    if (rc == GLINT_OK)
        rc = need_vec3(L, map, "max", "box", &hi);
    if (rc != GLINT_OK)
        return rc;
    uint32_t mn = get(L, map, "min"), mx = get(L, map, "max");
    for (int a = 0; a < 3; a++)
        if (!(v3_at(lo, a) < v3_at(hi, a))) {
            char b1[SHOWN], b2[SHOWN];
            return fail(L, mx, "max must be greater than min on every axis (%c: min %s, max %s)",
                        "xyz"[a], shown(L, ydoc_item(doc(L), node(L, mn), (uint32_t)a), b1),
                        shown(L, ydoc_item(doc(L), node(L, mx), (uint32_t)a), b2));
        }
    *out = shape_box(lo, hi);
    return GLINT_OK;
}

static glint_rc load_triangle(loader *L, uint32_t map, shape *out)
{
    vec3 p[3];
    static const char *const pk[3] = {"p0", "p1", "p2"};
    glint_rc rc = GLINT_OK;
    for (int i = 0; rc == GLINT_OK && i < 3; i++)
        rc = need_vec3(L, map, pk[i], "triangle", &p[i]);
    if (rc != GLINT_OK)
        return rc;
    if (v3_is_zero(v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]))))
        return fail(L, map, "triangle is degenerate: p0, p1 and p2 lie on one line");
    *out = shape_triangle(p[0], p[1], p[2]);
    uint32_t v = get(L, map, "uv");
    if (v == YDOC_NONE)
        return GLINT_OK;
    const ynode *s = node(L, v);
    if (s->kind != YNODE_SEQ)
        return expected(L, v, "[[u, v], [u, v], [u, v]]", "uv");
    if (s->count != 3)
        return fail(L, v, "expected 3 [u, v] pairs for 'uv', got %u", s->count);
    for (uint32_t i = 0; rc == GLINT_OK && i < 3; i++)
        rc = read_numbers(L, ydoc_item(doc(L), s, i), "uv", "[u, v]", 2, out->triangle.uv[i]);
    return rc;
}

/* The mesh at a path written in the file, imported once per resolved path
 * however many objects place it. Files on disk go to assimp by path (so an
 * OBJ finds its .mtl); through another reader, from memory. The file's own
 * materials join the scene's, and its triangles index them there. */
static glint_rc load_mesh_file(loader *L, uint32_t v, shape *out)
{
    const char *written = ydoc_text(doc(L), node(L, v));
    char *resolved = join_path(L->files[L->cur].dir, written);
    char *data = NULL;
    mesh_file mf = {0};
    glint_rc rc = GLINT_OK;
    if (!resolved) {
        rc = err_nomem(L->err);
        goto out;
    }
    int index = names_find(&L->meshes, resolved, strlen(resolved));
    if (index >= 0) {
        *out = shape_mesh(L->s->meshes[index]);
        goto out;
    }
    glint_error merr = {0};
    if (L->reader == scene_read_file) {
        FILE *probe = fopen(resolved, "rb");
        if (!probe) {
            rc = cannot_read(L, v, "mesh", written, resolved, strerror(errno));
            goto out;
        }
        fclose(probe);
        rc = mesh_import(resolved, &mf, &merr);
    } else {
        size_t size;
        rc = read_named_file(L, v, written, resolved, "mesh", &data, &size);
        if (rc != GLINT_OK)
            goto out;
        rc = mesh_import_memory(data, size, resolved, &mf, &merr);
    }
    if (rc == GLINT_ERR_NOMEM) {
        rc = err_nomem(L->err);
        goto out;
    }
    if (rc != GLINT_OK) {
        rc = fail(L, v, "%s", merr.msg);
        goto out;
    }
    int base = L->s->nmaterials;
    for (int i = 0; i < mf.nmaterials; i++)
        if (scene_add_material(L->s, &mf.materials[i]) < 0) {
            rc = err_nomem(L->err);
            goto out;
        }
    for (int t = 0; t < mf.mesh->ntris; t++)
        mf.mesh->tri_material[t] += base;
    index = scene_add_mesh(L->s, mf.mesh);
    if (index < 0) {
        rc = err_nomem(L->err);
        goto out;
    }
    mf.mesh = NULL; /* the scene owns it now */
    if (!names_put(&L->meshes, resolved, strlen(resolved), index)) {
        rc = err_nomem(L->err);
        goto out;
    }
    *out = shape_mesh(L->s->meshes[index]);
out:
    mesh_file_free(&mf);
    free(data);
    free(resolved);
    return rc;
}

static glint_rc load_shape(loader *L, uint32_t map, shape_kind kind, shape *out)
{
    const char *what = object_types[kind];
    vec3 a, b, c;
    float r, h;
    uint32_t v;
    glint_rc rc = GLINT_OK;
    switch (kind) {
    case SHAPE_SPHERE:
        rc = need_vec3(L, map, "center", what, &a);
        if (rc == GLINT_OK)
            rc = need_positive(L, map, "radius", what, &r);
        if (rc == GLINT_OK)
            *out = shape_sphere(a, r);
        return rc;
    case SHAPE_PLANE:
        rc = need_vec3(L, map, "point", what, &a);
        if (rc == GLINT_OK)
            rc = need(L, map, "normal", what, &v);
        if (rc == GLINT_OK)
            rc = read_nonzero_vec3(L, v, "normal", &b);
        if (rc == GLINT_OK)
            *out = shape_plane(a, b);
        return rc;
    case SHAPE_QUAD:
        rc = need_vec3(L, map, "origin", what, &a);
        if (rc == GLINT_OK)
            rc = need_vec3(L, map, "edge_u", what, &b);
        if (rc == GLINT_OK)
            rc = need_vec3(L, map, "edge_v", what, &c);
        if (rc == GLINT_OK && v3_is_zero(v3_cross(b, c)))
            rc = fail(L, get(L, map, "edge_v"),
                      "edge_v must not be parallel to edge_u (nor either be zero)");
        if (rc == GLINT_OK)
            *out = shape_quad(a, b, c);
        return rc;
    case SHAPE_BOX:
        return load_box(L, map, out);
    case SHAPE_CYLINDER: {
        bool capped = true;
        rc = need_vec3(L, map, "base", what, &a);
        if (rc == GLINT_OK)
            rc = need_positive(L, map, "radius", what, &r);
        if (rc == GLINT_OK)
            rc = need_positive(L, map, "height", what, &h);
        if (rc == GLINT_OK && (v = get(L, map, "capped")) != YDOC_NONE)
            rc = read_bool(L, v, "capped", &capped);
        if (rc == GLINT_OK)
            *out = shape_cylinder(a, r, h, capped);
        return rc;
    }
    case SHAPE_TRIANGLE:
        return load_triangle(L, map, out);
    case SHAPE_MESH:
        rc = need(L, map, "file", "mesh", &v);
        if (rc == GLINT_OK)
            rc = read_path(L, v, "file");
        if (rc == GLINT_OK)
            rc = load_mesh_file(L, v, out);
        return rc;
    }
    return rc;
}

/* The object's material: a name (resolved later), a mapping, or nothing:
 * a mesh's own materials (index -1) or the default material, added once. */
static glint_rc object_material(loader *L, uint32_t map, bool is_mesh, int *index, uint32_t *name)
{
    uint32_t v = get(L, map, "material");
    *name = YDOC_NONE;
    *index = -1;
    if (v == YDOC_NONE && is_mesh)
        return GLINT_OK;
    if (v == YDOC_NONE) {
        if (L->default_material < 0) {
            material m = material_default();
            L->default_material = scene_add_material(L->s, &m);
            if (L->default_material < 0)
                return err_nomem(L->err);
        }
        *index = L->default_material;
        return GLINT_OK;
    }
    ynode_kind k = (ynode_kind)node(L, v)->kind;
    if (k == YNODE_MAP)
        return load_material(L, v, index);
    if (k == YNODE_STRING || k == YNODE_NUMBER) {
        *name = v;
        return read_name(L, v, "material");
    }
    return expected(L, v, "a material name or mapping", "material");
}

static glint_rc load_object(loader *L, uint32_t map)
{
    if (node(L, map)->kind != YNODE_MAP)
        return expected(L, map, "a mapping", "objects");
    if (L->s->nobjects >= LOAD_MAX_OBJECTS)
        return fail(L, map, "more than %d objects", LOAD_MAX_OBJECTS);
    uint32_t v;
    int type;
    glint_rc rc = need(L, map, "type", "object", &v);
    if (rc == GLINT_OK)
        rc = read_enum(L, v, "type", "object type", object_types, &type);
    if (rc != GLINT_OK)
        return rc;
    char where[32];
    snprintf(where, sizeof where, "in %s", object_types[type]);
    rc = check_keys(L, map, object_keys[type], where);
    shape sh;
    if (rc == GLINT_OK)
        rc = load_shape(L, map, (shape_kind)type, &sh);
    int mat, xf = -1;
    uint32_t name;
    if (rc == GLINT_OK)
        rc = object_material(L, map, type == SHAPE_MESH, &mat, &name);
    if (rc == GLINT_OK && (v = get(L, map, "transform")) != YDOC_NONE)
        rc = load_transform(L, v, &xf);
    if (rc != GLINT_OK)
        return rc;
    int o = scene_add_object(L->s, &sh, mat, xf);
    if (o < 0)
        return err_nomem(L->err);
    if (name != YDOC_NONE)
        return add_ref(L, &L->material_refs, &L->nmaterial_refs, &L->cap_material_refs, o, name);
    return GLINT_OK;
}

/* ---- lights, image, camera -------------------------------------------- */

static const char *const light_types[] = {"point", NULL};
static const char *const point_light_keys[] = {"type", "position", "color", NULL};

static glint_rc load_light(loader *L, uint32_t map)
{
    if (node(L, map)->kind != YNODE_MAP)
        return expected(L, map, "a mapping", "lights");
    uint32_t v;
    int type;
    glint_rc rc = need(L, map, "type", "light", &v);
    if (rc == GLINT_OK)
        rc = read_enum(L, v, "type", "light type", light_types, &type);
    if (rc == GLINT_OK)
        rc = check_keys(L, map, point_light_keys, "in point light");
    light l = {LIGHT_POINT, v3s(0.0f), v3s(1.0f)};
    if (rc == GLINT_OK)
        rc = need_vec3(L, map, "position", "point light", &l.position);
    if (rc == GLINT_OK && (v = get(L, map, "color")) != YDOC_NONE)
        rc = read_color(L, v, "color", &l.color);
    if (rc != GLINT_OK)
        return rc;
    return scene_add_light(L->s, &l) < 0 ? err_nomem(L->err) : GLINT_OK;
}

/* Whether this file may set the setting: no file read before it did. */
static bool claim(loader *L, unsigned bit)
{
    bool first = !(L->set & bit);
    L->set |= bit;
    return first;
}

static const char *const image_keys[] = {"width", "height", "samples", "depth",
                                         "background", "transfer", NULL};
static const char *const transfers[] = {"none", "srgb", NULL};

static glint_rc load_image_settings(loader *L, uint32_t map)
{
    glint_rc rc = want_map(L, map, "image");
    if (rc == GLINT_OK)
        rc = check_keys(L, map, image_keys, "in image");
    glint_settings *st = &L->s->settings;
    uint32_t v;
    int x;
    vec3 c;
    char buf[SHOWN];
    if (rc == GLINT_OK && (v = get(L, map, "width")) != YDOC_NONE) {
        rc = read_int(L, v, "width", 1, SETTINGS_MAX_SIDE, &x);
        if (rc == GLINT_OK && claim(L, SET_WIDTH))
            st->width = x;
    }
    if (rc == GLINT_OK && (v = get(L, map, "height")) != YDOC_NONE) {
        rc = read_int(L, v, "height", 1, SETTINGS_MAX_SIDE, &x);
        if (rc == GLINT_OK && claim(L, SET_HEIGHT))
            st->height = x;
    }
    if (rc == GLINT_OK && L->size_file < 0 &&
        (get(L, map, "width") != YDOC_NONE || get(L, map, "height") != YDOC_NONE)) {
        L->size_file = L->cur;
        L->size_node = map;
    }
    if (rc == GLINT_OK && (v = get(L, map, "samples")) != YDOC_NONE) {
        rc = read_int(L, v, "samples", 1, SETTINGS_MAX_SAMPLES, &x);
        if (rc == GLINT_OK && settings_grid_side(x) < 0)
            rc = fail(L, v, "samples must be a perfect square (1, 4, 9, 16, ...) (got %s)",
                      shown(L, v, buf));
        if (rc == GLINT_OK && claim(L, SET_SAMPLES))
            st->samples = x;
    }
    if (rc == GLINT_OK && (v = get(L, map, "depth")) != YDOC_NONE) {
        rc = read_int(L, v, "depth", 0, SETTINGS_MAX_DEPTH, &x);
        if (rc == GLINT_OK && claim(L, SET_DEPTH))
            st->max_depth = x;
    }
    if (rc == GLINT_OK && (v = get(L, map, "background")) != YDOC_NONE) {
        rc = read_color(L, v, "background", &c);
        if (rc == GLINT_OK && claim(L, SET_BACKGROUND))
            L->s->background = c;
    }
    if (rc == GLINT_OK && (v = get(L, map, "transfer")) != YDOC_NONE) {
        rc = read_enum(L, v, "transfer", "transfer", transfers, &x);
        if (rc == GLINT_OK && claim(L, SET_TRANSFER))
            st->transfer = x == 0 ? GLINT_TRANSFER_NONE : GLINT_TRANSFER_SRGB;
    }
    return rc;
}

static const char *const camera_keys[] = {"eye", "look_at", "up", "fov", NULL};

static glint_rc load_camera(loader *L, uint32_t map)
{
    glint_rc rc = want_map(L, map, "camera");
    if (rc == GLINT_OK)
        rc = check_keys(L, map, camera_keys, "in camera");
    if (rc != GLINT_OK)
        return rc;
    if (L->camera_file < 0) {
        L->camera_file = L->cur;
        L->camera_node = map;
    }
    camera *cam = &L->s->camera;
    uint32_t v;
    vec3 p;
    float f;
    char buf[SHOWN];
    if ((v = get(L, map, "eye")) != YDOC_NONE) {
        rc = read_vec3(L, v, "eye", &p);
        if (rc == GLINT_OK && claim(L, SET_EYE))
            cam->eye = p;
    }
    if (rc == GLINT_OK && (v = get(L, map, "look_at")) != YDOC_NONE) {
        rc = read_vec3(L, v, "look_at", &p);
        if (rc == GLINT_OK && claim(L, SET_LOOK_AT))
            cam->target = p;
    }
    if (rc == GLINT_OK && (v = get(L, map, "up")) != YDOC_NONE) {
        rc = read_nonzero_vec3(L, v, "up", &p);
        if (rc == GLINT_OK && claim(L, SET_UP))
            cam->up = p;
    }
    if (rc == GLINT_OK && (v = get(L, map, "fov")) != YDOC_NONE) {
        rc = read_number(L, v, "fov", &f);
        if (rc == GLINT_OK && !(f > 0.0f && f < 180.0f))
            rc = fail(L, v, "fov must be > 0 and < 180 degrees (got %s)", shown(L, v, buf));
        if (rc == GLINT_OK && claim(L, SET_FOV))
            cam->hfov = f;
    }
    return rc;
}

/* ---- files ------------------------------------------------------------ */

static const char *const top_keys[] = {"image",     "camera",  "ambient", "lights",
                                       "textures",  "materials", "objects", "include", NULL};

static glint_rc load_list(loader *L, uint32_t v, const char *key,
                          glint_rc (*item)(loader *, uint32_t))
{
    const ynode *s = node(L, v);
    if (s->kind != YNODE_SEQ)
        return expected(L, v, "a list", key);
    for (uint32_t i = 0; i < s->count; i++) {
        glint_rc rc = item(L, ydoc_item(doc(L), s, i));
        if (rc != GLINT_OK)
            return rc;
    }
    return GLINT_OK;
}

static glint_rc load_text(loader *L, const char *text, size_t len, char *data, const char *name,
                          const char *key, const char *dir);

static glint_rc follow_include(loader *L, uint32_t v)
{
    glint_rc rc = read_path(L, v, "include");
    if (rc != GLINT_OK)
        return rc;
    const char *written = ydoc_text(doc(L), node(L, v));
    char *path = join_path(L->files[L->cur].dir, written);
    char *dir = path ? dir_of(path) : NULL;
    char *name = path ? printable(path) : NULL;
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
        rc = fail_in(L, L->chain[k], L->via[k], "include cycle: %s", cycle);
        goto out;
    }
    if (L->depth >= LOAD_MAX_INCLUDE_DEPTH) {
        rc = fail(L, v, "includes nested more than %d deep", LOAD_MAX_INCLUDE_DEPTH);
        goto out;
    }
    if (L->nfiles >= LOAD_MAX_FILES) {
        rc = fail(L, v, "more than %d files included", LOAD_MAX_FILES);
        goto out;
    }
    size_t size;
    rc = read_named_file(L, v, written, path, "include", &data, &size);
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
    const ydoc *d = doc(L);
    if (root == YDOC_NONE || node(L, root)->kind == YNODE_NULL) {
        uint32_t line = root == YDOC_NONE ? 1 : node(L, root)->line;
        uint32_t col = root == YDOC_NONE ? 1 : node(L, root)->col;
        return err_set(L->err, GLINT_ERR_INPUT,
                       "%s:%u:%u: the scene is empty (expected a mapping with keys such as "
                       "camera, lights and objects)",
                       L->files[L->cur].name, line, col);
    }
    if (node(L, root)->kind != YNODE_MAP) {
        char got[SHOWN + 32];
        ydoc_describe(d, node(L, root), got, sizeof got);
        return fail(L, root, "expected a mapping at the top of the scene, got %s", got);
    }
    glint_rc rc = check_keys(L, root, top_keys, "at the top level");
    const ynode *m = node(L, root);
    uint32_t include = YDOC_NONE;
    for (uint32_t i = 0; rc == GLINT_OK && i < m->count; i++) {
        const ynode *k = node(L, ydoc_key(d, m, i));
        const char *key = ydoc_text(d, k);
        uint32_t v = ydoc_value(d, m, i);
        vec3 c;
        if (strcmp(key, "image") == 0) {
            rc = load_image_settings(L, v);
        } else if (strcmp(key, "camera") == 0) {
            rc = load_camera(L, v);
        } else if (strcmp(key, "ambient") == 0) {
            rc = read_color(L, v, "ambient", &c);
            if (rc == GLINT_OK && claim(L, SET_AMBIENT))
                L->s->ambient = c;
        } else if (strcmp(key, "lights") == 0) {
            rc = load_list(L, v, "lights", load_light);
        } else if (strcmp(key, "textures") == 0) {
            rc = load_named(L, v, true);
        } else if (strcmp(key, "materials") == 0) {
            rc = load_named(L, v, false);
        } else if (strcmp(key, "objects") == 0) {
            rc = load_list(L, v, "objects", load_object);
        } else {
            include = v;
        }
    }
    if (rc != GLINT_OK || include == YDOC_NONE)
        return rc;
    /* Included files add to what this one has, after it. */
    if (node(L, include)->kind == YNODE_SEQ)
        return load_list(L, include, "include", follow_include);
    if (node(L, include)->kind != YNODE_STRING)
        return expected(L, include, "a file path or a list of them", "include");
    return follow_include(L, include);
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

/* Resolves the names materials give textures, or objects materials. */
static glint_rc resolve(loader *L, const ref *refs, int n, const names *table, const char *what)
{
    for (int i = 0; i < n; i++) {
        const ydoc *d = L->files[refs[i].file].doc;
        const ynode *nn = ydoc_node(d, refs[i].node);
        const char *name = ydoc_text(d, nn);
        int at = names_find(table, name, nn->count);
        if (at >= 0) {
            int index = L->defs[at].index;
            if (table == &L->texture_names)
                L->s->materials[refs[i].index].texture = index;
            else
                L->s->objects[refs[i].index].material = index;
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
        return fail_in(L, refs[i].file, refs[i].node, "unknown %s '%s'%s", what, buf, hint);
    }
    return GLINT_OK;
}

static glint_rc finish(loader *L)
{
    glint_rc rc = resolve(L, L->texture_refs, L->ntexture_refs, &L->texture_names, "texture");
    if (rc == GLINT_OK)
        rc = resolve(L, L->material_refs, L->nmaterial_refs, &L->material_names, "material");
    if (rc != GLINT_OK)
        return rc;
    glint_error serr = {0};
    if (settings_check(&L->s->settings, &serr) != GLINT_OK) {
        if (L->size_file < 0)
            return err_set(L->err, GLINT_ERR_INPUT, "%s", serr.msg);
        return fail_in(L, L->size_file, L->size_node, "%s", serr.msg);
    }
    const camera *c = &L->s->camera;
    vec3 view = v3_sub(c->target, c->eye);
    if (L->camera_file >= 0 && v3_is_zero(view))
        return fail_in(L, L->camera_file, L->camera_node, "camera look_at must differ from eye");
    if (L->camera_file >= 0 && v3_is_zero(v3_cross(view, c->up)))
        return fail_in(L, L->camera_file, L->camera_node,
                       "camera up must not be parallel to the view direction");
    return scene_build(L->s, L->err);
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
}

static glint_rc load(const char *text, size_t len, char *data, const char *name, const char *dir,
                     scene_reader reader, void *user, scene **out, glint_error *err)
{
    loader L = {.reader = reader ? reader : scene_read_file,
                .user = user,
                .err = err,
                .default_material = -1,
                .size_file = -1,
                .camera_file = -1};
    glint_rc rc = GLINT_OK;
    char *key = join_path(NULL, name);
    L.s = scene_new();
    if (!L.s || !key) {
        free(data);
        rc = err_nomem(err);
        goto out;
    }
    rc = load_text(&L, text, len, data, name, key, dir);
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
    return load(text, len, NULL, name, base_dir, reader, user, out, err);
}

glint_rc scene_load_file(const char *path, scene **out, glint_error *err)
{
    char *data = NULL, *dir = dir_of(path);
    size_t size = 0;
    glint_error rerr = {0};
    if (!dir)
        return err_nomem(err);
    glint_rc rc = scene_read_file(NULL, path, &data, &size, &rerr);
    if (rc == GLINT_ERR_NOMEM)
        rc = err_nomem(err);
    else if (rc != GLINT_OK)
        rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot read scene: %s", path, rerr.msg);
    if (rc == GLINT_OK)
        rc = load(data, size, data, path, dir, scene_read_file, NULL, out, err);
    free(dir);
    return rc;
}


glint_rc scene_read_file(void *user, const char *path, char **data, size_t *size,
                         glint_error *err)
{
    (void)user;
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(err, GLINT_ERR_IO, "%s", strerror(errno));
    glint_rc rc = GLINT_OK;
    size_t n = 0, cap = 1 << 16;
    char *buf = malloc(cap);
    if (!buf) {
        rc = err_nomem(err);
        goto out;
    }
    for (;;) {
        n += fread(buf + n, 1, cap - n, f);
        if (ferror(f)) {
            rc = err_set(err, GLINT_ERR_IO, "%s", strerror(errno));
            goto out;
        }
        if (n < cap)
            break; /* end of file */
        if (n > LOAD_MAX_FILE_BYTES) {
            rc = err_set(err, GLINT_ERR_INPUT, "the file is larger than the %u-byte limit",
                         LOAD_MAX_FILE_BYTES);
            goto out;
        }
        /* One byte past the limit tells a file of exactly the limit from a larger one. */
        size_t ncap = cap * 2 > (size_t)LOAD_MAX_FILE_BYTES + 1 ? (size_t)LOAD_MAX_FILE_BYTES + 1
                                                                : cap * 2;
        char *bigger = realloc(buf, ncap);
        if (!bigger) {
            rc = err_nomem(err);
            goto out;
        }
        buf = bigger;
        cap = ncap;
    }
out:
    fclose(f);
    if (rc != GLINT_OK) {
        free(buf);
        return rc;
    }
    *data = buf;
    *size = n;
    return GLINT_OK;
}
