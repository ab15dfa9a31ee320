/* v4: four floats for the BVH builders (accel/split.c, bvh.c,
 * wide_build.c): an SSE register, or plain floats without SSE; the same
 * values either way (lane-wise IEEE operations). */
#ifndef GLINT_ACCEL_V4_H
#define GLINT_ACCEL_V4_H

#include <string.h>
#include "core/vec3.h"
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#if defined(__SSE2__)
typedef __m128 v4;
static inline v4 v4_set(float x, float y, float z, float w) { return _mm_setr_ps(x, y, z, w); }
static inline v4 v4_splat(float x) { return _mm_set1_ps(x); }
static inline v4 v4_load(const float *p) { return _mm_load_ps(p); }
static inline void v4_store(float *p, v4 a) { _mm_store_ps(p, a); }
/* min and max return b where either is NaN, as minf and maxf do. */
static inline v4 v4_min(v4 a, v4 b) { return _mm_min_ps(a, b); }
static inline v4 v4_max(v4 a, v4 b) { return _mm_max_ps(a, b); }
static inline v4 v4_add(v4 a, v4 b) { return _mm_add_ps(a, b); }
static inline v4 v4_sub(v4 a, v4 b) { return _mm_sub_ps(a, b); }
static inline v4 v4_mul(v4 a, v4 b) { return _mm_mul_ps(a, b); }
static inline v4 v4_div(v4 a, v4 b) { return _mm_div_ps(a, b); }
static inline v4 v4_neg(v4 a) { return _mm_xor_ps(a, _mm_set1_ps(-0.0f)); }
static inline float v4_x(v4 a) { return _mm_cvtss_f32(a); }
static inline float v4_y(v4 a) { return _mm_cvtss_f32(_mm_shuffle_ps(a, a, 1)); }
static inline float v4_z(v4 a) { return _mm_cvtss_f32(_mm_shuffle_ps(a, a, 2)); }
static inline float v4_w(v4 a) { return _mm_cvtss_f32(_mm_shuffle_ps(a, a, 3)); }
/* Bit k set where a[k] < b[k]. */
static inline int v4_lt(v4 a, v4 b) { return _mm_movemask_ps(_mm_cmplt_ps(a, b)); }
static inline int v4_eq(v4 a, v4 b) { return _mm_movemask_ps(_mm_cmpeq_ps(a, b)); }
/* a with its NaN lanes replaced by x */
static inline v4 v4_nan_to(v4 a, float x)
{
    __m128 nan = _mm_cmpunord_ps(a, a);
    return _mm_or_ps(_mm_andnot_ps(nan, a), _mm_and_ps(nan, _mm_set1_ps(x)));
}
#define v4_shuffle(a, i, j, k, l) _mm_shuffle_ps((a), (a), _MM_SHUFFLE(l, k, j, i))
/* The fourth lanes of a, b, c and d. */
static inline v4 v4_lane3(v4 a, v4 b, v4 c, v4 d)
{
    return _mm_movehl_ps(_mm_unpackhi_ps(c, d), _mm_unpackhi_ps(a, b));
}
/* x where s > 0, else y */
static inline v4 v4_select_gt0(v4 s, v4 x, float y)
{
    __m128 m = _mm_cmpgt_ps(s, _mm_setzero_ps());
    return _mm_or_ps(_mm_and_ps(m, x), _mm_andnot_ps(m, _mm_set1_ps(y)));
}
static inline void v4_transpose(v4 *a, v4 *b, v4 *c, v4 *d) { _MM_TRANSPOSE4_PS(*a, *b, *c, *d); }
/* The lanes' values truncated to integers, for the first three lanes. */
static inline void v4_trunc3(v4 a, int k[3])
{
    __m128i i = _mm_cvttps_epi32(a);
    k[0] = _mm_cvtsi128_si32(i);
    k[1] = _mm_cvtsi128_si32(_mm_shuffle_epi32(i, _MM_SHUFFLE(1, 1, 1, 1)));
    k[2] = _mm_cvtsi128_si32(_mm_shuffle_epi32(i, _MM_SHUFFLE(2, 2, 2, 2)));
}
#else
typedef struct v4 {
    float f[4];
} v4;
static inline v4 v4_set(float x, float y, float z, float w) { return (v4){{x, y, z, w}}; }
static inline v4 v4_splat(float x) { return (v4){{x, x, x, x}}; }
static inline v4 v4_load(const float *p) { return (v4){{p[0], p[1], p[2], p[3]}}; }
static inline void v4_store(float *p, v4 a) { memcpy(p, a.f, sizeof a.f); }
#define V4_LANES(expr)                                                                             \
    v4 r;                                                                                          \
    for (int i = 0; i < 4; i++)                                                                    \
        r.f[i] = expr;                                                                             \
    return r
static inline v4 v4_min(v4 a, v4 b) { V4_LANES(minf(a.f[i], b.f[i])); }
static inline v4 v4_max(v4 a, v4 b) { V4_LANES(maxf(a.f[i], b.f[i])); }
static inline v4 v4_add(v4 a, v4 b) { V4_LANES(a.f[i] + b.f[i]); }
static inline v4 v4_sub(v4 a, v4 b) { V4_LANES(a.f[i] - b.f[i]); }
static inline v4 v4_mul(v4 a, v4 b) { V4_LANES(a.f[i] * b.f[i]); }
static inline v4 v4_div(v4 a, v4 b) { V4_LANES(a.f[i] / b.f[i]); }
static inline v4 v4_neg(v4 a) { V4_LANES(-a.f[i]); }
static inline float v4_x(v4 a) { return a.f[0]; }
static inline float v4_y(v4 a) { return a.f[1]; }
static inline float v4_z(v4 a) { return a.f[2]; }
static inline float v4_w(v4 a) { return a.f[3]; }
static inline int v4_lt(v4 a, v4 b)
{
    int m = 0;
    for (int i = 0; i < 4; i++)
        m |= (a.f[i] < b.f[i]) << i;
    return m;
}
static inline void v4_trunc3(v4 a, int k[3])
{
    for (int i = 0; i < 3; i++)
        k[i] = (int)a.f[i];
}
static inline int v4_eq(v4 a, v4 b)
{
    int m = 0;
    for (int i = 0; i < 4; i++)
        m |= (a.f[i] == b.f[i]) << i;
    return m;
}
static inline v4 v4_nan_to(v4 a, float x) { V4_LANES(a.f[i] != a.f[i] ? x : a.f[i]); }
static inline v4 v4_lane3(v4 a, v4 b, v4 c, v4 d) { return (v4){{a.f[3], b.f[3], c.f[3], d.f[3]}}; }
static inline v4 v4_select_gt0(v4 s, v4 x, float y) { V4_LANES(s.f[i] > 0.0f ? x.f[i] : y); }
static inline v4 v4_shuffle_(v4 a, int i, int j, int k, int l) { return (v4){{a.f[i], a.f[j], a.f[k], a.f[l]}}; }
#define v4_shuffle(a, i, j, k, l) v4_shuffle_((a), (i), (j), (k), (l))
static inline void v4_transpose(v4 *a, v4 *b, v4 *c, v4 *d)
{
    v4 *r[4] = {a, b, c, d}, t[4] = {*a, *b, *c, *d};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r[i]->f[j] = t[j].f[i];
}
#endif

static inline float v4_at(v4 a, int i)
{
    return i == 0 ? v4_x(a) : i == 1 ? v4_y(a) : v4_z(a);
}

#endif
