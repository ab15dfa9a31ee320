/* light8: a point light's one sample seen from the shading points of eight
 * lanes at once, with their shadow rays, and the lanes' local light (its
 * start, each point light's share, its end): lane by lane the floats that
 * light_sample, lit, shadow_ray, add_seen and local_sum (lighting.c) work
 * out, in the same order. For translation units compiled with AVX2
 * (lighting_<isa>.c). */
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
__attribute__((always_inline)) static inline void light8_highlight(const shade8 *sp, int need,
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
     * them stored lane by lane and loaded at once would stall the load) */
    const void *m[8];
    simd8_materials(sp, need, m);
    __m256 sv = simd8_mfield(sp, m, offsetof(material, specular));
    __m256 nv = simd8_mfield(sp, m, offsetof(material, shininess));
    __m256 nu[3], r[3], v[3];
    for (int c = 0; c < 3; c++)
        nu[c] = _mm256_xor_ps(u[c], sign);
    __m256 s = _mm256_mul_ps(_mm256_set1_ps(-2.0f), simd8_dot(nu, n)); /* v3_reflect */
    for (int c = 0; c < 3; c++)
        r[c] = _mm256_add_ps(nu[c], _mm256_mul_ps(n[c], s));
    for (int c = 0; c < 3; c++)
        v[c] = simd8_lanes(sp->d[c], sp->lanewise);
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
                                                              const shade8 *sp, int lanes,
                                                              const float time[8], ray8 *p,
                                                              light8_seen *out)
{
    const struct point_light *pl = &l->point;
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    __m256 at[3], d[3], u[3], n[3], ng[3], o[3];
    for (int c = 0; c < 3; c++) {
        at[c] = simd8_lanes(sp->p[c], sp->lanewise);
        n[c] = simd8_lanes(sp->n[c], sp->lanewise);
        ng[c] = simd8_lanes(sp->ng[c], sp->lanewise);
    }
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
    __m256 dark = simd8_is_zero(color);
    __m256 ndl = simd8_dot(n, u);
    int need = lanes & ~_mm256_movemask_ps(dark) &
               _mm256_movemask_ps(_mm256_cmp_ps(ndl, zero, _CMP_NLE_UQ));
    /* shadow_ray: from the offset origin to the light */
    simd8_offset(at, ng, u, o);
    if (need) {
        __m256 dir[3];
        for (int c = 0; c < 3; c++)
            dir[c] = _mm256_sub_ps(pos[c], o[c]);
        simd8_store_rays(p, need, o, dir, zero, one, simd8_field(time, sizeof(float), 0));
    }
    light8_highlight(sp, need, u, n, out);
    _mm256_storeu_ps(out->ndl, ndl);
    for (int c = 0; c < 3; c++) {
        _mm256_storeu_ps(out->dir[c], u[c]);
        _mm256_storeu_ps(out->color[c], color[c]);
    }
    return need;
}

/* light8_start (light8_api.h): v3_scale(ambient, m->ambient), and 0. */
__attribute__((always_inline)) static inline void light8_start(const shade8 *sp, int lanes,
                                                               vec3 ambient, light8_acc *acc)
{
    if (!lanes)
        return;
    const void *m[8];
    simd8_materials(sp, lanes, m);
    __m256 a = simd8_mfield(sp, m, offsetof(material, ambient));
    const float amb[3] = {ambient.x, ambient.y, ambient.z};
    for (int c = 0; c < 3; c++) {
        _mm256_storeu_ps(acc->diffuse.c[c], _mm256_mul_ps(_mm256_set1_ps(amb[c]), a));
        _mm256_storeu_ps(acc->specular.c[c], _mm256_setzero_ps());
    }
}

/* light8_add (light8_api.h): lighting.c's add_seen where what reaches the
 * point is not zero: lc = color * vis; diffuse + lc * (m->diffuse * ndl);
 * specular + lc * hl where hl > 0. */
__attribute__((always_inline)) static inline void light8_add(const shade8 *sp, int need,
                                                             const light8_seen *seen,
                                                             const vis8 *vis, light8_acc *acc)
{
    if (!need)
        return;
    const __m256 zero = _mm256_setzero_ps();
    const void *m[8];
    simd8_materials(sp, need, m);
    __m256 v[3], open = _mm256_blendv_ps(_mm256_set1_ps(1.0f), zero, packet_lanes(vis->blocked));
    __m256 filtered = packet_lanes(vis->filtered);
    for (int c = 0; c < 3; c++) /* the filters were stored lane by lane */
        v[c] = vis->filtered ? _mm256_blendv_ps(
                                   open, simd8_field(vis->filter.c[c], sizeof(float), 0), filtered)
                             : open;
    __m256 dark = simd8_is_zero(v);
    __m256 live = _mm256_andnot_ps(dark, packet_lanes(need));
    __m256 hl = _mm256_loadu_ps(seen->hl);
    __m256 shine = _mm256_and_ps(live, _mm256_cmp_ps(hl, zero, _CMP_GT_OQ));
    __m256 f = _mm256_mul_ps(simd8_mfield(sp, m, offsetof(material, diffuse)),
                             _mm256_loadu_ps(seen->ndl));
    for (int c = 0; c < 3; c++) {
        __m256 lc = _mm256_mul_ps(_mm256_loadu_ps(seen->color[c]), v[c]);
        __m256 d = _mm256_loadu_ps(acc->diffuse.c[c]), s = _mm256_loadu_ps(acc->specular.c[c]);
        d = _mm256_blendv_ps(d, _mm256_add_ps(d, _mm256_mul_ps(lc, f)), live);
        s = _mm256_blendv_ps(s, _mm256_add_ps(s, _mm256_mul_ps(lc, hl)), shine);
        _mm256_storeu_ps(acc->diffuse.c[c], d);
        _mm256_storeu_ps(acc->specular.c[c], s);
    }
}

/* light8_end (light8_api.h): lighting.c's local_sum, ((diffuse * base) *
 * max(1 - transmit, 0) + specular) + emission. */
__attribute__((always_inline)) static inline void light8_end(const shade8 *sp, int lanes,
                                                             const light8_acc *acc, color8 *out)
{
    if (!lanes)
        return;
    const void *m[8];
    simd8_materials(sp, lanes, m);
    __m256 w = _mm256_max_ps(_mm256_sub_ps(_mm256_set1_ps(1.0f),
                                           simd8_mfield(sp, m, offsetof(material, transmit))),
                             _mm256_setzero_ps());
    for (int i = 0; i < 3; i++) {
        __m256 d = _mm256_mul_ps(_mm256_loadu_ps(acc->diffuse.c[i]),
                                 simd8_lanes(sp->base[i], sp->lanewise));
        __m256 v = _mm256_add_ps(_mm256_mul_ps(d, w), _mm256_loadu_ps(acc->specular.c[i]));
        __m256 e = simd8_mfield(sp, m, offsetof(material, emission) + (size_t)i * sizeof(float));
        _mm256_storeu_ps(out->c[i], _mm256_add_ps(v, e));
    }
}

/* Defines light8_point_<isa>, light8_start_<isa>, light8_add_<isa> and
 * light8_end_<isa>. */
#define LIGHT8_KERNELS(isa)                                                                    \
    int light8_point_##isa(const light *l, const shade8 *sp, int lanes, const float time[8],  \
                           ray8 *p, light8_seen *out)                                          \
    {                                                                                          \
        return light8_point(l, sp, lanes, time, p, out);                                       \
    }                                                                                          \
    void light8_start_##isa(const shade8 *sp, int lanes, vec3 ambient, light8_acc *acc)        \
    {                                                                                          \
        light8_start(sp, lanes, ambient, acc);                                                 \
    }                                                                                          \
    void light8_add_##isa(const shade8 *sp, int need, const light8_seen *seen, const vis8 *vis, \
                          light8_acc *acc)                                                     \
    {                                                                                          \
        light8_add(sp, need, seen, vis, acc);                                                  \
    }                                                                                          \
    void light8_end_##isa(const shade8 *sp, int lanes, const light8_acc *acc, color8 *out)     \
    {                                                                                          \
        light8_end(sp, lanes, acc, out);                                                       \
    }

#endif
