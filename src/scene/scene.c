#include "scene.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/array.h"
#include "core/error.h"
#include "geom/shape_bounds.h"
#include "scene/fingerprint.h"
#include "scene/settings.h"
#include "scene_surface.h"

scene *scene_new(void)
{
    scene *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->camera = (camera){.eye = v3(0, 0, 0), .target = v3(0, 0, -1), .up = v3(0, 1, 0),
                         .hfov = 90.0f, .projection = CAMERA_PERSPECTIVE};
    s->background = v3s(0.0f);
    s->ambient = v3s(0.2f);
    s->settings = (glint_settings){.width = 500, .height = 500, .samples = 1, .max_depth = 5,
                                   .threads = 0, .transfer = GLINT_TRANSFER_NONE,
                                   .adc_bailout = SETTINGS_ADC_BAILOUT,
                                   .sampler = GLINT_SAMPLER_GRID, .threshold = 0.05,
                                   .adaptive_depth = 3, .alpha = 0};
    s->anim.frames = 1;
    s->anim.fps = 24.0f;
    return s;
}

void scene_free(scene *s)
{
    if (!s)
        return;
    for (int i = 0; i < s->nimages; i++)
        image_free(&s->images[i]);
    free(s->warnings);
    free(s->objects);
    free(s->bounds);
    bvhw_free(&s->bvh);
    free(s->unbounded);
    free(s->xforms);
    free(s->materials);
    free(s->textures);
    free(s->images);
    free(s->lights);
    for (int i = 0; i < s->nmeshes; i++) {
        mesh_free(s->meshes[i]);
        free(s->meshes[i]);
    }
    free(s->meshes);
    for (int i = 0; i < s->nsources; i++)
        free(s->sources[i].path);
    free(s->sources);
    anim_free(&s->anim);
    for (int i = 0; i < s->npolyhedra; i++) {
        polyhedron_free(s->polyhedra[i]);
        free(s->polyhedra[i]);
    }
    free(s->polyhedra);
    for (int i = 0; i < s->ncsgs; i++) {
        csg_free(s->csgs[i]);
        free(s->csgs[i]);
    }
    free(s->csgs);
    free(s);
}

#define PUSH(arr, n, cap, value)                                                            \
    do {                                                                                    \
        int i_ = array_push((void **)&(arr), &(n), &(cap), sizeof *(arr));                  \
        if (i_ >= 0)                                                                        \
            (arr)[i_] = (value);                                                            \
        return i_;                                                                          \
    } while (0)

int scene_add_material(scene *s, const material *m) { PUSH(s->materials, s->nmaterials, s->cap_materials, *m); }
int scene_add_texture(scene *s, const texture *t) { PUSH(s->textures, s->ntextures, s->cap_textures, *t); }
int scene_add_light(scene *s, const light *l) { PUSH(s->lights, s->nlights, s->cap_lights, *l); }
int scene_add_xform(scene *s, const xform *x) { PUSH(s->xforms, s->nxforms, s->cap_xforms, *x); }

int scene_add_source(scene *s, const char *path)
{
    for (int i = 0; i < s->nsources; i++)
        if (strcmp(s->sources[i].path, path) == 0)
            return i;
    char *copy = strdup(path);
    if (!copy)
        return -1;
    int i = array_push((void **)&s->sources, &s->nsources, &s->cap_sources, sizeof *s->sources);
    if (i < 0)
        free(copy);
    else
        s->sources[i] = (scene_source){copy, 0, false};
    return i;
}

void scene_source_read(scene *s, int i, const void *data, size_t n)
{
    s->sources[i].bytes = fingerprint_file_bytes(data, n);
    s->sources[i].read = true;
}

int scene_add_image(scene *s, image *img)
{
    int i = array_push((void **)&s->images, &s->nimages, &s->cap_images, sizeof *s->images);
    if (i >= 0) {
        s->images[i] = *img;
        img->rgb = NULL;
    }
    return i;
}

void scene_set_image(scene *s, int i, image *img)
{
    image_free(&s->images[i]);
    s->images[i] = *img;
    *img = (image){0};
}

int scene_add_object(scene *s, const shape *sh, int mat, int xf)
{
    object o = {*sh, mat, xf, false, {0.0f, 0.0f, 0.0f}, -1, false};
    s->built = false;
    PUSH(s->objects, s->nobjects, s->cap_objects, o);
}

/* Makes *cap at least n + more, counted in elements of size elem. */
static bool reserve_more(void **items, int n, int *cap, int more, size_t elem)
{
    if (more <= 0 || n > INT_MAX - more || n + more <= *cap)
        return true;
    void *p = realloc(*items, (size_t)(n + more) * elem);
    if (!p)
        return false;
    *items = p;
    *cap = n + more;
    return true;
}

bool scene_reserve_objects(scene *s, int n)
{
    return reserve_more((void **)&s->objects, s->nobjects, &s->cap_objects, n,
                        sizeof *s->objects) &&
           reserve_more((void **)&s->xforms, s->nxforms, &s->cap_xforms, n, sizeof *s->xforms);
}

int scene_add_mesh(scene *s, mesh *m)
{
    PUSH(s->meshes, s->nmeshes, s->cap_meshes, m);
}

int scene_add_polyhedron(scene *s, polyhedron *p)
{
    PUSH(s->polyhedra, s->npolyhedra, s->cap_polyhedra, p);
}

int scene_add_csg(scene *s, csg *c)
{
    PUSH(s->csgs, s->ncsgs, s->cap_csgs, c);
}

void scene_set_camera(scene *s, const camera *c) { s->camera = *c; }

void scene_set_settings(scene *s, const glint_settings *st) { s->settings = *st; }

void scene_set_background(scene *s, vec3 color) { s->background = color; }

void scene_set_ambient(scene *s, vec3 color) { s->ambient = color; }

void scene_set_fog(scene *s, const fog *f) { s->fog = *f; }

void scene_set_material_texture(scene *s, int mat, int tex)
{
    s->materials[mat].texture = tex;
    s->built = false;
}

void scene_set_object_material(scene *s, int obj, int mat)
{
    s->objects[obj].material = mat;
    s->built = false;
}

void scene_set_material_bump(scene *s, int mat, int tex)
{
    s->materials[mat].bump = tex;
    s->built = false;
}

void scene_set_csg_material(scene *s, int c, int leaf, int mat)
{
    s->csgs[c]->leaves[leaf].material = mat;
    s->built = false;
}

camera scene_camera(const scene *s) { return s->camera; }

glint_settings scene_settings(const scene *s) { return s->settings; }

vec3 scene_background(const scene *s) { return s->background; }

vec3 scene_ambient(const scene *s) { return s->ambient; }

fog scene_fog(const scene *s) { return s->fog; }

int scene_object_count(const scene *s) { return s->nobjects; }

int scene_material_count(const scene *s) { return s->nmaterials; }

int scene_texture_count(const scene *s) { return s->ntextures; }

int scene_mesh_count(const scene *s) { return s->nmeshes; }

const struct mesh *scene_mesh(const scene *s, int index) { return s->meshes[index]; }

/* Whether testing the object costs several node visits: a transformed one
 * maps the ray first, and a torus, csg, mesh or polyhedron is dear in
 * itself. */
static bool object_is_dear(const object *o)
{
    switch (o->shape.kind) {
    case SHAPE_TORUS:
    case SHAPE_CSG:
    case SHAPE_MESH:
    case SHAPE_POLYHEDRON:
        return true;
    case SHAPE_SPHERE:
    case SHAPE_PLANE:
    case SHAPE_QUAD:
    case SHAPE_BOX:
    case SHAPE_CYLINDER:
    case SHAPE_TRIANGLE:
    case SHAPE_CONE:
    case SHAPE_DISK:
    case SHAPE_COUNT:
        break;
    }
    return o->xform >= 0;
}

/* Whether the material a shape uses (mat, or with mat -1 those of a
 * mesh's triangles or a csg's operands) exist; *transmits is set when one
 * of them transmits. */
static bool materials_ok(const scene *s, const shape *sh, int mat, bool *transmits)
{
    if (mat >= s->nmaterials)
        return false;
    if (mat >= 0) {
        *transmits = *transmits || s->materials[mat].transmit > 0.0f;
        return true;
    }
    if (sh->kind == SHAPE_CSG) {
        const csg *c = sh->csg;
        for (int k = 0; k < c->nleaves; k++)
            if (!materials_ok(s, &c->leaves[k].shape, c->leaves[k].material, transmits))
                return false;
        return true;
    }
    const mesh *m = sh->kind == SHAPE_MESH ? sh->mesh : NULL;
    if (!m || !m->tri_material)
        return false;
    for (int t = 0; t < m->ntris; t++) {
        int32_t tm = m->tri_material[t];
        if (tm < 0 || tm >= s->nmaterials)
            return false;
        *transmits = *transmits || s->materials[tm].transmit > 0.0f;
    }
    return true;
}

/* Textures' images and materials' textures exist; bump patterns are
 * functions of a point in space (their gradient is taken there). */
static glint_rc check_shading(const scene *s, glint_error *err)
{
    for (int i = 0; i < s->ntextures; i++)
        if (s->textures[i].kind == TEXTURE_IMAGE &&
            (s->textures[i].image.image < 0 || s->textures[i].image.image >= s->nimages))
            return err_set(err, GLINT_ERR_INPUT, "texture %d refers to a missing image", i);
    for (int i = 0; i < s->nmaterials; i++) {
        const material *m = &s->materials[i];
        if (m->texture >= s->ntextures || m->bump >= s->ntextures)
            return err_set(err, GLINT_ERR_INPUT, "material %d refers to a missing texture", i);
        if (m->bump >= 0 && s->textures[m->bump].space == SPACE_UV)
            return err_set(err, GLINT_ERR_INPUT,
                           "material %d's bump texture is on (u, v); bump patterns must be in "
                           "object or world space", i);
    }
    return GLINT_OK;
}

/* Scenes of at least this many bounded objects take ranges of up to a
 * node's width of them whole in their BVH (bvhw_build's bundles, eight on
 * the eight-wide paths, four on the others): each object keeps a lane of
 * its own, and the build does not split a range that one node holds. With
 * eight instead of four, 10^6 random spheres built 19% faster on one
 * thread (a third fewer nodes); row 8's render took as long. */
#define BUNDLE_MIN 4096
#define BUNDLE 8

/* The BVH over bounded objects; unbounded ones are listed apart. When
 * most of them are dear to test (object_is_dear) a leaf holds one, so
 * that a ray tests only the objects whose own boxes it enters: on row 8
 * of the benchmark (10,000 turned tori) 5 % fewer instructions. nb: the
 * bounded objects, dear: how many of them are dear. */
static glint_rc build_accel(scene *s, int nb, int dear, glint_error *err)
{
    s->nunbounded = 0;
    int32_t *bounded = NULL;
    if (nb < s->nobjects) { /* the unbounded apart, the others' indices in order */
        bounded = malloc(sizeof *bounded * (size_t)(nb ? nb : 1));
        if (!bounded) {
            bvhw_free(&s->bvh);
            return err_nomem(err);
        }
        for (int i = 0, k = 0; i < s->nobjects; i++) {
            if (aabb_is_unbounded(s->bounds[i]))
                s->unbounded[s->nunbounded++] = i;
            else
                bounded[k++] = i;
        }
    }
    /* The last build's arrays are reused (bvhw_rebuild) */
    glint_rc rc = bvhw_rebuild(&s->bvh, s->bounds, bounded, nb, nb > 4 && 2 * dear > nb ? 1 : 4,
                               nb >= BUNDLE_MIN ? BUNDLE : 0, accel_isa_active(), s->threads, err);
    free(bounded);
    return rc;
}

/* Object i's world bounds (scene_object_bounds) and where its object-space
 * textures have their origin (texture_origin), from one shape_bounds_inline. */
static aabb object_bounds(const scene *s, object *o)
{
    aabb b = shape_bounds_inline(&o->shape);
    if (o->shape.kind == SHAPE_PLANE)
        o->origin = o->shape.plane.point;
    else if (aabb_is_unbounded(b))
        o->origin = v3s(0.0f);
    else
        o->origin = v3_scale(v3_add(b.lo, b.hi), 0.5f);
    return scene_object_bounds_of(s, o, b);
}

/* Each object's material and transform checked, what scene_build notes
 * of it (transmits, motion, moving, crossed, origin) and its world bounds
 * in s->bounds; *nb: how many are bounded, *dear: how many of those are
 * dear to test. of: from scene_motions_of. */
static glint_rc build_objects(scene *s, const int *of, int *nb, int *dear, glint_error *err)
{
    s->ncrossed = 0;
    for (int i = 0; i < s->nobjects; i++) {
        object *o = &s->objects[i];
        o->transmits = false;
        if (o->material >= 0 && o->material < s->nmaterials)
            o->transmits = s->materials[o->material].transmit > 0.0f;
        else if (!materials_ok(s, &o->shape, o->material, &o->transmits))
            return err_set(err, GLINT_ERR_INPUT, "object %d refers to a missing material", i);
        if (o->xform >= s->nxforms)
            return err_set(err, GLINT_ERR_INPUT, "object %d refers to a missing transform", i);
        if (o->transmits && s->ncrossed >= 0)
            s->ncrossed = s->ncrossed < SCENE_FEW_CROSSED ? s->ncrossed + 1 : -1;
        if (o->transmits && s->ncrossed > 0)
            s->crossed[s->ncrossed - 1] = i;
        scene_link_motion(s, of, o);
        aabb b = object_bounds(s, o);
        s->bounds[i] = b;
        if (!aabb_is_unbounded(b)) {
            ++*nb;
            *dear += object_is_dear(o);
        }
    }
    return GLINT_OK;
}

static glint_rc build(scene *s, glint_error *err)
{
    glint_rc rc = check_shading(s, err);
    if (rc != GLINT_OK)
        return rc;
    /* The arrays of the last build are kept when they are large enough:
     * fresh memory would be cleared by the kernel first. */
    size_t n = (size_t)(s->nobjects ? s->nobjects : 1);
    if (n > s->cap_bounds) {
        aabb *bounds = malloc(sizeof *bounds * n);
        int32_t *unbounded = malloc(sizeof *unbounded * n);
        if (!bounds || !unbounded) {
            free(bounds);
            free(unbounded);
            return err_nomem(err);
        }
        if (s->nunbounded > 0) /* the built scene's, until this build is done */
            memcpy(unbounded, s->unbounded, sizeof *unbounded * (size_t)s->nunbounded);
        free(s->bounds);
        free(s->unbounded);
        s->bounds = bounds;
        s->unbounded = unbounded;
        s->cap_bounds = n;
    }
    int *of, nb = 0, dear = 0;
    if (!scene_motions_of(s, &of))
        return err_nomem(err);
    rc = build_objects(s, of, &nb, &dear, err);
    free(of);
    if (rc != GLINT_OK)
        return rc;
    rc = build_accel(s, nb, dear, err);
    if (rc != GLINT_OK)
        return rc;
    s->flat = s->bvh.nnodes == 0 || s->bvh.leaf_root;
    s->any_transmit = s->any_reflect = s->any_absorb = false;
    for (int i = 0; i < s->nmaterials; i++) {
        const material *m = &s->materials[i];
        s->any_transmit = s->any_transmit || m->transmit > 0.0f;
        s->any_reflect = s->any_reflect || m->reflect > 0.0f;
        s->any_absorb = s->any_absorb || material_absorbs(m);
    }
    s->built = true;
    return GLINT_OK;
}

SCENE_KERNELS(sse, 4)

/* The flat scene's queries, out of line so that the dispatchers below
 * stay small for every other scene. */
static __attribute__((noinline)) bool intersect_flat(const scene *s, const ray *r,
                                                     scene_hit *hit)
{
    return scene_closest_walk(s, r, hit, 4, true);
}

static __attribute__((noinline)) bool occluded_flat(const scene *s, const ray *r)
{
    return scene_any_walk(s, r, 4, true);
}

static __attribute__((noinline)) bool shadow_flat(const scene *s, const ray *r,
                                                  scene_crossings *out)
{
    return scene_shadow_walk(s, r, out, 4, true);
}

bool scene_intersect(const scene *s, const ray *r, scene_hit *hit)
{
    if (s->flat)
        return intersect_flat(s, r, hit);
    accel_isa isa = s->bvh.isa;
#if defined(GLINT_WIDE_KERNELS)
    if (isa == ACCEL_AVX512)
        return scene_intersect_avx512(s, r, hit);
    if (isa == ACCEL_AVX2)
        return scene_intersect_avx2(s, r, hit);
#endif
    return isa == ACCEL_SCALAR ? scene_intersect_scalar(s, r, hit) : scene_intersect_sse(s, r, hit);
}

bool scene_occluded_opaque(const scene *s, const ray *r)
{
    if (s->flat)
        return occluded_flat(s, r);
    accel_isa isa = s->bvh.isa;
#if defined(GLINT_WIDE_KERNELS)
    if (isa == ACCEL_AVX512)
        return scene_occluded_avx512(s, r);
    if (isa == ACCEL_AVX2)
        return scene_occluded_avx2(s, r);
#endif
    return isa == ACCEL_SCALAR ? scene_occluded_scalar(s, r) : scene_occluded_sse(s, r);
}

bool scene_shadow(const scene *s, const ray *r, scene_crossings *out)
{
    accel_isa isa = s->bvh.isa;
    bool blocked;
    if (s->flat)
        blocked = shadow_flat(s, r, out);
#if defined(GLINT_WIDE_KERNELS)
    else if (isa == ACCEL_AVX512)
        blocked = scene_shadow_walk_avx512(s, r, out);
    else if (isa == ACCEL_AVX2)
        blocked = scene_shadow_walk_avx2(s, r, out);
    else
#endif
        blocked = isa == ACCEL_SCALAR ? scene_shadow_walk_scalar(s, r, out)
                                      : scene_shadow_walk_sse(s, r, out);
    if (blocked)
        return true;
    scene_sort_crossings(out);
    return false;
}

void scene_surface(const scene *s, const ray *r, const scene_hit *hit, surface *out)
{
    scene_surface_inline(s, r, hit, out);
}

void scene_object_point(const scene *s, int i, vec3 p, vec3 n, vec3 *po, vec3 *no)
{
    const object *o = &s->objects[i];
    if (o->xform < 0) {
        *po = v3_sub(p, o->origin);
        *no = n;
        return;
    }
    const xform *x = &s->xforms[o->xform];
    mat4 ft = mat4_transpose(&x->fwd);
    *po = v3_sub(mat4_point(&x->inv, p), o->origin);
    *no = mat4_vector(&ft, n);
}

bool scene_add_warnings(scene *s, const char *lines)
{
    size_t have = s->warnings ? strlen(s->warnings) : 0, n = strlen(lines);
    if (n == 0)
        return true;
    char *w = realloc(s->warnings, have + n + 1);
    if (!w)
        return false;
    memcpy(w + have, lines, n + 1);
    s->warnings = w;
    return true;
}

const char *scene_warnings(const scene *s) { return s->warnings ? s->warnings : ""; }

/* Times the build for --stats (glint_scene_describe). */
glint_rc scene_build(scene *s, glint_error *err)
{
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    glint_rc rc = build(s, err);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    s->build_seconds = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-9;
    return rc;
}
