/* light8: a point light's one sample seen from the shading points of eight
 * lanes at once, with their shadow rays: lane by lane the floats that
 * light_sample, lit and shadow_ray (lighting.c) work out, in the same
 * order. For translation units compiled with AVX2 (lighting_<isa>.c). */
#ifndef GLINT_TRACE_LIGHT8_H
#define GLINT_TRACE_LIGHT8_H

#include "geom/mesh_packet.h" /* packet_lanes */
#include "trace/light8_api.h"
#include "trace/simd8.h"

/* highlight (lighting.c) for the lanes of need, whose points see the
 * light in unit directions u at shading normals n: the material's
 * specular times max(0, r.v)^shininess, r the reflection of -u about n
 * and v = -d, with a whole shininess raised by repeated squaring in
 * material_highlight's steps (the bits of n from the lowest, each
 * squaring after its product) and the same +0 for results below 2^-152;
 * into out->hl, the lanes done into out->highlit. */
__attribute__((always_inline)) static inline void light8_highlight(const shade_point *sp, int need,
                                                                   const __m256 u[3],
                                                                   const __m256 n[3],
                                                                   light8_seen *out)
{
    const __m256 zero = _mm256_setzero_ps(), sign = _mm256_set1_ps(-0.0f);
    if (!need) {
        out->highlit = 0;
        return;
    }
    /* the materials' fields lane by lane into the registers (an array of
     * them stored lane by lane and loaded at once would stall the load);
     * an idle lane repeats the first lane's */
    const material *m[8];
    for (int k = 0, first = __builtin_ctz((unsigned)need); k < 8; k++)
        m[k] = need >> k & 1 ? sp[k].m : sp[first].m;
    __m256 sv = _mm256_setr_ps(m[0]->specular, m[1]->specular, m[2]->specular, m[3]->specular,
                               m[4]->specular, m[5]->specular, m[6]->specular, m[7]->specular);
    __m256 nv = _mm256_setr_ps(m[0]->shininess, m[1]->shininess, m[2]->shininess,
                               m[3]->shininess, m[4]->shininess, m[5]->shininess,
                               m[6]->shininess, m[7]->shininess);
    __m256 nu[3], r[3], v[3];
    for (int c = 0; c < 3; c++)
        nu[c] = _mm256_xor_ps(u[c], sign);
    __m256 s = _mm256_mul_ps(_mm256_set1_ps(-2.0f), simd8_dot(nu, n)); /* v3_reflect */
    for (int c = 0; c < 3; c++)
        r[c] = _mm256_add_ps(nu[c], _mm256_mul_ps(n[c], s));
    simd8_vec3(sp, sizeof *sp, offsetof(shade_point, d), v);
    __m256 rv = _mm256_xor_ps(simd8_dot(r, v), sign);
    __m256i bits = _mm256_castps_si256(rv);
    __m256 e = _mm256_cvtepi32_ps(_mm256_sub_epi32(
        _mm256_and_si256(_mm256_srli_epi32(bits, 23), _mm256_set1_epi32(0xff)),
        _mm256_set1_epi32(126)));
    __m256 lit = _mm256_and_ps(_mm256_cmp_ps(sv, zero, _CMP_GT_OQ),
                               _mm256_cmp_ps(rv, zero, _CMP_GT_OQ));
    __m256 faint = _mm256_cmp_ps(_mm256_mul_ps(e, nv), _mm256_set1_ps(-152.0f), _CMP_LE_OQ);
    __m256i k = _mm256_cvttps_epi32(nv);
    __m256 whole = _mm256_and_ps(
        _mm256_and_ps(_mm256_cmp_ps(nv, _mm256_set1_ps(1.0f), _CMP_GE_OQ),
                      _mm256_cmp_ps(nv, _mm256_set1_ps(65536.0f), _CMP_LE_OQ)),
        _mm256_cmp_ps(nv, _mm256_cvtepi32_ps(k), _CMP_EQ_OQ));
    /* only the lanes of need: the others' shading points were never set */
    __m256 raise =
        _mm256_and_ps(packet_lanes(need), _mm256_andnot_ps(faint, _mm256_and_ps(lit, whole)));
    k = _mm256_and_si256(k, _mm256_castps_si256(raise));
    __m256 p = _mm256_set1_ps(1.0f), b = rv;
    const __m256i one = _mm256_set1_epi32(1);
    while (_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(k, _mm256_setzero_si256())))) {
        __m256 odd = _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(k, one), one));
        p = _mm256_blendv_ps(p, _mm256_mul_ps(p, b), odd);
        k = _mm256_srli_epi32(k, 1);
        b = _mm256_mul_ps(b, b);
    }
    _mm256_storeu_ps(out->hl, _mm256_and_ps(raise, _mm256_mul_ps(sv, p)));
    /* done: raised, or 0 (unlit or too faint); left: a shininess powf takes */
    __m256 for_powf = _mm256_andnot_ps(faint, _mm256_andnot_ps(whole, lit));
    out->highlit = need & ~_mm256_movemask_ps(for_powf);
}

/* light8_point (light8_api.h). */
__attribute__((always_inline)) static inline int light8_point(const light *l,
                                                              const shade_point *sp, int lanes,
                                                              const float time[8], ray8 *p,
                                                              light8_seen *out)
{
    const struct point_light *pl = &l->point;
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const size_t size = sizeof *sp;
    __m256 at[3], d[3], u[3], n[3], ng[3], o[3];
    simd8_vec3(sp, size, offsetof(shade_point, p), at);
    const __m256 pos[3] = {_mm256_set1_ps(pl->position.x), _mm256_set1_ps(pl->position.y),
                           _mm256_set1_ps(pl->position.z)};
    /* light_toward */
    for (int c = 0; c < 3; c++)
        d[c] = _mm256_sub_ps(pos[c], at[c]);
    __m256 dist = _mm256_sqrt_ps(simd8_dot(d, d));
    if (_mm256_movemask_ps(_mm256_cmp_ps(dist, _mm256_set1_ps(INFINITY), _CMP_EQ_OQ)) & lanes)
        return -1; /* a shadow ray without end: lighting.c's own way */
    __m256 inv = _mm256_and_ps(_mm256_cmp_ps(dist, zero, _CMP_GT_OQ), _mm256_div_ps(one, dist));
    for (int c = 0; c < 3; c++)
        u[c] = _mm256_mul_ps(d[c], inv);
    __m256 color[3] = {_mm256_set1_ps(l->color.x), _mm256_set1_ps(l->color.y),
                       _mm256_set1_ps(l->color.z)};
    vec3 att = pl->attenuation;
    if (!(att.x == 1.0f && att.y == 0.0f && att.z == 0.0f)) { /* light_attenuation */
        __m256 lq = _mm256_add_ps(_mm256_set1_ps(att.y), _mm256_mul_ps(dist, _mm256_set1_ps(att.z)));
        __m256 k = _mm256_add_ps(_mm256_set1_ps(att.x), _mm256_mul_ps(dist, lq));
        __m256 f = _mm256_and_ps(_mm256_cmp_ps(k, zero, _CMP_GT_OQ), _mm256_div_ps(one, k));
        for (int c = 0; c < 3; c++)
            color[c] = _mm256_mul_ps(color[c], f);
    }
    /* lit: a colour that is not zero, and !(n . dir <= 0) */
    __m256 dark = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(color[0], zero, _CMP_EQ_OQ),
                                              _mm256_cmp_ps(color[1], zero, _CMP_EQ_OQ)),
                                _mm256_cmp_ps(color[2], zero, _CMP_EQ_OQ));
    simd8_vec3(sp, size, offsetof(shade_point, n), n);
    __m256 ndl = simd8_dot(n, u);
    int need = lanes & ~_mm256_movemask_ps(dark) &
               _mm256_movemask_ps(_mm256_cmp_ps(ndl, zero, _CMP_NLE_UQ));
    /* shadow_ray: from the offset origin to the light */
    simd8_vec3(sp, size, offsetof(shade_point, ng), ng);
    simd8_offset(at, ng, u, o);
    _mm256_storeu_ps(p->ox, o[0]), _mm256_storeu_ps(p->oy, o[1]), _mm256_storeu_ps(p->oz, o[2]);
    _mm256_storeu_ps(p->dx, _mm256_sub_ps(pos[0], o[0]));
    _mm256_storeu_ps(p->dy, _mm256_sub_ps(pos[1], o[1]));
    _mm256_storeu_ps(p->dz, _mm256_sub_ps(pos[2], o[2]));
    _mm256_storeu_ps(p->tmin, zero), _mm256_storeu_ps(p->tmax, one);
    _mm256_storeu_ps(p->time, _mm256_loadu_ps(time));
    if (need)
        ray8_fill(p, need);
    light8_highlight(sp, need, u, n, out);
    _mm256_storeu_ps(out->ndl, ndl);
    for (int c = 0; c < 3; c++) {
        _mm256_storeu_ps(out->dir[c], u[c]);
        _mm256_storeu_ps(out->color[c], color[c]);
    }
    return need;
}

/* Defines light8_point_<isa>. */
#define LIGHT8_KERNELS(isa)                                                                    \
    int light8_point_##isa(const light *l, const shade_point *sp, int lanes,                  \
                           const float time[8], ray8 *p, light8_seen *out)                     \
    {                                                                                          \
        return light8_point(l, sp, lanes, time, p, out);                                       \
    }

#endif
