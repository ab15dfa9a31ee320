/* scene_trace: a ray against the scene's objects (the scene's BVH, then
 * each object's own test), written once and compiled once per SIMD path
 * (accel/isa.h): scene.c holds the SSE copy, scene_scalar.c,
 * scene_avx2.c and scene_avx512.c the others. scene_intersect and
 * scene_occluded_opaque call the copy that matches the layout the scene's
 * BVH was built for. */
#ifndef GLINT_SCENE_SCENE_TRACE_H
#define GLINT_SCENE_SCENE_TRACE_H

#include "accel/traverse.h"
#if defined(GLINT_TRAVERSE_AVX2)
#include "geom/mesh_packet.h"
#include "geom/shape8.h"
#endif
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

/* keep8 for shape8_hit's hits h of the rays of `any`, of which those of
 * `nearer` beat best[k] and the others tie with it. */
static inline int keep_hits8(int i, int any, int nearer, const shape_hits8 *h, float best[8],
                             scene_hit hit[8])
{
    int kept = nearer;
    for (int m = any & ~nearer; m; m &= m - 1) { /* ties: the lower index */
        int k = __builtin_ctz((unsigned)m);
        kept |= (i < hit[k].object) << k;
    }
    for (int m = kept; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        best[k] = h->t[k];
        hit[k] = (scene_hit){{.t = h->t[k], .part = h->part[k], .b1 = h->b1[k], .b2 = h->b2[k]}, i};
    }
    return kept;
}

/* Object i against the rays of active of packet r, each searched up to
 * best[k] (scene_packet.c); returns the rays whose nearest hit it now is. */
int scene_packet_object(const scene *s, int i, const ray8 *r, int active, float best[8],
                        scene_hit hit[8]);

/* Object i against the shadow rays of active, as scene_shadow_object asks
 * it: adds to *blocked the rays an opaque object blocks, to *crosses those
 * a transmitting one meets, or may meet (scene_shadow8, scene_packet.c). */
void scene_shadow8_object(const scene *s, int i, const ray8 *r, int active, int *blocked,
                          int *crosses);

#if defined(GLINT_TRAVERSE_AVX2)
typedef struct scene_packet_ctx {
    const scene *s;
    const ray8 *r;
    float *best;
    scene_hit *hit;
    int found;
} scene_packet_ctx;

/* keep_hits8 with best written in one 32-byte store, which the next
 * test's 32-byte load of it takes straight from the store (the kept
 * lanes' 4-byte stores made that load wait until they reached the
 * cache). */
__attribute__((always_inline)) static inline int keep_hits8_wide(int i, int any, int nearer,
                                                                 const shape_hits8 *h,
                                                                 float best[8], scene_hit hit[8])
{
    int kept = nearer;
    for (int m = any & ~nearer; m; m &= m - 1) { /* ties: the lower index */
        int k = __builtin_ctz((unsigned)m);
        kept |= (i < hit[k].object) << k;
    }
    if (!kept)
        return 0;
    _mm256_storeu_ps(best, _mm256_blendv_ps(_mm256_loadu_ps(best), _mm256_loadu_ps(h->t),
                                            packet_lanes(kept)));
    for (int m = kept; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        hit[k] = (scene_hit){{.t = h->t[k], .part = h->part[k], .b1 = h->b1[k], .b2 = h->b2[k]}, i};
    }
    return kept;
}

/* Object k against the rays of `rays`, as scene_packet_object tests it. */
__attribute__((always_inline)) static inline void scene_packet_one(scene_packet_ctx *c, int k,
                                                                   int rays)
{
    const object *o = &c->s->objects[k];
    if (o->xform < 0 && shape_tests_eight(o->shape.kind) && ray8_three_or_more(rays)) {
        /* scene_packet_object's commonest case, here without its calls */
        shape_hits8 h;
        int nearer = 0, any = shape8_hit(&o->shape, c->r, c->best, rays, &h, &nearer);
        c->found |= keep_hits8_wide(k, any, nearer, &h, c->best, c->hit);
    } else {
        c->found |= scene_packet_object(c->s, k, c->r, rays, c->best, c->hit);
    }
}

__attribute__((always_inline)) static inline bool scene_packet_leaf(void *ctx, uint32_t first,
                                                                    uint32_t count, int rays,
                                                                    __m256 *tmax)
{
    scene_packet_ctx *c = ctx;
    for (uint32_t i = 0; i < count; i++)
        scene_packet_one(c, c->s->bvh.prims[first + i], rays);
    *tmax = _mm256_loadu_ps(c->best);
    return true;
}

/* The rays of active through the scene's eight-wide tree together
 * (packet_walk), each leaf's objects tested against the rays that enter
 * it; the order of the leaves does not change the hits (scene_hit_object).
 * Returns the rays whose nearest hit was found here, or -1 when the rays
 * differ in their directions' signs. */
__attribute__((always_inline)) static inline int scene_walk8(const scene *s, const ray8 *r,
                                                             int active, float best[8],
                                                             scene_hit hit[8], bool cull)
{
    packet8 p;
    if (s->bvh.width != 8 || s->bvh.nnodes == 0 || !packet_make(&p, r, active))
        return -1;
    scene_packet_ctx c = {s, r, best, hit, 0};
    __m256 tmax = _mm256_loadu_ps(best);
    if (cull)
        packet_bound(&p, active);
    packet_walk(&s->bvh, &p, active, &tmax, scene_packet_leaf, &c, cull);
    return c.found;
}

typedef struct scene_shadow8_ctx {
    const scene *s;
    const ray8 *r;
    int active, blocked, crosses;
} scene_shadow8_ctx;

/* Object i against the shadow rays of active, as scene_shadow8_object
 * asks it: its commonest case (an unturned shape of shape_tests_eight's
 * kinds and three rays or more) here, without the calls. */
__attribute__((always_inline)) static inline void scene_shadow8_one(const scene *s, int i,
                                                                    const ray8 *r, int active,
                                                                    int *blocked, int *crosses)
{
    const object *o = &s->objects[i];
    if (o->xform < 0 && !o->moving && shape_tests_eight(o->shape.kind) &&
        ray8_three_or_more(active)) {
        *(o->transmits ? crosses : blocked) |= shape8_hit(&o->shape, r, NULL, active, NULL, NULL);
        return;
    }
    scene_shadow8_object(s, i, r, active, blocked, crosses);
}

/* A leaf's objects against the shadow rays that enter it and are not yet
 * blocked; a blocked ray's lane of *tmax drops below every box, and once
 * every ray is blocked the walk stops. */
__attribute__((always_inline)) static inline bool scene_shadow8_leaf(void *ctx, uint32_t first,
                                                                     uint32_t count, int rays,
                                                                     __m256 *tmax)
{
    scene_shadow8_ctx *c = ctx;
    for (uint32_t i = 0; i < count; i++)
        scene_shadow8_one(c->s, c->s->bvh.prims[first + i], c->r, rays & ~c->blocked,
                          &c->blocked, &c->crosses);
    if (!(c->active & ~c->blocked))
        return false;
    *tmax = _mm256_blendv_ps(*tmax, _mm256_set1_ps(-INFINITY), packet_lanes(c->blocked));
    return true;
}

/* The shadow rays of active through the scene's eight-wide tree together,
 * adding to *blocked and *crosses (scene_shadow8); false when the rays
 * differ in their directions' signs. */
__attribute__((always_inline)) static inline bool scene_shadow_walk8(const scene *s, const ray8 *r,
                                                                     int active, int *blocked,
                                                                     int *crosses, bool cull)
{
    packet8 p;
    if (s->bvh.width != 8 || s->bvh.nnodes == 0 || !packet_make(&p, r, active))
        return s->bvh.nnodes == 0;
    scene_shadow8_ctx c = {s, r, active, *blocked, *crosses};
    __m256 tmax = _mm256_loadu_ps(r->tmax);
    if (cull)
        packet_bound(&p, active);
    packet_walk(&s->bvh, &p, active, &tmax, scene_shadow8_leaf, &c, cull);
    *blocked = c.blocked;
    *crosses = c.crosses;
    return true;
}

/* Row i of a times (x, y, z, w), in mat4_point's order of operations
 * (w 0: mat4_vector's, which adds nothing). */
static inline __m256 scene_row8(const float a[4], __m256 x, __m256 y, __m256 z, bool w)
{
    __m256 v = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(a[0]), x),
                                           _mm256_mul_ps(_mm256_set1_ps(a[1]), y)),
                             _mm256_mul_ps(_mm256_set1_ps(a[2]), z));
    return w ? _mm256_add_ps(v, _mm256_set1_ps(a[3])) : v;
}

/* object_rays (scene_packet.c) in vector registers, to the bit the same:
 * the rays of active through inv (NULL: as they are), each searched up to
 * next_up(best[k]) (best NULL: its tmax), the idle lanes repeating the
 * first active one (ray8_fill). */
__attribute__((always_inline)) static inline void
scene_object_rays8(const mat4 *inv, const ray8 *r, int active, const float *best, ray8 *out)
{
    __m256 v[9] = {_mm256_loadu_ps(r->ox),   _mm256_loadu_ps(r->oy),   _mm256_loadu_ps(r->oz),
                   _mm256_loadu_ps(r->dx),   _mm256_loadu_ps(r->dy),   _mm256_loadu_ps(r->dz),
                   _mm256_loadu_ps(r->tmin), _mm256_loadu_ps(r->tmax), _mm256_loadu_ps(r->time)};
    if (inv) {
        __m256 o[3] = {v[0], v[1], v[2]}, d[3] = {v[3], v[4], v[5]};
        for (int i = 0; i < 3; i++) {
            v[i] = scene_row8(inv->m[i], o[0], o[1], o[2], true);
            v[3 + i] = scene_row8(inv->m[i], d[0], d[1], d[2], false);
        }
    }
    if (best)
        v[7] = packet_next_up(_mm256_loadu_ps(best));
    __m256i first = _mm256_set1_epi32(__builtin_ctz((unsigned)active));
    __m256 idle = packet_lanes(~active & 0xff);
    float *field[9] = {out->ox, out->oy, out->oz, out->dx,  out->dy,
                       out->dz, out->tmin, out->tmax, out->time};
    for (int i = 0; i < 9; i++)
        _mm256_storeu_ps(field[i],
                         _mm256_blendv_ps(v[i], _mm256_permutevar8x32_ps(v[i], first), idle));
}

/* Defines scene_walk8_<isa>, scene_shadow_walk8_<isa>, their _culled
 * twins and scene_object_rays8_<isa>. Each walk is flattened: its leaf's
 * shape tests (shape8_hit) are inlined into it, as they were when the
 * file held one walk of each kind and GCC inlined what was called once. */
#define SCENE_PACKET_KERNELS(isa)                                                              \
    void scene_object_rays8_##isa(const mat4 *inv, const ray8 *r, int active,                 \
                                  const float *best, ray8 *out)                                \
    {                                                                                          \
        scene_object_rays8(inv, r, active, best, out);                                         \
    }                                                                                          \
    __attribute__((flatten))                                                                   \
    int scene_among8_##isa(const scene *s, const ray8 *r, int active, const int32_t *list,     \
                           int n, scene_hit hit[8])                                            \
    {                                                                                          \
        float best[8];                                                                         \
        _mm256_storeu_ps(best, _mm256_loadu_ps(r->tmax));                                      \
        for (int k = 0; k < 8; k++)                                                            \
            hit[k].object = -1;                                                                \
        scene_packet_ctx c = {s, r, best, hit, 0};                                             \
        for (int i = 0; i < s->nunbounded; i++)                                                \
            scene_packet_one(&c, s->unbounded[i], active);                                     \
        for (int i = 0; i < n; i++)                                                            \
            scene_packet_one(&c, list[i], active);                                             \
        return c.found;                                                                        \
    }                                                                                          \
    __attribute__((flatten))                                                                   \
    void scene_shadow_among8_##isa(const scene *s, const ray8 *r, int active,                  \
                                   const int32_t *list, int n, int *blocked, int *crosses)     \
    {                                                                                          \
        for (int i = 0; i < s->nunbounded; i++)                                                \
            scene_shadow8_one(s, s->unbounded[i], r, active & ~*blocked, blocked, crosses);    \
        for (int i = 0; i < n; i++)                                                            \
            scene_shadow8_one(s, list[i], r, active & ~*blocked, blocked, crosses);            \
    }                                                                                          \
    __attribute__((flatten))                                                                   \
    int scene_walk8_##isa(const scene *s, const ray8 *r, int active, float best[8],            \
                          scene_hit hit[8])                                                    \
    {                                                                                          \
        return scene_walk8(s, r, active, best, hit, false);                                    \
    }                                                                                          \
    __attribute__((flatten))                                                                   \
    int scene_walk8_culled_##isa(const scene *s, const ray8 *r, int active, float best[8],     \
                                 scene_hit hit[8])                                             \
    {                                                                                          \
        return scene_walk8(s, r, active, best, hit, true);                                     \
    }                                                                                          \
    __attribute__((flatten))                                                                   \
    bool scene_shadow_walk8_##isa(const scene *s, const ray8 *r, int active, int *blocked,     \
                                  int *crosses)                                                \
    {                                                                                          \
        return scene_shadow_walk8(s, r, active, blocked, crosses, false);                      \
    }                                                                                          \
    __attribute__((flatten))                                                                   \
    bool scene_shadow_walk8_culled_##isa(const scene *s, const ray8 *r, int active,            \
                                         int *blocked, int *crosses)                           \
    {                                                                                          \
        return scene_shadow_walk8(s, r, active, blocked, crosses, true);                       \
    }
#endif

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
/* The packet walks: without culling the nodes' children for the whole
 * packet (for a tree of one node, where it costs more than it saves: +2.7%
 * instructions on the built-in scene's nine objects) and with it (the
 * _culled ones, for deeper trees: -4.5% on bench row 8's 11,000 objects);
 * each compiled on its own, as the walk together with its leaf tests. */
int scene_walk8_avx2(const scene *s, const ray8 *r, int active, float best[8], scene_hit hit[8]);
int scene_walk8_avx512(const scene *s, const ray8 *r, int active, float best[8],
                       scene_hit hit[8]);
int scene_walk8_culled_avx2(const scene *s, const ray8 *r, int active, float best[8],
                            scene_hit hit[8]);
int scene_walk8_culled_avx512(const scene *s, const ray8 *r, int active, float best[8],
                              scene_hit hit[8]);
/* scene_intersect8_among: the rays of active against the unbounded
 * objects and the n of list, as a walk's leaves test them. */
int scene_among8_avx2(const scene *s, const ray8 *r, int active, const int32_t *list, int n,
                      scene_hit hit[8]);
int scene_among8_avx512(const scene *s, const ray8 *r, int active, const int32_t *list, int n,
                        scene_hit hit[8]);
/* scene_shadow8_among's tests: the shadow rays of active against the
 * unbounded objects and the n of list, adding to *blocked and *crosses. */
void scene_shadow_among8_avx2(const scene *s, const ray8 *r, int active, const int32_t *list,
                              int n, int *blocked, int *crosses);
void scene_shadow_among8_avx512(const scene *s, const ray8 *r, int active, const int32_t *list,
                                int n, int *blocked, int *crosses);
/* object_rays eight lanes at once (scene_object_rays8). */
void scene_object_rays8_avx2(const mat4 *inv, const ray8 *r, int active, const float *best,
                             ray8 *out);
void scene_object_rays8_avx512(const mat4 *inv, const ray8 *r, int active, const float *best,
                               ray8 *out);
bool scene_shadow_walk8_avx2(const scene *s, const ray8 *r, int active, int *blocked,
                             int *crosses);
bool scene_shadow_walk8_avx512(const scene *s, const ray8 *r, int active, int *blocked,
                               int *crosses);
bool scene_shadow_walk8_culled_avx2(const scene *s, const ray8 *r, int active, int *blocked,
                                    int *crosses);
bool scene_shadow_walk8_culled_avx512(const scene *s, const ray8 *r, int active, int *blocked,
                                      int *crosses);

#endif
