/* scene_packet8: eight rays at once through the scene (scene_packet.c,
 * scene_cone.c): how a packet keeps its nearest hits, and the packet
 * walks and object tests written once and compiled once per eight-wide
 * path (SCENE_PACKET_KERNELS, in scene_avx2.c and scene_avx512.c). */
#ifndef GLINT_SCENE_SCENE_PACKET8_H
#define GLINT_SCENE_SCENE_PACKET8_H

#include "scene_trace.h"
#if defined(GLINT_TRAVERSE_AVX2)
#include "geom/mesh_packet.h"
#include "geom/shape8.h"
#endif

/* Which of object i's hits, on the rays of `any`, are kept: those of
 * `nearer`, which beat the best so far, and of the others, which tie with
 * it, those where i is the lower index. */
static inline int kept_hits8(int i, int any, int nearer, const scene_hit hit[8])
{
    int kept = nearer;
    for (int m = any & ~nearer; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        kept |= (i < hit[k].object) << k;
    }
    return kept;
}

/* keep8 for shape8_hit's hits h of the rays of `any`, of which those of
 * `nearer` beat best[k] and the others tie with it. */
static inline int keep_hits8(int i, int any, int nearer, const shape_hits8 *h, float best[8],
                             scene_hit hit[8])
{
    int kept = kept_hits8(i, any, nearer, hit);
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
    int kept = kept_hits8(i, any, nearer, hit);
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

/* The rays of `rays` that may meet box b before their limits (lim, a
 * walk's tmax), by a walk's test of a node's box (packet_child). */
__attribute__((always_inline)) static inline int scene_packet_box(const packet8 *p, aabb b,
                                                                  __m256 lim, int rays)
{
    const float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    const bool neg[3] = {p->nx, p->ny, p->nz};
    const __m256 o[3] = {p->ox, p->oy, p->oz}, inv[3] = {p->ix, p->iy, p->iz};
    __m256 t0[3], t1[3];
    for (int a = 0; a < 3; a++) {
        t0[a] = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(neg[a] ? hi[a] : lo[a]), o[a]), inv[a]);
        t1[a] = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(neg[a] ? lo[a] : hi[a]), o[a]), inv[a]);
    }
    /* in packet_child's order, so that a NaN (a direction's zero component
     * on a face's plane: 0 times infinity) drops out as it does there */
    __m256 vn = _mm256_max_ps(_mm256_max_ps(t0[0], t0[1]), _mm256_max_ps(t0[2], p->tmin));
    __m256 vf = _mm256_min_ps(_mm256_min_ps(t1[0], t1[1]),
                              _mm256_min_ps(t1[2], _mm256_set1_ps(INFINITY)));
    __m256 reach = _mm256_mul_ps(lim, _mm256_set1_ps(WIDE_TIE_SCALE));
    vf = _mm256_min_ps(_mm256_mul_ps(vf, _mm256_set1_ps(WIDE_FAR_SCALE)), reach);
    return rays & _mm256_movemask_ps(_mm256_cmp_ps(vn, vf, _CMP_LE_OQ));
}

/* Whether object o takes the general way (turned, moving, or of a kind
 * shape8_hit does not test), which a walk's box test spares most rays. */
static inline bool scene_packet_costly(const object *o)
{
    return !(o->xform < 0 && !o->moving && shape_tests_eight(o->shape.kind));
}

/* scene_intersect8_among (scene_packet.c): the rays of active against the
 * unbounded objects and those of list; a costly object only against the
 * rays that may meet its box, as in a walk's leaf. */
__attribute__((always_inline)) static inline int scene_among8(const scene *s, const ray8 *r,
                                                              int active, const int32_t *list,
                                                              int n, scene_hit hit[8])
{
    float best[8];
    _mm256_storeu_ps(best, _mm256_loadu_ps(r->tmax));
    for (int k = 0; k < 8; k++)
        hit[k].object = -1;
    scene_packet_ctx c = {s, r, best, hit, 0};
    for (int i = 0; i < s->nunbounded; i++)
        scene_packet_one(&c, s->unbounded[i], active);
    int i = 0; /* the packet's inverse directions made at the first costly object */
    while (i < n && !scene_packet_costly(&s->objects[list[i]]))
        scene_packet_one(&c, list[i++], active);
    packet8 p;
    bool boxed = i < n && packet_make(&p, r, active);
    for (; i < n; i++) {
        int rays = active;
        if (boxed && scene_packet_costly(&s->objects[list[i]]))
            rays = scene_packet_box(&p, s->bounds[list[i]], _mm256_loadu_ps(best), active);
        if (rays)
            scene_packet_one(&c, list[i], rays);
    }
    return c.found;
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
    /* best was copied 16 bytes at a time by code without AVX (packet_begin):
     * read back as it was written, then stored whole for the leaves' loads */
    __m256 tmax = _mm256_loadu2_m128(best + 4, best);
    _mm256_storeu_ps(best, tmax);
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

/* scene_shadow8_among (scene_packet.c): the shadow rays of active against
 * the unbounded objects and those of list, a costly one only against the
 * rays that may meet its box. */
__attribute__((always_inline)) static inline void scene_shadow_among8(const scene *s,
                                                                      const ray8 *r, int active,
                                                                      const int32_t *list, int n,
                                                                      int *blocked, int *crosses)
{
    for (int i = 0; i < s->nunbounded; i++)
        scene_shadow8_one(s, s->unbounded[i], r, active & ~*blocked, blocked, crosses);
    int i = 0; /* as in scene_among8 */
    for (; i < n && !scene_packet_costly(&s->objects[list[i]]); i++)
        if (active & ~*blocked)
            scene_shadow8_one(s, list[i], r, active & ~*blocked, blocked, crosses);
    packet8 p;
    bool boxed = i < n && packet_make(&p, r, active);
    for (; i < n; i++) {
        int rays = active & ~*blocked;
        if (rays && boxed && scene_packet_costly(&s->objects[list[i]]))
            rays = scene_packet_box(&p, s->bounds[list[i]], _mm256_loadu_ps(r->tmax), rays);
        if (rays)
            scene_shadow8_one(s, list[i], r, rays, blocked, crosses);
    }
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
        return scene_among8(s, r, active, list, n, hit);                                       \
    }                                                                                          \
    __attribute__((flatten))                                                                   \
    void scene_shadow_among8_##isa(const scene *s, const ray8 *r, int active,                  \
                                   const int32_t *list, int n, int *blocked, int *crosses)     \
    {                                                                                          \
        scene_shadow_among8(s, r, active, list, n, blocked, crosses);                          \
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
