/* light8: a point light's one sample seen from the shading points of eight
 * lanes at once, with their shadow rays: lane by lane the floats that
 * light_sample, lit and shadow_ray (lighting.c) work out, in the same
 * order. For translation units compiled with AVX2 (lighting_<isa>.c). */
#ifndef GLINT_TRACE_LIGHT8_H
#define GLINT_TRACE_LIGHT8_H

#include <immintrin.h>
#include <stddef.h>
#include <string.h>
#include "trace/light8_api.h"

/* Field `off` (bytes into a shade point) of the eight points sp[k], by
 * eight loads (faster here than a gather instruction). */
static inline __m256 light8_gather(const shade_point *sp, size_t off)
{
    const char *f = (const char *)sp + off;
    const size_t n = sizeof *sp;
    float v[8];
    for (int k = 0; k < 8; k++)
        memcpy(&v[k], f + (size_t)k * n, sizeof v[k]);
    return _mm256_setr_ps(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]);
}

/* (a.x * b.x + a.y * b.y) + a.z * b.z, as v3_dot. */
static inline __m256 light8_dot(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz)
{
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by)),
                         _mm256_mul_ps(az, bz));
}

/* light8_point (light8_api.h). */
static inline int light8_point(const light *l, const shade_point *sp, int lanes,
                               const float time[8], ray8 *p, light8_seen *out)
{
    const struct point_light *pl = &l->point;
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const __m256 abs = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    __m256 px = light8_gather(sp, offsetof(shade_point, p.x));
    __m256 py = light8_gather(sp, offsetof(shade_point, p.y));
    __m256 pz = light8_gather(sp, offsetof(shade_point, p.z));
    __m256 lx = _mm256_set1_ps(pl->position.x), ly = _mm256_set1_ps(pl->position.y);
    __m256 lz = _mm256_set1_ps(pl->position.z);
    /* light_toward */
    __m256 dx = _mm256_sub_ps(lx, px), dy = _mm256_sub_ps(ly, py), dz = _mm256_sub_ps(lz, pz);
    __m256 dist = _mm256_sqrt_ps(light8_dot(dx, dy, dz, dx, dy, dz));
    if (_mm256_movemask_ps(_mm256_cmp_ps(dist, _mm256_set1_ps(INFINITY), _CMP_EQ_OQ)) & lanes)
        return -1; /* a shadow ray without end: lighting.c's own way */
    __m256 inv = _mm256_and_ps(_mm256_cmp_ps(dist, zero, _CMP_GT_OQ), _mm256_div_ps(one, dist));
    __m256 ux = _mm256_mul_ps(dx, inv), uy = _mm256_mul_ps(dy, inv), uz = _mm256_mul_ps(dz, inv);
    __m256 cr = _mm256_set1_ps(l->color.x), cg = _mm256_set1_ps(l->color.y);
    __m256 cb = _mm256_set1_ps(l->color.z);
    vec3 att = pl->attenuation;
    if (!(att.x == 1.0f && att.y == 0.0f && att.z == 0.0f)) { /* light_attenuation */
        __m256 k = _mm256_add_ps(_mm256_set1_ps(att.x),
                                 _mm256_mul_ps(dist, _mm256_add_ps(_mm256_set1_ps(att.y),
                                                                   _mm256_mul_ps(dist, _mm256_set1_ps(att.z)))));
        __m256 f = _mm256_and_ps(_mm256_cmp_ps(k, zero, _CMP_GT_OQ), _mm256_div_ps(one, k));
        cr = _mm256_mul_ps(cr, f), cg = _mm256_mul_ps(cg, f), cb = _mm256_mul_ps(cb, f);
    }
    /* lit: a colour that is not zero, and !(n . dir <= 0) */
    __m256 dark = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(cr, zero, _CMP_EQ_OQ),
                                              _mm256_cmp_ps(cg, zero, _CMP_EQ_OQ)),
                                _mm256_cmp_ps(cb, zero, _CMP_EQ_OQ));
    __m256 ndl = light8_dot(light8_gather(sp, offsetof(shade_point, n.x)),
                            light8_gather(sp, offsetof(shade_point, n.y)),
                            light8_gather(sp, offsetof(shade_point, n.z)), ux, uy, uz);
    int need = lanes & ~_mm256_movemask_ps(dark) &
               _mm256_movemask_ps(_mm256_cmp_ps(ndl, zero, _CMP_NLE_UQ));
    /* shadow_ray: ray_offset along ng to the light's side, towards the light */
    __m256 nx = light8_gather(sp, offsetof(shade_point, ng.x));
    __m256 ny = light8_gather(sp, offsetof(shade_point, ng.y));
    __m256 nz = light8_gather(sp, offsetof(shade_point, ng.z));
    __m256 m = _mm256_max_ps(_mm256_and_ps(px, abs),
                             _mm256_max_ps(_mm256_and_ps(py, abs), _mm256_and_ps(pz, abs)));
    __m256 e = _mm256_mul_ps(_mm256_set1_ps(RAY_EPS_REL), _mm256_add_ps(one, m));
    __m256 toward = _mm256_cmp_ps(light8_dot(nx, ny, nz, ux, uy, uz), zero, _CMP_GE_OQ);
    __m256 s = _mm256_blendv_ps(_mm256_xor_ps(e, _mm256_set1_ps(-0.0f)), e, toward);
    __m256 ox = _mm256_add_ps(px, _mm256_mul_ps(nx, s));
    __m256 oy = _mm256_add_ps(py, _mm256_mul_ps(ny, s));
    __m256 oz = _mm256_add_ps(pz, _mm256_mul_ps(nz, s));
    _mm256_storeu_ps(p->ox, ox), _mm256_storeu_ps(p->oy, oy), _mm256_storeu_ps(p->oz, oz);
    _mm256_storeu_ps(p->dx, _mm256_sub_ps(lx, ox));
    _mm256_storeu_ps(p->dy, _mm256_sub_ps(ly, oy));
    _mm256_storeu_ps(p->dz, _mm256_sub_ps(lz, oz));
    _mm256_storeu_ps(p->tmin, zero), _mm256_storeu_ps(p->tmax, one);
    _mm256_storeu_ps(p->time, _mm256_loadu_ps(time));
    _mm256_storeu_ps(out->ndl, ndl);
    _mm256_storeu_ps(out->dir[0], ux), _mm256_storeu_ps(out->dir[1], uy);
    _mm256_storeu_ps(out->dir[2], uz);
    _mm256_storeu_ps(out->color[0], cr), _mm256_storeu_ps(out->color[1], cg);
    _mm256_storeu_ps(out->color[2], cb);
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
