/* bounce8: a packet's reflected or transmitted rays, eight lanes at once:
 * lane by lane the floats of adc_keep, v3_reflect, ray_offset and
 * ray_make (whitted.c, core/ray.h), in the same order. For translation
 * units compiled with AVX2 (whitted_<isa>.c). */
#ifndef GLINT_TRACE_BOUNCE8_H
#define GLINT_TRACE_BOUNCE8_H

#include "trace/bounce8_api.h"
#include "trace/simd8.h"

__attribute__((always_inline)) static inline int bounce8(const bounce8_from *f, int found,
                                                         bool reflect, ray rs[8], ray8 *p,
                                                         float weight[8])
{
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const shade_point *sp = f->sp;
    const size_t size = sizeof *sp;
    /* adc_keep: share * k / max(total, 1), kept where k > 0 and not below
     * the bailout; the factors were just stored one by one */
    __m256 kr = simd8_field(f->kr, sizeof(float), 0), gt = simd8_field(f->gt, sizeof(float), 0);
    __m256 k = reflect ? kr : gt;
    __m256 w = _mm256_div_ps(_mm256_mul_ps(simd8_field(f->share, sizeof(float), 0), k),
                             _mm256_max_ps(_mm256_add_ps(kr, gt), one));
    __m256 keep = _mm256_and_ps(_mm256_cmp_ps(k, zero, _CMP_GT_OQ),
                                _mm256_cmp_ps(w, _mm256_set1_ps(f->bailout), _CMP_NLT_UQ));
    if (!reflect)
        keep = _mm256_and_ps(keep, _mm256_cmp_ps(simd8_field(f->kt, sizeof(float), 0), zero,
                                                  _CMP_GT_OQ));
    found &= _mm256_movemask_ps(keep);
    if (!found)
        return 0;
    __m256 d[3], at[3], ng[3], o[3];
    if (reflect) { /* v3_reflect(d, n) = d + n (-2 d.n) */
        __m256 in[3], n[3];
        simd8_vec3(sp, size, offsetof(shade_point, d), in);
        simd8_vec3(sp, size, offsetof(shade_point, n), n);
        __m256 s = _mm256_mul_ps(_mm256_set1_ps(-2.0f), simd8_dot(in, n));
        for (int c = 0; c < 3; c++)
            d[c] = _mm256_add_ps(in[c], _mm256_mul_ps(n[c], s));
    } else {
        simd8_vec3(f->tdir, sizeof *f->tdir, 0, d);
    }
    simd8_vec3(sp, size, offsetof(shade_point, p), at);
    simd8_vec3(sp, size, offsetof(shade_point, ng), ng);
    simd8_offset(at, ng, d, o);
    _mm256_storeu_ps(p->ox, o[0]), _mm256_storeu_ps(p->oy, o[1]), _mm256_storeu_ps(p->oz, o[2]);
    _mm256_storeu_ps(p->dx, d[0]), _mm256_storeu_ps(p->dy, d[1]), _mm256_storeu_ps(p->dz, d[2]);
    _mm256_storeu_ps(p->tmin, zero), _mm256_storeu_ps(p->tmax, _mm256_set1_ps(INFINITY));
    _mm256_storeu_ps(p->time, simd8_field(f->time, sizeof(float), 0));
    float ws[8];
    _mm256_storeu_ps(ws, w);
    for (int b = found; b; b &= b - 1) {
        int j = __builtin_ctz((unsigned)b);
        rs[j] = ray8_get(p, j);
        weight[j] = ws[j];
    }
    ray8_fill(p, found);
    return found;
}

/* Defines bounce8_<isa>. */
#define BOUNCE8_KERNELS(isa)                                                                   \
    int bounce8_##isa(const bounce8_from *f, int found, bool reflect, ray rs[8], ray8 *p,      \
                      float weight[8])                                                         \
    {                                                                                          \
        return bounce8(f, found, reflect, rs, p, weight);                                      \
    }

#endif
