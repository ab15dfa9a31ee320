/* scene_trace: a ray against the scene's objects (the scene's BVH, then
 * each object's own test), written once and compiled once per SIMD path
 * (accel/isa.h): scene.c holds the SSE copy, scene_scalar.c,
 * scene_avx2.c and scene_avx512.c the others. scene_intersect and
 * scene_occluded_opaque call the copy that matches the layout the scene's
 * BVH was built for. */
#ifndef GLINT_SCENE_SCENE_TRACE_H
#define GLINT_SCENE_SCENE_TRACE_H

#include "accel/traverse.h"
#include "geom/shape_inline.h"
#include "scene/scene.h"

/* The ray in the object's own space; t values carry over unchanged because
 * the direction is transformed without renormalising. */
__attribute__((always_inline)) static inline ray scene_object_ray(const scene *s, const object *o, const ray *r)
{
    if (o->xform < 0) /* field by field: a block copy (rep movs, which a profile-guided
                         build can choose) leaves its 4-byte stores for the wider reads of
                         the ray that follow to wait on */
        return (ray){.o = r->o, .tmin = r->tmin, .d = r->d, .tmax = r->tmax, .time = r->time};
    if (__builtin_expect(o->moving, 0)) {
        xform x = scene_object_xform_at(s, o, r->time);
        return mat4_ray(&x.inv, r);
    }
    const xform *x = &s->xforms[o->xform];
    return mat4_ray(&x->inv, r);
}

typedef struct scene_leaf_ctx {
    const scene *s;
    const ray *r;
    scene_hit *hit;
} scene_leaf_ctx;

/* Object i's hit, kept when it is nearer than *tmax, or as near and i is
 * lower than hit->object (-1 before the first hit): of two objects hit at
 * the same distance the lower index wins, whatever order the walk visits
 * them in (scene_intersect8 visits them in another). */
__attribute__((always_inline)) static inline bool scene_hit_object(const scene *s, int i,
                                                                   const ray *r, float tmin,
                                                                   float *tmax, scene_hit *hit)
{
    const object *o = &s->objects[i];
    ray lr = scene_object_ray(s, o, r);
    lr.tmin = tmin;
    lr.tmax = next_up(*tmax);
    shape_hit h;
    shape_hit_at(&h, 0.0f);
    if (!shape_intersect_inline(&o->shape, &lr, &h) ||
        !(h.t < *tmax || (h.t == *tmax && i < hit->object)))
        return false;
    *tmax = h.t;
    hit->h = h;
    hit->object = i;
    return true;
}

__attribute__((always_inline)) static inline bool scene_leaf_closest(void *ctx, uint32_t first,
                                                                     uint32_t count, float tmin,
                                                                     float *tmax)
{
    scene_leaf_ctx *c = ctx;
    const int32_t *prims = c->s->bvh.prims + first;
    bool found = false;
    for (uint32_t i = 0; i < count; i++)
        found |= scene_hit_object(c->s, prims[i], c->r, tmin, tmax, c->hit);
    return found;
}

__attribute__((always_inline)) static inline bool scene_blocks(const scene *s, int i, const ray *r)
{
    const object *o = &s->objects[i];
    if (o->transmits)
        return false;
    ray lr = scene_object_ray(s, o, r);
    return shape_occluded_inline(&o->shape, &lr);
}

__attribute__((always_inline)) static inline bool scene_leaf_any(void *ctx, uint32_t first,
                                                                 uint32_t count, float tmin,
                                                                 float *tmax)
{
    (void)tmin, (void)tmax;
    scene_leaf_ctx *c = ctx;
    const int32_t *prims = c->s->bvh.prims + first;
    for (uint32_t i = 0; i < count; i++)
        if (scene_blocks(c->s, prims[i], c->r))
            return true;
    return false;
}

typedef struct scene_shadow_ctx {
    const scene *s;
    const ray *r;
    float dlen;
    scene_crossings *out;
} scene_shadow_ctx;

/* Whether ray r (whose direction's inverse is inv) meets the world bounds
 * of object i within its range, as the walks' box tests would let it reach
 * the object (core/aabb.h: rounding never drops a ray); true for an
 * unbounded object. */
__attribute__((always_inline)) static inline bool scene_bounds_met(const scene *s, int i,
                                                                   const ray *r, vec3 inv)
{
    aabb b = s->bounds[i];
    if (!v3_is_finite(b.lo) || !v3_is_finite(b.hi))
        return true;
    return aabb_hit(b, r->o, inv, r->tmin, r->tmax);
}

/* Where the search for a shadow ray's next crossing starts after one at
 * t: ray_epsilon beyond it (core/ray.h). */
__attribute__((always_inline)) static inline float scene_cross_next(const scene_shadow_ctx *c,
                                                                    float t)
{
    float next = t + ray_epsilon(ray_at(c->r, t)) / c->dlen;
    return next > t ? next : nextafterf(t, INFINITY);
}

/* Object i against a shadow ray: true when it blocks it (an opaque object
 * in the way, or more crossings than fit); a transmitting object adds its
 * crossings to c->out. */
__attribute__((always_inline)) static inline bool scene_shadow_object(scene_shadow_ctx *c, int i)
{
    const object *o = &c->s->objects[i];
    ray lr = scene_object_ray(c->s, o, c->r);
    if (!o->transmits)
        return shape_occluded_inline(&o->shape, &lr);
    scene_crossings *out = c->out;
    shape_hit h;
    float root[2];
    if (o->shape.kind == SHAPE_SPHERE) { /* the loop below, with one root finding */
        if (!sphere_roots(&o->shape.sphere, &lr, &root[0], &root[1]))
            return false;
        for (int k = 0; k < 2; k++) {
            if (!ray_in_range(&lr, root[k]))
                continue;
            if (out->n == SCENE_SHADOW_MAX)
                return true;
            scene_hit *x = &out->hit[out->n++]; /* as sphere_hit's */
            shape_hit_at(&x->h, root[k]);
            x->object = i;
            lr.tmin = scene_cross_next(c, root[k]);
        }
        return false;
    }
    while (shape_intersect_inline(&o->shape, &lr, &h)) {
        if (out->n == SCENE_SHADOW_MAX)
            return true;
        out->hit[out->n++] = (scene_hit){h, i};
        lr.tmin = scene_cross_next(c, h.t);
    }
    return false;
}

/* Crossings by t, ties by object; few, mostly in order already:
 * insertion sort. */
static inline void scene_sort_crossings(scene_crossings *out)
{
    for (int i = 1; i < out->n; i++) {
        scene_hit h = out->hit[i];
        int j = i;
        for (; j > 0 && (out->hit[j - 1].h.t > h.h.t ||
                         (out->hit[j - 1].h.t == h.h.t && out->hit[j - 1].object > h.object));
             j--)
            out->hit[j] = out->hit[j - 1];
        out->hit[j] = h;
    }
}

__attribute__((always_inline)) static inline bool scene_leaf_shadow(void *ctx, uint32_t first,
                                                                    uint32_t count, float tmin,
                                                                    float *tmax)
{
    (void)tmin, (void)tmax;
    scene_shadow_ctx *c = ctx;
    const int32_t *prims = c->s->bvh.prims + first;
    for (uint32_t i = 0; i < count; i++)
        if (scene_shadow_object(c, prims[i]))
            return true;
    return false;
}

/* The one leaf of a flat scene (scene.flat): its first entry in bvh.prims
 * and its count (0 for an empty tree). */
static inline uint32_t scene_flat_leaf(const scene *s, uint32_t *first)
{
    const bvhw *b = &s->bvh;
    *first = 0;
    if (b->nnodes == 0)
        return 0;
    int32_t c = b->width == 8 ? b->n8[0].child[0] : b->n4[0].child[0];
    *first = (uint32_t)(-1 - c);
    return b->width == 8 ? b->n8[0].count[0] : b->n4[0].count[0];
}

/* A tree of one node, whose children are then all leaves (a small scene:
 * up to width leaves): the node's test, and its leaves visited near to far
 * for closest hits (ties in child order) or in child order for the others,
 * without the traversal's stack. */
__attribute__((always_inline)) static inline int scene_node_test(const scene *s, int width,
                                                                 const wide_ray *wr, float tmax,
                                                                 float tn[8], const int32_t **child,
                                                                 const uint32_t **count)
{
    (void)width;
#if defined(GLINT_TRAVERSE_AVX2)
    if (width == 8) {
        *child = s->bvh.n8[0].child;
        *count = s->bvh.n8[0].count;
        return wide_test8(&s->bvh.n8[0], wr, tmax, tn);
    }
#endif
    *child = s->bvh.n4[0].child;
    *count = s->bvh.n4[0].count;
    return wide_test4(&s->bvh.n4[0], wr, tmax, tn);
}

__attribute__((always_inline)) static inline bool scene_closest_node(scene_leaf_ctx *c, int width,
                                                                     float *tmax)
{
    const ray *r = c->r;
    wide_ray wr = wide_ray_make(r->o, r->d, r->tmin);
    float tn[8];
    const int32_t *child;
    const uint32_t *count;
    int mask = scene_node_test(c->s, width, &wr, wide_reach(*tmax), tn, &child, &count);
    bool found = false;
    while (mask) {
        int k = __builtin_ctz((unsigned)mask);
        for (int m = mask & (mask - 1); m; m &= m - 1) {
            int j = __builtin_ctz((unsigned)m);
            k = tn[j] < tn[k] ? j : k;
        }
        if (tn[k] > wide_reach(*tmax))
            break;
        mask &= ~(1 << k);
        found |= scene_leaf_closest(c, (uint32_t)(-1 - child[k]), count[k], r->tmin, tmax);
    }
    return found;
}

/* The same for the queries that stop at a blocker (leaf is scene_leaf_any
 * or scene_leaf_shadow). */
__attribute__((always_inline)) static inline bool scene_blocked_node(const scene *s, const ray *r,
                                                                     int width, wide_leaf_fn leaf,
                                                                     void *ctx)
{
    wide_ray wr = wide_ray_make(r->o, r->d, r->tmin);
    float tn[8], tmax = r->tmax;
    const int32_t *child;
    const uint32_t *count;
    int mask = scene_node_test(s, width, &wr, tmax, tn, &child, &count);
    for (; mask; mask &= mask - 1) {
        int k = __builtin_ctz((unsigned)mask);
        if (leaf(ctx, (uint32_t)(-1 - child[k]), count[k], r->tmin, &tmax))
            return true;
    }
    return false;
}

/* The three queries: unbounded objects first, then the BVH of the given
 * width, or for a flat scene its one leaf without a traversal (and so
 * without the traversal's stack frame). */
__attribute__((always_inline)) static inline bool
scene_closest_walk(const scene *s, const ray *r, scene_hit *hit, int width, bool flat)
{
    float tmax = r->tmax;
    bool found = false;
    hit->object = -1;
    for (int i = 0; i < s->nunbounded; i++)
        found |= scene_hit_object(s, s->unbounded[i], r, r->tmin, &tmax, hit);
    scene_leaf_ctx c = {s, r, hit};
    uint32_t first, n;
    if (!flat && s->bvh.nnodes == 1)
        found |= scene_closest_node(&c, width, &tmax);
    else if (!flat)
        found |= wide_traverse(&s->bvh, width, r->o, r->d, r->tmin, &tmax, false,
                               scene_leaf_closest, &c);
    else if ((n = scene_flat_leaf(s, &first)) > 0)
        found |= scene_leaf_closest(&c, first, n, r->tmin, &tmax);
    return found;
}

__attribute__((always_inline)) static inline bool scene_any_walk(const scene *s, const ray *r,
                                                                 int width, bool flat)
{
    for (int i = 0; i < s->nunbounded; i++)
        if (scene_blocks(s, s->unbounded[i], r))
            return true;
    scene_leaf_ctx c = {s, r, NULL};
    float tmax = r->tmax;
    uint32_t first, n;
    if (!flat && s->bvh.nnodes == 1)
        return scene_blocked_node(s, r, width, scene_leaf_any, &c);
    if (!flat)
        return wide_traverse(&s->bvh, width, r->o, r->d, r->tmin, &tmax, true, scene_leaf_any,
                             &c);
    return (n = scene_flat_leaf(s, &first)) > 0 && scene_leaf_any(&c, first, n, r->tmin, &tmax);
}

__attribute__((always_inline)) static inline bool
scene_shadow_walk(const scene *s, const ray *r, scene_crossings *out, int width, bool flat)
{
    scene_shadow_ctx c = {s, r, v3_len(r->d), out};
    out->n = 0;
    for (int i = 0; i < s->nunbounded; i++)
        if (scene_shadow_object(&c, s->unbounded[i]))
            return true;
    float tmax = r->tmax;
    uint32_t first, n;
    if (!flat && s->bvh.nnodes == 1)
        return scene_blocked_node(s, r, width, scene_leaf_shadow, &c);
    if (!flat)
        return wide_traverse(&s->bvh, width, r->o, r->d, r->tmin, &tmax, true,
                             scene_leaf_shadow, &c);
    return (n = scene_flat_leaf(s, &first)) > 0 &&
           scene_leaf_shadow(&c, first, n, r->tmin, &tmax);
}

/* Defines scene_intersect_<isa>, scene_occluded_<isa> and
 * scene_shadow_walk_<isa> for nodes of the given width. */
#define SCENE_KERNELS(isa, width)                                                              \
    bool scene_intersect_##isa(const scene *s, const ray *r, scene_hit *hit)                   \
    {                                                                                          \
        return scene_closest_walk(s, r, hit, width, false);                                    \
    }                                                                                          \
    bool scene_occluded_##isa(const scene *s, const ray *r)                                    \
    {                                                                                          \
        return scene_any_walk(s, r, width, false);                                             \
    }                                                                                          \
    bool scene_shadow_walk_##isa(const scene *s, const ray *r, scene_crossings *out)           \
    {                                                                                          \
        return scene_shadow_walk(s, r, out, width, false);                                     \
    }

bool scene_intersect_scalar(const scene *s, const ray *r, scene_hit *hit);
bool scene_occluded_scalar(const scene *s, const ray *r);
bool scene_shadow_walk_scalar(const scene *s, const ray *r, scene_crossings *out);
bool scene_intersect_sse(const scene *s, const ray *r, scene_hit *hit);
bool scene_occluded_sse(const scene *s, const ray *r);
bool scene_shadow_walk_sse(const scene *s, const ray *r, scene_crossings *out);
bool scene_intersect_avx2(const scene *s, const ray *r, scene_hit *hit);
bool scene_occluded_avx2(const scene *s, const ray *r);
bool scene_shadow_walk_avx2(const scene *s, const ray *r, scene_crossings *out);
bool scene_intersect_avx512(const scene *s, const ray *r, scene_hit *hit);
bool scene_occluded_avx512(const scene *s, const ray *r);
bool scene_shadow_walk_avx512(const scene *s, const ray *r, scene_crossings *out);
#endif
