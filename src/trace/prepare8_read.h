/* prepare8_read: how the packet kernels of prepare8.h read what a
 * packet's lanes hit: each record (object, transform, material) once, as
 * a broadcast blended in by its lanes, rather than eight loads a field.
 * For translation units compiled with AVX2 (whitted_<isa>.c). */
#ifndef GLINT_TRACE_PREPARE8_READ_H
#define GLINT_TRACE_PREPARE8_READ_H

#include "geom/mesh_packet.h" /* packet_lanes */
#include "scene/scene.h"
#include "trace/simd8.h"

/* v3_norm lane by lane: a * (1 / |a|) where |a| > 0, else a. */
__attribute__((always_inline)) static inline void prepare8_norm(const __m256 a[3], __m256 out[3])
{
    __m256 l = _mm256_sqrt_ps(simd8_dot(a, a));
    __m256 pos = _mm256_cmp_ps(l, _mm256_setzero_ps(), _CMP_GT_OQ);
    __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), l);
    for (int c = 0; c < 3; c++)
        out[c] = _mm256_blendv_ps(a[c], _mm256_mul_ps(a[c], inv), pos);
}

/* The lanes of `lanes` grouped by the record each reads (at[k], a
 * pointer): each record once, with its lanes (bits, and as a register's
 * lanes). */
typedef struct prepare8_groups {
    int n, bits[8];
    const char *at[8];
    __m256 sel[8];
} prepare8_groups;

/* One group: every lane of `lanes` reads at. */
static inline void prepare8_one(const char *at, int lanes, prepare8_groups *g)
{
    g->n = 1, g->at[0] = at, g->bits[0] = lanes;
}

__attribute__((always_inline)) static inline void
prepare8_group(const char *const at[8], int lanes, prepare8_groups *g)
{
    g->n = 0;
    for (int m = lanes; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m), i = 0;
        while (i < g->n && g->at[i] != at[k])
            i++;
        if (i == g->n)
            g->at[i] = at[k], g->bits[i] = 0, g->n++;
        g->bits[i] |= 1 << k;
    }
    for (int i = 1; i < g->n; i++)
        g->sel[i] = packet_lanes(g->bits[i]);
}

/* The float at byte off of each lane's record (of base[i] + off for group
 * i): one broadcast for each, blended in by its lanes (the lanes of no
 * group take the first one's). */
__attribute__((always_inline)) static inline __m256
prepare8_read(const prepare8_groups *g, const char *const base[8], size_t off)
{
    __m256 v = _mm256_broadcast_ss((const float *)(const void *)(base[0] + off));
    for (int i = 1; i < g->n; i++)
        v = _mm256_blendv_ps(v, _mm256_broadcast_ss((const float *)(const void *)(base[i] + off)),
                             g->sel[i]);
    return v;
}

/* The objects a kind of surface reads for the lanes of `lanes`, each
 * once: its shape (at byte off of the object) and transform. */
typedef struct prepare8_objs {
    prepare8_groups g;
    const char *shape[8], *xf[8];
} prepare8_objs;

__attribute__((always_inline)) static inline void
prepare8_objects(const scene *s, const scene_hit *hit, int lanes, size_t off, prepare8_objs *o)
{
    int one = hit[__builtin_ctz((unsigned)lanes)].object, other = 0;
    for (int m = lanes & (lanes - 1); m; m &= m - 1) /* the commonest case: one object */
        other |= hit[__builtin_ctz((unsigned)m)].object ^ one;
    if (!other) {
        prepare8_one((const char *)&s->objects[one], lanes, &o->g);
    } else {
        const char *ob[8];
        for (int m = lanes; m; m &= m - 1) {
            int k = __builtin_ctz((unsigned)m);
            ob[k] = (const char *)&s->objects[hit[k].object];
        }
        prepare8_group(ob, lanes, &o->g);
    }
    for (int i = 0; i < o->g.n; i++) {
        const object *x = (const object *)(const void *)o->g.at[i];
        o->shape[i] = o->g.at[i] + off;
        o->xf[i] = x->xform >= 0 ? (const char *)&s->xforms[x->xform] : NULL;
    }
}

__attribute__((always_inline)) static inline __m256 prepare8_field(const prepare8_objs *o, bool xf,
                                                                   size_t off)
{
    return prepare8_read(&o->g, xf ? o->xf : o->shape, off);
}

/* b into c for the lanes of `lanes`, blended in whatever lanes they are:
 * assigned whole where they were all the lanes, c and b were copied
 * through the stack in wider moves than they were stored in, which
 * waited for those stores. */
__attribute__((always_inline)) static inline void prepare8_put(int lanes, const __m256 b[3],
                                                               __m256 c[3])
{
    __m256 m = packet_lanes(lanes);
    for (int i = 0; i < 3; i++)
        c[i] = _mm256_blendv_ps(c[i], b[i], m);
}

/* The top three rows of the matrix at byte off of each lane's transform. */
__attribute__((always_inline)) static inline void
prepare8_matrix(const prepare8_objs *o, size_t off, __m256 a[3][4])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++)
            a[r][c] = prepare8_field(o, true, off + (size_t)(r * 4 + c) * sizeof(float));
}

/* Row r of a times (x, y, z, w), as mat4_point (w) or mat4_vector (no w)
 * sum it. */
__attribute__((always_inline)) static inline __m256 prepare8_row(__m256 a[3][4], int r,
                                                                 const __m256 v[3], bool w)
{
    __m256 s = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(a[r][0], v[0]), _mm256_mul_ps(a[r][1], v[1])),
        _mm256_mul_ps(a[r][2], v[2]));
    return w ? _mm256_add_ps(s, a[r][3]) : s;
}

#endif
