/* tri4: four triangles tested against one ray at once. A mesh stores the
 * corners of each BVH leaf's triangles again here, structure-of-arrays, so
 * that a leaf costs one run of contiguous loads instead of an index and
 * three vertex fetches per triangle (the layout of Embree's "triangle4v";
 * Wald et al., "Embree: A Kernel Framework for Efficient CPU Ray Tracing",
 * ACM TOG 2014).
 *
 * The test is the watertight one of watertight.h, lane by lane: the same
 * shear, the same edge functions, and the same double-precision retry when
 * an edge function is exactly zero, so a ray that hits an edge shared by
 * two triangles still hits one of them. Unused lanes have id -1 and all
 * corners at the origin, and are masked out. A scalar path does the same
 * work where SSE is missing or GLINT_NO_SIMD is defined (accel/isa.h). */
#ifndef GLINT_GEOM_TRI4_H
#define GLINT_GEOM_TRI4_H

#include <stdint.h>
#if defined(__SSE2__) && !defined(GLINT_NO_SIMD)
#define GLINT_TRI4_SSE 1
#include <emmintrin.h>
#endif
#include "geom/watertight.h"

typedef struct tri4 {
    float p[3][3][4]; /* corner, axis, lane */
    int32_t id[4];    /* the mesh's triangle index; -1: unused lane */
} __attribute__((aligned(16))) tri4;

/* The ray in the form the test wants: the axis it runs most along (kz), the
 * two others (kx, ky) and the shear constants (Woop et al., section 3). */
typedef struct tri4_ray {
#if !defined(GLINT_TRI4_SSE)
    tri_ray tr; /* the scalar test's form */
#endif
    vec3 o;
    int kx, ky, kz;
    float ox, oy, oz; /* origin along kx, ky, kz */
    float sx, sy, sz;
} tri4_ray;

/* The same shear in tri_ray_make's form (watertight.h), for the scalar test:
 * the SSE path needs it only to retry a lane in double precision. */
static inline tri_ray tri4_scalar_ray(const tri4_ray *q)
{
    tri_ray t;
    t.o = q->o;
    t.mx = v3_add(tri_axis(q->kx, 1.0f), tri_axis(q->kz, -q->sx));
    t.my = v3_add(tri_axis(q->ky, 1.0f), tri_axis(q->kz, -q->sy));
    t.mz = tri_axis(q->kz, q->sz);
    return t;
}

__attribute__((always_inline)) static inline tri4_ray tri4_ray_make(const ray *r)
{
    tri4_ray q;
    vec3 ad = v3(fabsf(r->d.x), fabsf(r->d.y), fabsf(r->d.z));
    q.kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    q.kx = (q.kz + 1) % 3;
    q.ky = (q.kx + 1) % 3;
    float dz = v3_at(r->d, q.kz);
    if (dz < 0.0f) {
        int k = q.kx;
        q.kx = q.ky;
        q.ky = k;
    }
    q.sx = v3_at(r->d, q.kx) / dz;
    q.sy = v3_at(r->d, q.ky) / dz;
    q.sz = 1.0f / dz;
    q.ox = v3_at(r->o, q.kx);
    q.oy = v3_at(r->o, q.ky);
    q.oz = v3_at(r->o, q.kz);
    q.o = r->o;
#if !defined(GLINT_TRI4_SSE)
    q.tr = tri4_scalar_ray(&q);
#endif
    return q;
}

static inline vec3 tri4_corner(const tri4 *b, int corner, int lane)
{
    return v3(b->p[corner][0][lane], b->p[corner][1][lane], b->p[corner][2][lane]);
}

/* The lanes hit with t in (tmin, tmax), as a bit mask; t, b1, b2 per lane
 * (barycentric weights of corners 1 and 2) are valid for those lanes. */
__attribute__((always_inline)) static inline int tri4_intersect(const tri4_ray *q, const tri4 *b,
                                                                float tmin, float tmax,
                                                                float t[4], float b1[4],
                                                                float b2[4])
{
#if defined(GLINT_TRI4_SSE)
    const __m128 ox = _mm_set1_ps(q->ox), oy = _mm_set1_ps(q->oy), oz = _mm_set1_ps(q->oz);
    const __m128 sx = _mm_set1_ps(q->sx), sy = _mm_set1_ps(q->sy), sz = _mm_set1_ps(q->sz);
    __m128 ex[3], ey[3], ez[3];
    for (int c = 0; c < 3; c++) {
        __m128 az = _mm_sub_ps(_mm_load_ps(b->p[c][q->kz]), oz);
        ex[c] = _mm_sub_ps(_mm_sub_ps(_mm_load_ps(b->p[c][q->kx]), ox), _mm_mul_ps(sx, az));
        ey[c] = _mm_sub_ps(_mm_sub_ps(_mm_load_ps(b->p[c][q->ky]), oy), _mm_mul_ps(sy, az));
        ez[c] = _mm_mul_ps(sz, az);
    }
    /* Edge functions: u against the edge 1-2, v against 2-0, w against 0-1. */
    __m128 u = _mm_sub_ps(_mm_mul_ps(ex[2], ey[1]), _mm_mul_ps(ey[2], ex[1]));
    __m128 v = _mm_sub_ps(_mm_mul_ps(ex[0], ey[2]), _mm_mul_ps(ey[0], ex[2]));
    __m128 w = _mm_sub_ps(_mm_mul_ps(ex[1], ey[0]), _mm_mul_ps(ey[1], ex[0]));
    const __m128 zero = _mm_setzero_ps();
    int on_edge = _mm_movemask_ps(_mm_or_ps(
        _mm_or_ps(_mm_cmpeq_ps(u, zero), _mm_cmpeq_ps(v, zero)), _mm_cmpeq_ps(w, zero)));
    __m128 neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, zero), _mm_cmplt_ps(v, zero)),
                           _mm_cmplt_ps(w, zero));
    __m128 pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, zero), _mm_cmpgt_ps(v, zero)),
                           _mm_cmpgt_ps(w, zero));
    __m128 det = _mm_add_ps(_mm_add_ps(u, v), w);
    __m128 ok = _mm_andnot_ps(_mm_and_ps(neg, pos), _mm_cmpneq_ps(det, zero));
    __m128i used = _mm_cmpgt_epi32(_mm_load_si128((const __m128i *)b->id), _mm_set1_epi32(-1));
    int mask = _mm_movemask_ps(_mm_and_ps(ok, _mm_castsi128_ps(used))) & ~on_edge;
    if (mask) {
        __m128 tt = _mm_add_ps(_mm_add_ps(_mm_mul_ps(u, ez[0]), _mm_mul_ps(v, ez[1])),
                               _mm_mul_ps(w, ez[2]));
        __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), det);
        tt = _mm_mul_ps(tt, inv);
        ok = _mm_and_ps(_mm_cmpgt_ps(tt, _mm_set1_ps(tmin)), _mm_cmplt_ps(tt, _mm_set1_ps(tmax)));
        mask &= _mm_movemask_ps(ok);
        if (mask) { /* every lane is stored; the caller reads those in the mask */
            _mm_storeu_ps(t, tt);
            _mm_storeu_ps(b1, _mm_mul_ps(v, inv));
            _mm_storeu_ps(b2, _mm_mul_ps(w, inv));
        }
    }
    if (on_edge) {
        /* Rare: settle those lanes one at a time in double precision (after
         * the stores above, which wrote every lane). */
        tri_ray tr = tri4_scalar_ray(q);
        for (int k = 0; k < 4; k++)
            if ((on_edge >> k & 1) && b->id[k] >= 0 &&
                tri_intersect(&tr, tri4_corner(b, 0, k), tri4_corner(b, 1, k),
                              tri4_corner(b, 2, k), tmin, tmax, &t[k], &b1[k], &b2[k]))
                mask |= 1 << k;
    }
    return mask;
#else
    int mask = 0;
    for (int k = 0; k < 4; k++)
        if (b->id[k] >= 0 && tri_intersect(&q->tr, tri4_corner(b, 0, k), tri4_corner(b, 1, k),
                                           tri4_corner(b, 2, k), tmin, tmax, &t[k], &b1[k],
                                           &b2[k]))
            mask |= 1 << k;
    return mask;
#endif
}

#if defined(__AVX2__) && !defined(GLINT_NO_SIMD)
#define GLINT_TRI8 1
#include <immintrin.h>

/* Two blocks side by side (b[0] and b[1], a leaf's consecutive blocks) in
 * one AVX register: lane k is lane k % 4 of block k / 4, with the same
 * operations as tri4_intersect's, so each lane gets the same answer. */
static inline __m256 tri8_load(const tri4 *b, int corner, int axis)
{
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(b[0].p[corner][axis])),
                                _mm_load_ps(b[1].p[corner][axis]), 1);
}

/* The watertight test's second half on eight lanes, tri4_intersect's
 * operations in its order, from the corners in the sheared space (ex, ey,
 * ez): returns the lanes of `used` hit with t in (tmin, tmax), with t, b1
 * and b2, which are set on every lane when any lane passes the edge test;
 * *on_edge gets the lanes of `used` where an edge function is exactly
 * zero, which the caller settles one at a time in double precision. Shared
 * by tri8_intersect (eight triangles, one ray) and mesh_packet.h (one
 * triangle, eight rays). */
__attribute__((always_inline)) static inline int tri8_solve(const __m256 ex[3], const __m256 ey[3],
                                                            const __m256 ez[3], int used,
                                                            __m256 tmin, __m256 tmax,
                                                            int *on_edge, __m256 *t, __m256 *b1,
                                                            __m256 *b2)
{
    __m256 u = _mm256_sub_ps(_mm256_mul_ps(ex[2], ey[1]), _mm256_mul_ps(ey[2], ex[1]));
    __m256 v = _mm256_sub_ps(_mm256_mul_ps(ex[0], ey[2]), _mm256_mul_ps(ey[0], ex[2]));
    __m256 w = _mm256_sub_ps(_mm256_mul_ps(ex[1], ey[0]), _mm256_mul_ps(ey[1], ex[0]));
    const __m256 zero = _mm256_setzero_ps();
    int edge = _mm256_movemask_ps(_mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_EQ_OQ), _mm256_cmp_ps(v, zero, _CMP_EQ_OQ)),
        _mm256_cmp_ps(w, zero, _CMP_EQ_OQ)));
    __m256 neg = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_LT_OQ), _mm256_cmp_ps(v, zero, _CMP_LT_OQ)),
        _mm256_cmp_ps(w, zero, _CMP_LT_OQ));
    __m256 pos = _mm256_or_ps(
        _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_GT_OQ), _mm256_cmp_ps(v, zero, _CMP_GT_OQ)),
        _mm256_cmp_ps(w, zero, _CMP_GT_OQ));
    __m256 det = _mm256_add_ps(_mm256_add_ps(u, v), w);
    __m256 ok = _mm256_andnot_ps(_mm256_and_ps(neg, pos), _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ));
    *on_edge = edge & used;
    int mask = _mm256_movemask_ps(ok) & used & ~edge;
    if (mask) {
        __m256 tt = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(u, ez[0]), _mm256_mul_ps(v, ez[1])),
                                  _mm256_mul_ps(w, ez[2]));
        __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
        tt = _mm256_mul_ps(tt, inv);
        ok = _mm256_and_ps(_mm256_cmp_ps(tt, tmin, _CMP_GT_OQ), _mm256_cmp_ps(tt, tmax, _CMP_LT_OQ));
        mask &= _mm256_movemask_ps(ok);
        *t = tt;
        *b1 = _mm256_mul_ps(v, inv);
        *b2 = _mm256_mul_ps(w, inv);
    }
    return mask;
}

__attribute__((always_inline)) static inline int tri8_intersect(const tri4_ray *q, const tri4 *b,
                                                                float tmin, float tmax,
                                                                float t[8], float b1[8],
                                                                float b2[8])
{
    const __m256 ox = _mm256_set1_ps(q->ox), oy = _mm256_set1_ps(q->oy), oz = _mm256_set1_ps(q->oz);
    const __m256 sx = _mm256_set1_ps(q->sx), sy = _mm256_set1_ps(q->sy), sz = _mm256_set1_ps(q->sz);
    __m256 ex[3], ey[3], ez[3];
    for (int c = 0; c < 3; c++) {
        __m256 az = _mm256_sub_ps(tri8_load(b, c, q->kz), oz);
        ex[c] = _mm256_sub_ps(_mm256_sub_ps(tri8_load(b, c, q->kx), ox), _mm256_mul_ps(sx, az));
        ey[c] = _mm256_sub_ps(_mm256_sub_ps(tri8_load(b, c, q->ky), oy), _mm256_mul_ps(sy, az));
        ez[c] = _mm256_mul_ps(sz, az);
    }
    __m256i ids = _mm256_insertf128_si256(
        _mm256_castsi128_si256(_mm_load_si128((const __m128i *)b[0].id)),
        _mm_load_si128((const __m128i *)b[1].id), 1);
    int used = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(ids, _mm256_set1_epi32(-1))));
    int on_edge;
    __m256 tt, u1, u2;
    int mask = tri8_solve(ex, ey, ez, used, _mm256_set1_ps(tmin), _mm256_set1_ps(tmax), &on_edge,
                          &tt, &u1, &u2);
    if (mask) {
        _mm256_storeu_ps(t, tt);
        _mm256_storeu_ps(b1, u1);
        _mm256_storeu_ps(b2, u2);
    }
    if (on_edge) { /* rare: those lanes one at a time, in double precision */
        tri_ray tr = tri4_scalar_ray(q);
        for (int k = 0; k < 8; k++)
            if ((on_edge >> k & 1) &&
                tri_intersect(&tr, tri4_corner(&b[k >> 2], 0, k & 3), tri4_corner(&b[k >> 2], 1, k & 3),
                              tri4_corner(&b[k >> 2], 2, k & 3), tmin, tmax, &t[k], &b1[k], &b2[k]))
                mask |= 1 << k;
    }
    return mask;
}
#endif

#endif
