/* simd8: what the eight-lane kernels of trace/ (light8.h, bounce8.h)
 * share: reading a field of eight records as one register, and v3_dot
 * lane by lane. For translation units compiled with AVX2. */
#ifndef GLINT_TRACE_SIMD8_H
#define GLINT_TRACE_SIMD8_H

#include <immintrin.h>
#include <stddef.h>
#include <string.h>
#include "core/ray.h"
#include "geom/mesh_packet.h" /* packet_lanes */
#include "trace/shading.h"

/* The float at f. */
__attribute__((always_inline)) static inline float simd8_float(const char *f)
{
    float v;
    memcpy(&v, f, sizeof v);
    return v;
}

/* The float at byte off of each of the eight records at b[k] (pointers
 * just stored one by one), by eight loads. Each pointer passes through an
 * empty asm so that the compiler does not load the eight of them as one
 * vector to add off, a load that would wait for those stores to reach the
 * cache. */
__attribute__((always_inline)) static inline __m256 simd8_at(const void *const b[8], size_t off)
{
    const char *f[8];
    for (int k = 0; k < 8; k++) {
        f[k] = b[k];
        __asm__("" : "+r"(f[k]));
    }
    return _mm256_setr_ps(simd8_float(f[0] + off), simd8_float(f[1] + off),
                          simd8_float(f[2] + off), simd8_float(f[3] + off),
                          simd8_float(f[4] + off), simd8_float(f[5] + off),
                          simd8_float(f[6] + off), simd8_float(f[7] + off));
}

/* The float at byte `off` of each of the eight records of `size` bytes
 * from base, by eight loads: faster here than a gather instruction, and
 * unlike one wide load it does not wait for fields just stored one by one
 * to reach the cache. */
__attribute__((always_inline)) static inline __m256 simd8_field(const void *base, size_t size,
                                                                size_t off)
{
    const char *f = (const char *)base + off;
    return _mm256_setr_ps(simd8_float(f), simd8_float(f + size), simd8_float(f + 2 * size),
                          simd8_float(f + 3 * size), simd8_float(f + 4 * size),
                          simd8_float(f + 5 * size), simd8_float(f + 6 * size),
                          simd8_float(f + 7 * size));
}

/* The vec3 at byte `off` of each record, as three registers. */
__attribute__((always_inline)) static inline void simd8_vec3(const void *base, size_t size,
                                                              size_t off, __m256 v[3])
{
    v[0] = simd8_field(base, size, off);
    v[1] = simd8_field(base, size, off + sizeof(float));
    v[2] = simd8_field(base, size, off + 2 * sizeof(float));
}

/* A field of eight lanes: one load, or eight (simd8_field) where some
 * lane was just stored on its own. */
__attribute__((always_inline)) static inline __m256 simd8_lanes(const float f[8], bool lanewise)
{
    return lanewise ? simd8_field(f, sizeof(float), 0) : _mm256_loadu_ps(f);
}

/* The materials of a packet's lanes (shading.h: shade8), an idle lane
 * (not in lanes, which is not empty) repeating the first one's; all of
 * them sp->same when the lanes share one. */
__attribute__((always_inline)) static inline void simd8_materials(const shade8 *sp, int lanes,
                                                                  const void *m[8])
{
    if (sp->same) {
        for (int k = 0; k < 8; k++)
            m[k] = sp->same;
        return;
    }
    for (int k = 0, first = __builtin_ctz((unsigned)lanes); k < 8; k++)
        m[k] = sp->m[lanes >> k & 1 ? k : first];
}

/* The float at byte off of each lane's material m[k] (simd8_materials):
 * one broadcast where the lanes share one. */
__attribute__((always_inline)) static inline __m256 simd8_mfield(const shade8 *sp,
                                                                 const void *const m[8],
                                                                 size_t off)
{
    if (sp->same)
        return _mm256_broadcast_ss((const float *)(const void *)((const char *)sp->same + off));
    return simd8_at(m, off);
}

/* ray8_fill (core/ray.h) of one field, in a register: the lanes not in
 * active (not 0) take the first active lane's value. Stored whole
 * afterwards, the field is loaded whole by the walks without waiting for
 * lanes stored one by one. */
__attribute__((always_inline)) static inline __m256 simd8_fill(__m256 v, int active)
{
    __m256i first = _mm256_set1_epi32(__builtin_ctz((unsigned)active));
    return _mm256_blendv_ps(_mm256_permutevar8x32_ps(v, first), v, packet_lanes(active));
}

/* The fields of a packet of rays (o, d, tmin, tmax, time) stored whole,
 * the lanes not in active filled (simd8_fill). */
__attribute__((always_inline)) static inline void simd8_store_rays(ray8 *p, int active,
                                                                   const __m256 o[3],
                                                                   const __m256 d[3], __m256 tmin,
                                                                   __m256 tmax, __m256 time)
{
    _mm256_storeu_ps(p->ox, simd8_fill(o[0], active));
    _mm256_storeu_ps(p->oy, simd8_fill(o[1], active));
    _mm256_storeu_ps(p->oz, simd8_fill(o[2], active));
    _mm256_storeu_ps(p->dx, simd8_fill(d[0], active));
    _mm256_storeu_ps(p->dy, simd8_fill(d[1], active));
    _mm256_storeu_ps(p->dz, simd8_fill(d[2], active));
    _mm256_storeu_ps(p->tmin, simd8_fill(tmin, active));
    _mm256_storeu_ps(p->tmax, simd8_fill(tmax, active));
    _mm256_storeu_ps(p->time, simd8_fill(time, active));
}

/* v3_dot's (a.x * b.x + a.y * b.y) + a.z * b.z, lane by lane. */
__attribute__((always_inline)) static inline __m256 simd8_dot(const __m256 a[3],
                                                              const __m256 b[3])
{
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(a[0], b[0]), _mm256_mul_ps(a[1], b[1])),
                         _mm256_mul_ps(a[2], b[2]));
}

/* The lanes where all three components of v are zero (v3_is_zero), as
 * all-ones lanes. */
__attribute__((always_inline)) static inline __m256 simd8_is_zero(const __m256 v[3])
{
    const __m256 zero = _mm256_setzero_ps();
    return _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(v[0], zero, _CMP_EQ_OQ),
                                       _mm256_cmp_ps(v[1], zero, _CMP_EQ_OQ)),
                         _mm256_cmp_ps(v[2], zero, _CMP_EQ_OQ));
}

/* ray_offset (core/ray.h) lane by lane: the origin for rays leaving
 * points p (geometric normals ng) in directions d. */
__attribute__((always_inline)) static inline void simd8_offset(const __m256 p[3],
                                                                const __m256 ng[3],
                                                                const __m256 d[3], __m256 o[3])
{
    const __m256 abs = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    __m256 m = _mm256_max_ps(_mm256_and_ps(p[0], abs),
                             _mm256_max_ps(_mm256_and_ps(p[1], abs), _mm256_and_ps(p[2], abs)));
    __m256 e = _mm256_mul_ps(_mm256_set1_ps(RAY_EPS_REL), _mm256_add_ps(_mm256_set1_ps(1.0f), m));
    __m256 out = _mm256_cmp_ps(simd8_dot(ng, d), _mm256_setzero_ps(), _CMP_GE_OQ);
    __m256 s = _mm256_blendv_ps(_mm256_xor_ps(e, _mm256_set1_ps(-0.0f)), e, out);
    for (int c = 0; c < 3; c++)
        o[c] = _mm256_add_ps(p[c], _mm256_mul_ps(ng[c], s));
}

#endif
