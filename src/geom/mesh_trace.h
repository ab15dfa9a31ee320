/* mesh_trace: a ray against a mesh's BVH and its tri4 blocks (nearest hit,
 * any hit, every crossing), written once
 * and compiled once per SIMD path (accel/isa.h): mesh.c holds the SSE
 * copy, mesh_scalar.c, mesh_avx2.c and mesh_avx512.c the others (the
 * Makefile gives the last two their -m flags). mesh_intersect and
 * mesh_occluded call the copy that matches the layout the mesh was built
 * for. */
#ifndef GLINT_GEOM_MESH_TRACE_H
#define GLINT_GEOM_MESH_TRACE_H

#include "accel/traverse.h"
#include "geom/mesh.h"
#include "geom/shape.h"
#include "geom/tri4.h"

typedef struct mesh_leaf_ctx {
    const mesh *m;
    const ray *r;
    shape_hit *hit;
    int32_t best; /* the triangle of *hit; -1 before the first */
    bool ready;   /* q is worked out (at the first leaf: rays that reach
                     none, most primary rays, never need it) */
    tri4_ray q;
} mesh_leaf_ctx;

/* Field by field: q is left unset until the first leaf (an initialiser
 * would clear it for every ray, most of which never need it). */
__attribute__((always_inline)) static inline void mesh_leaf_ctx_init(mesh_leaf_ctx *c, const mesh *m,
                                                                     const ray *r, shape_hit *hit)
{
    c->m = m;
    c->r = r;
    c->hit = hit;
    c->best = -1;
    c->ready = false;
}

__attribute__((always_inline)) static inline const tri4_ray *mesh_leaf_ray(mesh_leaf_ctx *c)
{
    if (!c->ready) {
        c->q = tri4_ray_make(c->r);
        c->ready = true;
    }
    return &c->q;
}

/* A leaf's count triangles fill (count + 3) / 4 blocks from block first.
 * Of two hits at the same distance the lower triangle index is kept,
 * whichever comes first, so that the hit does not depend on the order of
 * the walk (mesh_packet.h walks in another). Each block is tested against
 * the distance reached when it began, made inclusive for such ties. */
__attribute__((always_inline)) static inline bool mesh_leaf_closest(void *ctx, uint32_t first,
                                                                    uint32_t count, float tmin,
                                                                    float *tmax)
{
    mesh_leaf_ctx *c = ctx;
    const tri4 *blk = &c->m->blocks[first];
    const tri4_ray *q = mesh_leaf_ray(c);
    bool found = false;
    for (uint32_t j = 0; j < count;) {
        float t[8], b1[8], b2[8];
        int mask, lanes = 4;
#if defined(GLINT_TRI8)
        if (count - j > 4) { /* two blocks at once */
            mask = tri8_intersect(q, blk, tmin, next_up(*tmax), t, b1, b2);
            lanes = 8;
        } else
#endif
            mask = tri4_intersect(q, blk, tmin, next_up(*tmax), t, b1, b2);
        for (; mask; mask &= mask - 1) { /* the lanes hit, lowest first */
            int k = __builtin_ctz((unsigned)mask);
            int32_t id = blk[k >> 2].id[k & 3];
            if (t[k] < *tmax || (t[k] == *tmax && id < c->best)) {
                *tmax = t[k];
                c->best = id;
                c->hit->t = t[k];
                c->hit->part = id;
                c->hit->b1 = b1[k];
                c->hit->b2 = b2[k];
                found = true;
            }
        }
        j += (uint32_t)lanes;
        blk += lanes / 4;
    }
    return found;
}

__attribute__((always_inline)) static inline bool mesh_leaf_any(void *ctx, uint32_t first,
                                                                uint32_t count, float tmin,
                                                                float *tmax)
{
    mesh_leaf_ctx *c = ctx;
    const tri4 *blk = &c->m->blocks[first];
    const tri4_ray *q = mesh_leaf_ray(c);
    uint32_t j = 0;
#if defined(GLINT_TRI8)
    for (; j + 4 < count; j += 8, blk += 2) { /* two blocks at once */
        float t[8], b1[8], b2[8];
        if (tri8_intersect(q, blk, tmin, *tmax, t, b1, b2))
            return true;
    }
#endif
    for (; j < count; j += 4, blk++) {
        float t[4], b1[4], b2[4];
        if (tri4_intersect(q, blk, tmin, *tmax, t, b1, b2))
            return true;
    }
    return false;
}

typedef struct mesh_all_ctx {
    const mesh *m;
    tri4_ray q;
    const ray *r;
    crossing *out;
    int n, max;
    bool more;
} mesh_all_ctx;

/* Collects every hit of the leaf (tmax is left alone, so every leaf the
 * line meets is visited), keeping the max nearest in order. */
__attribute__((always_inline)) static inline bool mesh_leaf_all(void *ctx, uint32_t first,
                                                           uint32_t count, float tmin, float *tmax)
{
    mesh_all_ctx *c = ctx;
    const tri4 *blk = &c->m->blocks[first];
    for (uint32_t j = 0; j < count; j += 4, blk++) {
        float t[4], b1[4], b2[4];
        int mask = tri4_intersect(&c->q, blk, tmin, *tmax, t, b1, b2);
        for (int k = 0; mask; k++, mask >>= 1) {
            if (!(mask & 1))
                continue;
            const uint32_t *tri = c->m->tri[blk->id[k]];
            vec3 p0 = c->m->pos[tri[0]];
            vec3 ng = v3_cross(v3_sub(c->m->pos[tri[1]], p0), v3_sub(c->m->pos[tri[2]], p0));
            crossing x = {{.t = t[k], .part = blk->id[k], .b1 = b1[k], .b2 = b2[k]},
                          v3_dot(ng, c->r->d) < 0.0f};
            int at = c->n < c->max ? c->n++ : c->n;
            if (at == c->max) {
                c->more = true;
                if (t[k] >= c->out[c->max - 1].h.t)
                    continue;
                at = c->max - 1;
            }
            for (; at > 0 && c->out[at - 1].h.t > t[k]; at--)
                c->out[at] = c->out[at - 1];
            c->out[at] = x;
        }
    }
    return false;
}

/* Defines mesh_intersect_<isa>, mesh_occluded_<isa> and
 * mesh_crossings_<isa> for nodes of the given width. */
#define MESH_KERNELS(isa, width)                                                               \
    bool mesh_intersect_##isa(const mesh *m, const ray *r, shape_hit *hit)                     \
    {                                                                                          \
        mesh_leaf_ctx c;                                                                       \
        mesh_leaf_ctx_init(&c, m, r, hit);                                                     \
        float tmax = r->tmax;                                                                  \
        return wide_traverse(&m->bvh, width, r->o, r->d, r->tmin, &tmax, false,                \
                             mesh_leaf_closest, &c);                                           \
    }                                                                                          \
    bool mesh_occluded_##isa(const mesh *m, const ray *r)                                      \
    {                                                                                          \
        mesh_leaf_ctx c;                                                                       \
        mesh_leaf_ctx_init(&c, m, r, NULL);                                                    \
        float tmax = r->tmax;                                                                  \
        return wide_traverse(&m->bvh, width, r->o, r->d, r->tmin, &tmax, true, mesh_leaf_any,  \
                             &c);                                                              \
    }                                                                                          \
    int mesh_crossings_##isa(const mesh *m, const ray *r, crossing *out, int max, bool *more)  \
    {                                                                                          \
        mesh_all_ctx c = {m, tri4_ray_make(r), r, out, 0, max, false};                         \
        float tmax = INFINITY;                                                                 \
        wide_traverse(&m->bvh, width, r->o, r->d, r->tmin, &tmax, false, mesh_leaf_all, &c);   \
        *more = c.more;                                                                        \
        return c.n;                                                                            \
    }

bool mesh_intersect_scalar(const mesh *m, const ray *r, shape_hit *hit);
bool mesh_occluded_scalar(const mesh *m, const ray *r);
int mesh_crossings_scalar(const mesh *m, const ray *r, crossing *out, int max, bool *more);
bool mesh_intersect_sse(const mesh *m, const ray *r, shape_hit *hit);
bool mesh_occluded_sse(const mesh *m, const ray *r);
int mesh_crossings_sse(const mesh *m, const ray *r, crossing *out, int max, bool *more);
bool mesh_intersect_avx2(const mesh *m, const ray *r, shape_hit *hit);
bool mesh_occluded_avx2(const mesh *m, const ray *r);
int mesh_crossings_avx2(const mesh *m, const ray *r, crossing *out, int max, bool *more);
bool mesh_intersect_avx512(const mesh *m, const ray *r, shape_hit *hit);
bool mesh_occluded_avx512(const mesh *m, const ray *r);
int mesh_crossings_avx512(const mesh *m, const ray *r, crossing *out, int max, bool *more);
int mesh_intersect8_avx2(const mesh *m, const ray8 *r, int active, shape_hit hit[8]);
int mesh_intersect8_avx512(const mesh *m, const ray8 *r, int active, shape_hit hit[8]);

#endif
