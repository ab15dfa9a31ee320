/* torus8: the torus's setup (torus.c) against a packet's rays in vector
 * registers, four lanes of doubles at a time: the line against the ball,
 * the box, the two cylinders, then the quartic about the entry point. Each
 * lane does the one-ray setup's operations in the same order (no fused
 * multiply-adds: ISO C contracts nothing), so its quartic is the same to
 * the bit; branches become masks. The roots are then found lane by lane
 * (torus_solve). For translation units compiled with AVX2 (geom/shape8.h). */
#ifndef GLINT_GEOM_TORUS8_H
#define GLINT_GEOM_TORUS8_H

#include <immintrin.h>
#include "core/ray.h"
#include "geom/shape.h"

static inline __m256d t8_load(const float *p) { return _mm256_cvtps_pd(_mm_loadu_ps(p)); }
static inline __m256d t8_add(__m256d a, __m256d b) { return _mm256_add_pd(a, b); }
static inline __m256d t8_sub(__m256d a, __m256d b) { return _mm256_sub_pd(a, b); }
static inline __m256d t8_mul(__m256d a, __m256d b) { return _mm256_mul_pd(a, b); }
static inline __m256d t8_k(double v) { return _mm256_set1_pd(v); }
/* a ? b : c, lane by lane */
static inline __m256d t8_pick(__m256d a, __m256d b, __m256d c) { return _mm256_blendv_pd(c, b, a); }
/* (a0 * b0 + a1 * b1) + a2 * b2 */
static inline __m256d t8_dot(const __m256d *a, const __m256d *b)
{
    return t8_add(t8_add(t8_mul(a[0], b[0]), t8_mul(a[1], b[1])), t8_mul(a[2], b[2]));
}

/* The clip to the box enlarged by 1% (ext), axis by axis; a lane whose
 * direction is 0 on an axis keeps its range there, or is dropped from
 * *keep when its origin lies outside the slab. */
static inline void t8_clip(const __m256d *o, const __m256d *d, const double *ext, __m256d *t0,
                           __m256d *t1, __m256d *keep)
{
    const __m256d zero = _mm256_setzero_pd(), sign = t8_k(-0.0);
    for (int a = 0; a < 3; a++) {
        __m256d flat = _mm256_cmp_pd(d[a], zero, _CMP_EQ_OQ);
        __m256d out = _mm256_cmp_pd(_mm256_andnot_pd(sign, o[a]), t8_k(ext[a]), _CMP_GT_OQ);
        *keep = _mm256_andnot_pd(_mm256_and_pd(flat, out), *keep);
        __m256d inv = _mm256_div_pd(t8_k(1.0), d[a]);
        __m256d ta = t8_mul(t8_sub(t8_k(-ext[a]), o[a]), inv);
        __m256d tb = t8_mul(t8_sub(t8_k(ext[a]), o[a]), inv);
        __m256d swap = _mm256_cmp_pd(ta, tb, _CMP_GT_OQ);
        __m256d lo = t8_pick(swap, tb, ta), hi = t8_pick(swap, ta, tb);
        __m256d n0 = t8_pick(_mm256_cmp_pd(lo, *t0, _CMP_GT_OQ), lo, *t0);
        __m256d n1 = t8_pick(_mm256_cmp_pd(hi, *t1, _CMP_LT_OQ), hi, *t1);
        *t0 = t8_pick(flat, *t0, n0);
        *t1 = t8_pick(flat, *t1, n1);
    }
    *keep = _mm256_and_pd(*keep, _mm256_cmp_pd(*t0, *t1, _CMP_LT_OQ));
}

/* The cylinders' test: drops lanes whose segment stays inside the inner
 * one or outside the outer one. */
static inline __m256d t8_cylinders(const __m256d *o, const __m256d *d, __m256d t0, __m256d t1,
                                   double inner, double outer, __m256d keep)
{
    const __m256d zero = _mm256_setzero_pd(), two = t8_k(2.0);
    __m256d qa = t8_add(t8_mul(d[0], d[0]), t8_mul(d[2], d[2]));
    __m256d qb = t8_add(t8_mul(o[0], d[0]), t8_mul(o[2], d[2]));
    __m256d qc = t8_add(t8_mul(o[0], o[0]), t8_mul(o[2], o[2]));
    __m256d e0 = t8_add(qc, t8_mul(t0, t8_add(t8_mul(two, qb), t8_mul(t0, qa))));
    __m256d e1 = t8_add(qc, t8_mul(t1, t8_add(t8_mul(two, qb), t8_mul(t1, qa))));
    __m256d in = _mm256_and_pd(_mm256_cmp_pd(e0, t8_k(inner), _CMP_LT_OQ),
                               _mm256_cmp_pd(e1, t8_k(inner), _CMP_LT_OQ));
    keep = _mm256_andnot_pd(in, keep);
    __m256d tv = _mm256_div_pd(_mm256_xor_pd(qb, t8_k(-0.0)), qa);
    tv = t8_pick(_mm256_cmp_pd(qa, zero, _CMP_GT_OQ), tv, t0);
    __m256d clamped = t8_pick(_mm256_cmp_pd(tv, t1, _CMP_GT_OQ), t1, tv);
    tv = t8_pick(_mm256_cmp_pd(tv, t0, _CMP_LT_OQ), t0, clamped);
    __m256d ev = t8_add(qc, t8_mul(tv, t8_add(t8_mul(two, qb), t8_mul(tv, qa))));
    return _mm256_and_pd(keep, _mm256_cmp_pd(ev, t8_k(outer), _CMP_NGT_UQ));
}

/* Lanes base .. base + 3 of r (those in active, bits 0-3): the ones whose
 * segment survives, with q[0 .. 4) set for them. */
static inline int torus4_setup(const struct torus *s, const ray8 *r, int base, int active,
                               torus_quartic *q)
{
    if (!active)
        return 0;
    double R = s->major, rm = s->minor;
    double ext[3] = {1.01 * (R + rm), 1.01 * rm, 1.01 * (R + rm)};
    __m256d o[3] = {t8_sub(t8_load(r->ox + base), t8_k(s->center.x)),
                    t8_sub(t8_load(r->oy + base), t8_k(s->center.y)),
                    t8_sub(t8_load(r->oz + base), t8_k(s->center.z))};
    __m256d d[3] = {t8_load(r->dx + base), t8_load(r->dy + base), t8_load(r->dz + base)};
    __m256d dd = t8_dot(d, d), od = t8_dot(o, d), oo = t8_dot(o, o);
    __m256d keep = _mm256_cmp_pd(t8_mul(od, od), t8_mul(dd, t8_sub(oo, t8_k(ext[0] * ext[0]))),
                                 _CMP_NLT_UQ);
    __m256d t0 = t8_load(r->tmin + base), t1 = t8_load(r->tmax + base);
    t8_clip(o, d, ext, &t0, &t1, &keep);
    double inner = R > rm ? (R - rm) * (R - rm) * 0.999 : 0.0, outer = (R + rm) * (R + rm) * 1.001;
    keep = t8_cylinders(o, d, t0, t1, inner, outer, keep);
    int live = active & _mm256_movemask_pd(keep);
    if (!live)
        return 0;
    __m256d len = _mm256_sqrt_pd(dd), u[3], p[3];
    for (int a = 0; a < 3; a++) {
        u[a] = _mm256_div_pd(d[a], len);
        p[a] = t8_add(o[a], t8_mul(t0, d[a]));
    }
    __m256d b = t8_dot(p, u), b4 = t8_mul(t8_k(4.0), b);
    __m256d beta = t8_sub(t8_add(t8_dot(p, p), t8_k(R * R)), t8_k(rm * rm));
    double k = 4.0 * R * R;
    __m256d c[4];
    c[3] = b4;
    c[2] = t8_sub(t8_add(t8_mul(b4, b), t8_mul(t8_k(2.0), beta)),
                  t8_mul(t8_k(k), t8_add(t8_mul(u[0], u[0]), t8_mul(u[2], u[2]))));
    c[1] = t8_sub(t8_mul(b4, beta),
                  t8_mul(t8_k(2.0 * k), t8_add(t8_mul(p[0], u[0]), t8_mul(p[2], u[2]))));
    c[0] = t8_sub(t8_mul(beta, beta),
                  t8_mul(t8_k(k), t8_add(t8_mul(p[0], p[0]), t8_mul(p[2], p[2]))));
    double cv[4][4], t0v[4], lenv[4], hiv[4], pyv[4], uyv[4];
    for (int i = 0; i < 4; i++)
        _mm256_storeu_pd(cv[i], c[i]);
    _mm256_storeu_pd(t0v, t0);
    _mm256_storeu_pd(lenv, len);
    _mm256_storeu_pd(hiv, t8_mul(t8_sub(t1, t0), len));
    _mm256_storeu_pd(pyv, p[1]);
    _mm256_storeu_pd(uyv, u[1]);
    for (int m = live; m; m &= m - 1) {
        int j = __builtin_ctz((unsigned)m);
        q[j] = (torus_quartic){{cv[0][j], cv[1][j], cv[2][j], cv[3][j], 1.0},
                               t0v[j], lenv[j], hiv[j], pyv[j], uyv[j]};
    }
    return live;
}

/* torus4_setup for the eight lanes: those whose segment survives. */
static inline int torus8_setup(const struct torus *s, const ray8 *r, int active, torus_quartic q[8])
{
    return torus4_setup(s, r, 0, active & 15, q) |
           torus4_setup(s, r, 4, active >> 4 & 15, q + 4) << 4;
}

/* torus_intersect against the rays of active, each within its own range. */
static inline int torus8_hit(const struct torus *s, const ray8 *r, int active, shape_hit *hit)
{
    torus_quartic q[8];
    int live = torus8_setup(s, r, active, q);
    int found = 0;
    for (int m = live; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray one = ray8_get(r, k);
        hit[k] = (shape_hit){0};
        if (torus_solve(&q[k], &one, &hit[k]))
            found |= 1 << k;
    }
    return found;
}

/* torus_occluded for the rays of active: those blocked. */
static inline int torus8_occluded(const struct torus *s, const ray8 *r, int active)
{
    torus_quartic q[8];
    int blocked = 0;
    for (int m = torus8_setup(s, r, active, q); m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray one = ray8_get(r, k);
        blocked |= torus_blocks(&q[k], &one) << k;
    }
    return blocked;
}

#endif
