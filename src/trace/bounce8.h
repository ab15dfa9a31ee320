/* bounce8: a packet's shading eight lanes at once (bounce8_api.h): lane by
 * lane the floats of shade_prepare's plain surfaces (prepare8.h), split,
 * adc_keep, v3_reflect, ray_offset, ray_make and the light the secondary
 * rays bring back (whitted.c, core/ray.h, shade/optics.h), in the same
 * order. For translation units compiled with AVX2 (whitted_<isa>.c). */
#ifndef GLINT_TRACE_BOUNCE8_H
#define GLINT_TRACE_BOUNCE8_H

#include "geom/mesh_packet.h" /* packet_lanes */
#include "scene/scene.h"
#include "trace/bounce8_api.h"
#include "trace/prepare8.h"
#include "trace/simd8.h"

/* split (whitted.c) with optics_refract and optics_schlick. */
__attribute__((always_inline)) static inline int bounce8_split(const shade8 *sp, int found,
                                                               float kr_out[8], float kt_out[8],
                                                               float gt_out[8], color8 *tdir,
                                                               int *transmits)
{
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const __m256 sign = _mm256_set1_ps(-0.0f);
    *transmits = 0;
    if (!found)
        return 0;
    const void *m[8];
    simd8_materials(sp, found, m);
    __m256 kr = simd8_mfield(sp, m, offsetof(material, reflect));
    __m256 kt = simd8_mfield(sp, m, offsetof(material, transmit));
    __m256 ior = simd8_mfield(sp, m, offsetof(material, ior));
    __m256 d[3], n[3], tdv[3];
    for (int c = 0; c < 3; c++) {
        d[c] = tdv[c] = simd8_lanes(sp->d[c], sp->lanewise);
        n[c] = simd8_lanes(sp->n[c], sp->lanewise);
    }
    __m256 bends = _mm256_and_ps(_mm256_cmp_ps(kt, zero, _CMP_NLE_UQ),
                                 _mm256_cmp_ps(ior, one, _CMP_NEQ_UQ));
    bends = _mm256_and_ps(bends, packet_lanes(found));
    if (_mm256_movemask_ps(bends)) {
        __m256 in = packet_lanes(sp->inside);
        __m256 n1 = _mm256_blendv_ps(one, ior, in), n2 = _mm256_blendv_ps(ior, one, in);
        __m256 eta = _mm256_div_ps(n1, n2);
        __m256 cosi = _mm256_xor_ps(simd8_dot(d, n), sign);
        __m256 k = _mm256_sub_ps(one, _mm256_mul_ps(_mm256_mul_ps(eta, eta),
                                                    _mm256_sub_ps(one, _mm256_mul_ps(cosi, cosi))));
        __m256 tir = _mm256_and_ps(bends, _mm256_cmp_ps(k, zero, _CMP_LT_OQ));
        __m256 refr = _mm256_andnot_ps(tir, bends);
        __m256 s = _mm256_sub_ps(_mm256_mul_ps(eta, cosi), _mm256_sqrt_ps(k));
        for (int c = 0; c < 3; c++)
            tdv[c] = _mm256_blendv_ps(
                d[c], _mm256_add_ps(_mm256_mul_ps(d[c], eta), _mm256_mul_ps(n[c], s)), refr);
        kr = _mm256_blendv_ps(kr, _mm256_add_ps(kr, kt), tir);
        kt = _mm256_blendv_ps(kt, zero, tir);
        int fres = sp->same ? -sp->same->fresnel : 0;
        for (int j = 0; j < 8 && !sp->same; j++)
            fres |= ((const material *)m[j])->fresnel << j;
        __m256 fr = _mm256_and_ps(refr, packet_lanes(fres));
        if (_mm256_movemask_ps(fr)) {
            __m256 dotc = _mm256_blendv_ps(simd8_dot(d, n), simd8_dot(tdv, n),
                                           _mm256_cmp_ps(n1, n2, _CMP_GT_OQ));
            __m256 cosine = _mm256_xor_ps(dotc, sign);
            __m256 r0 = _mm256_div_ps(_mm256_sub_ps(n1, n2), _mm256_add_ps(n1, n2));
            r0 = _mm256_mul_ps(r0, r0);
            __m256 mm = _mm256_sub_ps(one, cosine), m2 = _mm256_mul_ps(mm, mm);
            __m256 g = _mm256_mul_ps(_mm256_mul_ps(_mm256_sub_ps(one, r0), m2), m2);
            __m256 f = _mm256_add_ps(r0, _mm256_mul_ps(g, mm));
            kr = _mm256_blendv_ps(kr, _mm256_add_ps(kr, _mm256_mul_ps(kt, f)), fr);
            kt = _mm256_blendv_ps(kt, _mm256_mul_ps(kt, _mm256_sub_ps(one, f)), fr);
        }
    }
    __m256 tint[3];
    for (int c = 0; c < 3; c++) {
        tint[c] = simd8_mfield(sp, m, offsetof(material, tint) + (size_t)c * sizeof(float));
        _mm256_storeu_ps(tdir->c[c], tdv[c]);
    }
    __m256 big = _mm256_max_ps(tint[0], _mm256_max_ps(tint[1], tint[2]));
    _mm256_storeu_ps(kr_out, kr);
    _mm256_storeu_ps(kt_out, kt);
    _mm256_storeu_ps(gt_out, _mm256_mul_ps(kt, big));
    *transmits = found & _mm256_movemask_ps(_mm256_cmp_ps(kt, zero, _CMP_GT_OQ));
    return found & _mm256_movemask_ps(_mm256_cmp_ps(kr, zero, _CMP_GT_OQ));
}

/* mix (bounce8_api.h): v3_madd(c, sub, k), or v3_add(c, v3_scale(v3_mul(sub,
 * tint), k)). */
__attribute__((always_inline)) static inline void bounce8_mix(const shade8 *sp, int keep,
                                                              bool reflect, const color8 *sub,
                                                              const float k[8], color8 *c)
{
    if (!keep)
        return;
    const void *m[8];
    simd8_materials(sp, keep, m);
    __m256 kk = _mm256_loadu_ps(k), lanes = packet_lanes(keep);
    for (int i = 0; i < 3; i++) {
        __m256 s = _mm256_loadu_ps(sub->c[i]), v = _mm256_loadu_ps(c->c[i]);
        size_t tint = offsetof(material, tint) + (size_t)i * sizeof(float);
        if (!reflect)
            s = _mm256_mul_ps(s, simd8_mfield(sp, m, tint));
        __m256 sum = _mm256_add_ps(v, _mm256_mul_ps(s, kk));
        _mm256_storeu_ps(c->c[i], _mm256_blendv_ps(v, sum, lanes));
    }
}

__attribute__((always_inline)) static inline int bounce8(const bounce8_from *f, int found,
                                                         bool reflect, ray8 *p, float weight[8])
{
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const shade8 *sp = f->sp;
    /* adc_keep: share * k / max(total, 1), kept where k > 0 and not below
     * the bailout; the shares were just stored one by one */
    __m256 kr = _mm256_loadu_ps(f->kr), gt = _mm256_loadu_ps(f->gt);
    __m256 k = reflect ? kr : gt;
    __m256 w = _mm256_div_ps(_mm256_mul_ps(simd8_field(f->share, sizeof(float), 0), k),
                             _mm256_max_ps(_mm256_add_ps(kr, gt), one));
    __m256 keep = _mm256_and_ps(_mm256_cmp_ps(k, zero, _CMP_GT_OQ),
                                _mm256_cmp_ps(w, _mm256_set1_ps(f->bailout), _CMP_NLT_UQ));
    if (!reflect)
        keep = _mm256_and_ps(keep, _mm256_cmp_ps(_mm256_loadu_ps(f->kt), zero, _CMP_GT_OQ));
    found &= _mm256_movemask_ps(keep);
    if (!found)
        return 0;
    __m256 d[3], at[3], ng[3], o[3];
    if (reflect) { /* v3_reflect(d, n) = d + n (-2 d.n) */
        __m256 in[3], n[3];
        for (int c = 0; c < 3; c++)
            in[c] = simd8_lanes(sp->d[c], sp->lanewise), n[c] = simd8_lanes(sp->n[c], sp->lanewise);
        __m256 s = _mm256_mul_ps(_mm256_set1_ps(-2.0f), simd8_dot(in, n));
        for (int c = 0; c < 3; c++)
            d[c] = _mm256_add_ps(in[c], _mm256_mul_ps(n[c], s));
    } else {
        for (int c = 0; c < 3; c++)
            d[c] = _mm256_loadu_ps(f->tdir->c[c]);
    }
    for (int c = 0; c < 3; c++)
        at[c] = simd8_lanes(sp->p[c], sp->lanewise), ng[c] = simd8_lanes(sp->ng[c], sp->lanewise);
    simd8_offset(at, ng, d, o);
    simd8_store_rays(p, found, o, d, zero, _mm256_set1_ps(INFINITY),
                     simd8_field(f->time, sizeof(float), 0));
    float ws[8];
    _mm256_storeu_ps(ws, w);
    for (int b = found; b; b &= b - 1) {
        int j = __builtin_ctz((unsigned)b);
        weight[j] = ws[j];
    }
    return found;
}

/* Defines shade8_kernels_<isa>. */
#define BOUNCE8_KERNELS(isa)                                                                   \
    static void prepare_##isa(const scene *s, const float decode[256], const ray8 *p,         \
                              const shade8_plain *kinds, const scene_hit *hit, shade8 *sp)     \
    {                                                                                          \
        prepare8(s, decode, p, kinds, hit, sp);                                                \
    }                                                                                          \
    static int split_##isa(const shade8 *sp, int found, float kr[8], float kt[8], float gt[8], \
                           color8 *tdir, int *transmits)                                   \
    {                                                                                          \
        return bounce8_split(sp, found, kr, kt, gt, tdir, transmits);                          \
    }                                                                                          \
    static void mix_##isa(const shade8 *sp, int keep, bool reflect, const color8 *sub,        \
                          const float k[8], color8 *c)                                         \
    {                                                                                          \
        bounce8_mix(sp, keep, reflect, sub, k, c);                                             \
    }                                                                                          \
    static int bounce_##isa(const bounce8_from *f, int found, bool reflect, ray8 *p,          \
                            float weight[8])                                                   \
    {                                                                                          \
        return bounce8(f, found, reflect, p, weight);                                          \
    }                                                                                          \
    const shade8_kernels shade8_kernels_##isa = {prepare_##isa, split_##isa, mix_##isa,       \
                                                 bounce_##isa};

#endif
