/* bounce8: a packet's reflected or transmitted rays, eight lanes at once:
 * lane by lane the floats of adc_keep, v3_reflect, ray_offset and
 * ray_make (whitted.c, core/ray.h), in the same order. For translation
 * units compiled with AVX2 (whitted_<isa>.c). */
#ifndef GLINT_TRACE_BOUNCE8_H
#define GLINT_TRACE_BOUNCE8_H

#include <immintrin.h>
#include <math.h>
#include <stddef.h>
#include <string.h>
#include "trace/bounce8_api.h"

/* Field `off` (bytes into an element of `size` bytes) of the eight
 * elements from `base`, by eight loads. */
static inline __m256 bounce8_load(const void *base, size_t size, size_t off)
{
    const char *f = (const char *)base + off;
    float v[8];
    for (int k = 0; k < 8; k++)
        memcpy(&v[k], f + (size_t)k * size, sizeof v[k]);
    return _mm256_setr_ps(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]);
}

static inline __m256 bounce8_dot(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz)
{
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by)),
                         _mm256_mul_ps(az, bz));
}

static inline int bounce8(const bounce8_from *f, int found, bool reflect, ray rs[8], ray8 *p,
                          float weight[8])
{
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const __m256 abs = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const shade_point *sp = f->sp;
    const size_t n = sizeof *sp;
    /* adc_keep: share * k / max(total, 1), kept where k > 0 and not below the bailout */
    /* the lanes' factors were just stored one by one: loaded the same way,
     * as a wide load of narrow stores waits for them to reach the cache */
    __m256 kr = bounce8_load(f->kr, sizeof *f->kr, 0), gt = bounce8_load(f->gt, sizeof *f->gt, 0);
    __m256 k = reflect ? kr : gt;
    __m256 w = _mm256_div_ps(_mm256_mul_ps(bounce8_load(f->share, sizeof *f->share, 0), k),
                             _mm256_max_ps(_mm256_add_ps(kr, gt), one));
    __m256 keep = _mm256_and_ps(_mm256_cmp_ps(k, zero, _CMP_GT_OQ),
                                _mm256_cmp_ps(w, _mm256_set1_ps(f->bailout), _CMP_NLT_UQ));
    if (!reflect)
        keep = _mm256_and_ps(keep, _mm256_cmp_ps(bounce8_load(f->kt, sizeof *f->kt, 0), zero,
                                                  _CMP_GT_OQ));
    found &= _mm256_movemask_ps(keep);
    if (!found)
        return 0;
    __m256 dx, dy, dz;
    if (reflect) { /* v3_reflect(d, n) = d + n (-2 d.n) */
        __m256 ix = bounce8_load(sp, n, offsetof(shade_point, d.x));
        __m256 iy = bounce8_load(sp, n, offsetof(shade_point, d.y));
        __m256 iz = bounce8_load(sp, n, offsetof(shade_point, d.z));
        __m256 nx = bounce8_load(sp, n, offsetof(shade_point, n.x));
        __m256 ny = bounce8_load(sp, n, offsetof(shade_point, n.y));
        __m256 nz = bounce8_load(sp, n, offsetof(shade_point, n.z));
        __m256 s = _mm256_mul_ps(_mm256_set1_ps(-2.0f), bounce8_dot(ix, iy, iz, nx, ny, nz));
        dx = _mm256_add_ps(ix, _mm256_mul_ps(nx, s));
        dy = _mm256_add_ps(iy, _mm256_mul_ps(ny, s));
        dz = _mm256_add_ps(iz, _mm256_mul_ps(nz, s));
    } else {
        dx = bounce8_load(f->tdir, sizeof *f->tdir, offsetof(vec3, x));
        dy = bounce8_load(f->tdir, sizeof *f->tdir, offsetof(vec3, y));
        dz = bounce8_load(f->tdir, sizeof *f->tdir, offsetof(vec3, z));
    }
    /* ray_offset(p, ng, d) */
    __m256 px = bounce8_load(sp, n, offsetof(shade_point, p.x));
    __m256 py = bounce8_load(sp, n, offsetof(shade_point, p.y));
    __m256 pz = bounce8_load(sp, n, offsetof(shade_point, p.z));
    __m256 gx = bounce8_load(sp, n, offsetof(shade_point, ng.x));
    __m256 gy = bounce8_load(sp, n, offsetof(shade_point, ng.y));
    __m256 gz = bounce8_load(sp, n, offsetof(shade_point, ng.z));
    __m256 m = _mm256_max_ps(_mm256_and_ps(px, abs),
                             _mm256_max_ps(_mm256_and_ps(py, abs), _mm256_and_ps(pz, abs)));
    __m256 e = _mm256_mul_ps(_mm256_set1_ps(RAY_EPS_REL), _mm256_add_ps(one, m));
    __m256 out = _mm256_cmp_ps(bounce8_dot(gx, gy, gz, dx, dy, dz), zero, _CMP_GE_OQ);
    __m256 s = _mm256_blendv_ps(_mm256_xor_ps(e, _mm256_set1_ps(-0.0f)), e, out);
    _mm256_storeu_ps(p->ox, _mm256_add_ps(px, _mm256_mul_ps(gx, s)));
    _mm256_storeu_ps(p->oy, _mm256_add_ps(py, _mm256_mul_ps(gy, s)));
    _mm256_storeu_ps(p->oz, _mm256_add_ps(pz, _mm256_mul_ps(gz, s)));
    _mm256_storeu_ps(p->dx, dx), _mm256_storeu_ps(p->dy, dy), _mm256_storeu_ps(p->dz, dz);
    _mm256_storeu_ps(p->tmin, zero), _mm256_storeu_ps(p->tmax, _mm256_set1_ps(INFINITY));
    _mm256_storeu_ps(p->time, bounce8_load(f->time, sizeof *f->time, 0));
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
