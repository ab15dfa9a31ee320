/* Textures: images with their mappings and the procedural patterns with
 * their colour maps (src/shade/texture.h), written under textures: or
 * inline in a material. */
#include "loader.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "core/array.h"
#include "core/cpus.h"

/* In texture_kind order. */
static const char *const texture_types[] = {"image", "checker", "stripes", "rings",
                                            "gradient", "noise", "turbulence", "marble",
                                            "wood", NULL};
_Static_assert(sizeof texture_types / sizeof *texture_types == TEXTURE_KIND_COUNT + 1,
               "texture_types names every texture_kind, in order");
/* In texture_space and texture_mapping order. */
static const char *const spaces[] = {"uv", "object", "world", NULL};
static const char *const mappings[] = {"uv", "planar", "spherical", "cylindrical", "box", NULL};
static const char *const axes[] = {"x", "y", "z", NULL};
static const char *const wrap_modes[] = {"repeat", "clamp", NULL};

#define PLACEMENT "scale", "offset", "transform", "space"
#define FRACTAL "octaves", "lacunarity", "gain"
static const char *const *const texture_keys[TEXTURE_KIND_COUNT] = {
    [TEXTURE_IMAGE] = (const char *const[]){"type", "file", "wrap", "mapping", "axis",
                                            PLACEMENT, NULL},
    [TEXTURE_CHECKER] = (const char *const[]){"type", "even", "odd", "colors", PLACEMENT, NULL},
    [TEXTURE_STRIPES] = (const char *const[]){"type", "colors", PLACEMENT, NULL},
    [TEXTURE_RINGS] = (const char *const[]){"type", "colors", PLACEMENT, NULL},
    [TEXTURE_GRADIENT] = (const char *const[]){"type", "colors", PLACEMENT, NULL},
    [TEXTURE_NOISE] = (const char *const[]){"type", "colors", PLACEMENT, NULL},
    [TEXTURE_TURBULENCE] = (const char *const[]){"type", "colors", FRACTAL, PLACEMENT, NULL},
    [TEXTURE_MARBLE] = (const char *const[]){"type", "colors", "turbulence", FRACTAL, PLACEMENT,
                                             NULL},
    [TEXTURE_WOOD] = (const char *const[]){"type", "colors", "turbulence", FRACTAL, PLACEMENT,
                                           NULL},
};

/* The image at a path written in the file, read once per resolved path:
 * an empty scene image now, its file decoded at the end of the first pass
 * with the others (load_decode_images). */
static glint_rc load_image_file(loader *L, uint32_t v, int *index)
{
    const char *written = ydoc_text(load_doc(L), load_node(L, v));
    char *resolved = path_join(L->files[L->cur].dir, written);
    char *shown_name = path_printable(written);
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
    rc = load_named_file(L, v, written, resolved, "texture", &data, &size);
    if (rc != GLINT_OK)
        goto out;
    image empty = {0};
    int job = array_push((void **)&L->image_jobs, &L->nimage_jobs, &L->cap_image_jobs,
                         sizeof *L->image_jobs);
    *index = job < 0 ? -1 : scene_add_image(L->s, &empty);
    if (*index < 0 || !names_put(&L->images, resolved, strlen(resolved), *index)) {
        L->nimage_jobs -= job >= 0;
        rc = err_nomem(L->err);
        goto out;
    }
    L->image_jobs[job] = (image_job){data, shown_name, size, L->cur, v, *index, {0}, GLINT_OK, {0}};
    data = shown_name = NULL;
out:
    free(data);
    free(resolved);
    free(shown_name);
    return rc;
}

typedef struct decoding {
    image_job *jobs;
    int n;
    atomic_int next;
} decoding;

static void *decode_worker(void *arg)
{
    decoding *d = arg;
    for (int i; (i = atomic_fetch_add(&d->next, 1)) < d->n;) {
        image_job *j = &d->jobs[i];
        j->rc = image_load_memory(j->data, j->size, j->shown, &j->img, &j->err);
    }
    return NULL;
}

/* Threads decoding textures at most. */
#define DECODE_THREADS 16

/* Every job decoded, on up to `threads` threads (0: one per CPU), the
 * calling one included. */
static void decode_all(image_job *jobs, int n, int threads)
{
    decoding d = {.jobs = jobs, .n = n};
    atomic_init(&d.next, 0);
    threads = cpus_threads(threads, DECODE_THREADS);
    threads = threads < n ? threads : n;
    cpus_share(threads, decode_worker, &d);
}

glint_rc load_decode_images(loader *L, glint_rc rc)
{
    image_job *jobs = L->image_jobs;
    int n = L->nimage_jobs;
    if (n > 0 && rc != GLINT_ERR_NOMEM)
        decode_all(jobs, n, L->s->threads);
    glint_rc first = GLINT_OK;
    for (int i = 0; i < n; i++) {
        image_job *j = &jobs[i];
        if (first == GLINT_OK && rc != GLINT_ERR_NOMEM && j->rc != GLINT_OK)
            first = j->rc == GLINT_ERR_NOMEM ? err_nomem(L->err)
                                             : load_fail_in(L, j->file, j->node, "%s", j->err.msg);
        if (first == GLINT_OK && rc == GLINT_OK)
            scene_set_image(L->s, j->index, &j->img);
        image_free(&j->img);
        free(j->data);
        free(j->shown);
    }
    free(jobs);
    L->image_jobs = NULL;
    L->nimage_jobs = L->cap_image_jobs = 0;
    return first != GLINT_OK ? first : rc;
}

static glint_rc read_wrap(loader *L, uint32_t v, struct image_texture *t)
{
    const ynode *n = load_node(L, v);
    int u, w;
    glint_rc rc;
    if (n->kind == YNODE_SEQ) {
        if (n->count != 2)
            return load_fail(L, v, "expected 2 wrap modes for 'wrap' ([u, v]), got %u", n->count);
        rc = load_enum(L, ydoc_item(load_doc(L), n, 0), "wrap", "wrap mode", wrap_modes, &u);
        if (rc == GLINT_OK)
            rc = load_enum(L, ydoc_item(load_doc(L), n, 1), "wrap", "wrap mode", wrap_modes, &w);
    } else if (n->kind == YNODE_STRING) {
        rc = load_enum(L, v, "wrap", "wrap mode", wrap_modes, &u);
        w = u;
    } else {
        return load_expected(L, v, "repeat, clamp or [u, v]", "wrap");
    }
    if (rc == GLINT_OK) {
        t->wrap_u = u == 0 ? WRAP_REPEAT : WRAP_CLAMP;
        t->wrap_v = w == 0 ? WRAP_REPEAT : WRAP_CLAMP;
    }
    return rc;
}

/* scale: a number or dims numbers, none 0; offset: dims numbers. dims is 2
 * on (u, v) and 3 for a pattern in space. */
static glint_rc read_placement(loader *L, uint32_t map, int dims, texture *t)
{
    const char *list = dims == 2 ? "[su, sv]" : "[sx, sy, sz]";
    const char *what = dims == 2 ? "a number or [su, sv]" : "a number or [sx, sy, sz]";
    uint32_t v = load_get(L, map, "scale");
    float f[3] = {1.0f, 1.0f, 1.0f};
    glint_rc rc = GLINT_OK;
    if (v != YDOC_NONE) {
        const ynode *n = load_node(L, v);
        if (n->kind == YNODE_NUMBER) {
            rc = load_nonzero(L, v, "scale", &f[0]);
            f[1] = f[2] = f[0];
        } else if (n->kind == YNODE_SEQ) {
            rc = load_numbers(L, v, "scale", list, dims, f);
            for (int i = 0; rc == GLINT_OK && i < dims; i++)
                rc = load_nonzero(L, ydoc_item(load_doc(L), n, (uint32_t)i), "scale", &f[i]);
        } else {
            return load_expected(L, v, what, "scale");
        }
    }
    t->scale = v3(f[0], f[1], dims == 2 ? 1.0f : f[2]);
    v = load_get(L, map, "offset");
    if (rc == GLINT_OK && v != YDOC_NONE) {
        float o[3] = {0.0f, 0.0f, 0.0f};
        rc = load_numbers(L, v, "offset", dims == 2 ? "[ou, ov]" : "[x, y, z]", dims, o);
        t->offset = v3(o[0], o[1], o[2]);
    }
    v = load_get(L, map, "transform");
    if (rc == GLINT_OK && v != YDOC_NONE)
        rc = load_xform(L, v, &t->xf, &t->has_xform);
    return rc;
}

/* colors: [[at, colour], ...], 1 to COLOR_MAP_MAX stops, at ascending. */
static glint_rc read_color_map(loader *L, uint32_t v, color_map *m)
{
    const ynode *s = load_node(L, v);
    if (s->kind != YNODE_SEQ)
        return load_expected(L, v, "a list of [value, colour] stops", "colors");
    if (s->count < 1 || s->count > COLOR_MAP_MAX)
        return load_fail(L, v, "colors must have 1 to %d stops (got %u)", COLOR_MAP_MAX,
                         s->count);
    for (uint32_t i = 0; i < s->count; i++) {
        uint32_t stop = ydoc_item(load_doc(L), s, i);
        const ynode *sn = load_node(L, stop);
        if (sn->kind != YNODE_SEQ || sn->count != 2)
            return load_expected(L, stop, "a stop [value, colour]", "colors");
        uint32_t at = ydoc_item(load_doc(L), sn, 0);
        glint_rc rc = load_number(L, at, "colors", &m->at[i]);
        if (rc == GLINT_OK)
            rc = load_color(L, ydoc_item(load_doc(L), sn, 1), "colors", &m->color[i]);
        if (rc != GLINT_OK)
            return rc;
        if (i > 0 && m->at[i] < m->at[i - 1])
            return load_fail(L, at, "colors must be in ascending order of value (%g after %g)",
                             (double)m->at[i], (double)m->at[i - 1]);
    }
    m->n = (int)s->count;
    return GLINT_OK;
}

/* octaves, lacunarity, gain and (marble, wood) turbulence. */
static glint_rc read_fractal(loader *L, uint32_t map, pattern_noise *pn)
{
    uint32_t v;
    glint_rc rc = GLINT_OK;
    if ((v = load_get(L, map, "octaves")) != YDOC_NONE)
        rc = load_int(L, v, "octaves", 1, 16, &pn->octaves);
    if (rc == GLINT_OK && (v = load_get(L, map, "lacunarity")) != YDOC_NONE)
        rc = load_positive(L, v, "lacunarity", &pn->lacunarity);
    if (rc == GLINT_OK && (v = load_get(L, map, "gain")) != YDOC_NONE)
        rc = load_positive(L, v, "gain", &pn->gain);
    if (rc == GLINT_OK && (v = load_get(L, map, "turbulence")) != YDOC_NONE)
        rc = load_nonneg(L, v, "turbulence", &pn->amount);
    return rc;
}

/* space: and (images) mapping: and axis:, consistent with each other. */
static glint_rc read_space(loader *L, uint32_t map, texture *t)
{
    uint32_t sv = load_get(L, map, "space"), mv = load_get(L, map, "mapping");
    uint32_t av = load_get(L, map, "axis");
    int space = t->space, mapping = MAPPING_UV, axis = 2;
    glint_rc rc = GLINT_OK;
    if (mv != YDOC_NONE)
        rc = load_enum(L, mv, "mapping", "mapping", mappings, &mapping);
    if (t->kind == TEXTURE_IMAGE)
        space = mapping == MAPPING_UV ? SPACE_UV : SPACE_OBJECT;
    if (rc == GLINT_OK && sv != YDOC_NONE)
        rc = load_enum(L, sv, "space", "texture space", spaces, &space);
    bool mismatch = t->kind == TEXTURE_IMAGE && (space == SPACE_UV) != (mapping == MAPPING_UV);
    if (rc == GLINT_OK && mismatch && mapping == MAPPING_UV)
        rc = load_fail(L, sv, "an image with mapping uv is on (u, v); space object or world "
                              "needs mapping planar, spherical, cylindrical or box");
    else if (rc == GLINT_OK && mismatch)
        rc = load_fail(L, sv, "mapping %s projects a point in space: space must be object or "
                              "world", mappings[mapping]);
    if (rc == GLINT_OK && av != YDOC_NONE) {
        rc = load_enum(L, av, "axis", "axis", axes, &axis);
        if (rc == GLINT_OK && mapping != MAPPING_PLANAR)
            rc = load_fail(L, av, "axis is for mapping planar only");
    }
    t->space = (texture_space)space;
    if (t->kind == TEXTURE_IMAGE) {
        t->image.mapping = (texture_mapping)mapping;
        t->image.axis = axis;
    }
    return rc;
}

/* An image texture's own keys (the file last: the others are cheaper to
 * check). */
static glint_rc read_image(loader *L, uint32_t map, texture *t)
{
    uint32_t v, w = load_get(L, map, "wrap");
    glint_rc rc = load_need(L, map, "file", "image texture", &v);
    if (rc == GLINT_OK)
        rc = load_path_key(L, v, "file");
    if (rc == GLINT_OK && w != YDOC_NONE)
        rc = read_wrap(L, w, &t->image);
    if (rc == GLINT_OK)
        rc = read_space(L, map, t);
    if (rc == GLINT_OK)
        rc = read_placement(L, map, 2, t);
    if (rc == GLINT_OK)
        rc = load_image_file(L, v, &t->image.image);
    return rc;
}

/* A pattern's own keys. */
static glint_rc read_pattern(loader *L, uint32_t map, texture *t)
{
    uint32_t v, c = load_get(L, map, "colors");
    glint_rc rc = GLINT_OK;
    if (t->kind == TEXTURE_CHECKER) {
        uint32_t e = load_get(L, map, "even"), o = load_get(L, map, "odd");
        if (c != YDOC_NONE && (e != YDOC_NONE || o != YDOC_NONE))
            return load_fail(L, e != YDOC_NONE ? e : o,
                             "a checker takes even and odd or colors, not both");
        if (e != YDOC_NONE)
            rc = load_color(L, e, "even", &t->pattern.map.color[0]);
        if (rc == GLINT_OK && o != YDOC_NONE)
            rc = load_color(L, o, "odd", &t->pattern.map.color[1]);
    }
    if (rc == GLINT_OK && c != YDOC_NONE)
        rc = read_color_map(L, c, &t->pattern.map);
    if (rc == GLINT_OK)
        rc = read_fractal(L, map, &t->pattern.noise);
    if (rc == GLINT_OK && (v = load_get(L, map, "space")) != YDOC_NONE)
        rc = read_space(L, map, t);
    if (rc == GLINT_OK)
        rc = read_placement(L, map, t->space == SPACE_UV ? 2 : 3, t);
    return rc;
}

/* A texture mapping, added to the scene; its index goes to *index. */
glint_rc load_texture(loader *L, uint32_t map, int *index)
{
    uint32_t v;
    int type;
    glint_rc rc = load_need(L, map, "type", "texture", &v);
    if (rc == GLINT_OK)
        rc = load_enum(L, v, "type", "texture type", texture_types, &type);
    if (rc != GLINT_OK)
        return rc;
    rc = load_check_keys_in(L, map, texture_keys[type], texture_types[type], " texture");
    if (rc != GLINT_OK)
        return rc;
    texture t;
    if (type == TEXTURE_IMAGE) {
        t = texture_image(-1);
        rc = read_image(L, map, &t);
    } else {
        t = type == TEXTURE_CHECKER ? texture_checker(v3s(1.0f), v3s(0.0f), 1.0f, 1.0f)
                                    : texture_pattern((texture_kind)type);
        rc = read_pattern(L, map, &t);
    }
    if (rc != GLINT_OK)
        return rc;
    *index = scene_add_texture(L->s, &t);
    return *index < 0 ? err_nomem(L->err) : GLINT_OK;
}
