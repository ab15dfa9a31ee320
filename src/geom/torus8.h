/* torus8: the torus's setup (torus.c) against a packet's rays in vector
 * registers, all eight lanes of doubles at once with AVX-512 and four at a
 * time with AVX2: the line against the ball,
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

/* A group of lanes in one register of doubles: all eight with AVX-512,
 * four at a time with AVX2; td is the register, tk the lanes a comparison
 * keeps (a mask register, or a register of all-ones lanes). */
#if defined(__AVX512F__)
#define TORUS_LANES 8
typedef __m512d td;
typedef __mmask8 tk;
static inline td t8_load(const float *p) { return _mm512_cvtps_pd(_mm256_loadu_ps(p)); }
static inline td t8_add(td a, td b) { return _mm512_add_pd(a, b); }
static inline td t8_sub(td a, td b) { return _mm512_sub_pd(a, b); }
static inline td t8_mul(td a, td b) { return _mm512_mul_pd(a, b); }
static inline td t8_div(td a, td b) { return _mm512_div_pd(a, b); }
static inline td t8_sqrt(td a) { return _mm512_sqrt_pd(a); }
static inline td t8_k(double v) { return _mm512_set1_pd(v); }
static inline td t8_zero(void) { return _mm512_setzero_pd(); }
/* |a| and -a: the sign bit cleared or flipped (AVX-512F has no and_pd) */
static inline td t8_abs(td a)
{
    return _mm512_castsi512_pd(
        _mm512_andnot_si512(_mm512_castpd_si512(t8_k(-0.0)), _mm512_castpd_si512(a)));
}
static inline td t8_neg(td a)
{
    return _mm512_castsi512_pd(
        _mm512_xor_si512(_mm512_castpd_si512(t8_k(-0.0)), _mm512_castpd_si512(a)));
}
static inline void t8_store(double *p, td a) { _mm512_storeu_pd(p, a); }
#define t8_cmp(a, b, pred) _mm512_cmp_pd_mask((a), (b), (pred))
static inline tk tk_and(tk a, tk b) { return a & b; }
static inline tk tk_andnot(tk a, tk b) { return (tk)(~a & b); } /* b without a */
static inline int tk_bits(tk a) { return (int)a; }
/* a ? b : c, lane by lane */
static inline td t8_pick(tk a, td b, td c) { return _mm512_mask_blend_pd(a, c, b); }
#else
#define TORUS_LANES 4
typedef __m256d td;
typedef __m256d tk;
static inline td t8_load(const float *p) { return _mm256_cvtps_pd(_mm_loadu_ps(p)); }
static inline td t8_add(td a, td b) { return _mm256_add_pd(a, b); }
static inline td t8_sub(td a, td b) { return _mm256_sub_pd(a, b); }
static inline td t8_mul(td a, td b) { return _mm256_mul_pd(a, b); }
static inline td t8_div(td a, td b) { return _mm256_div_pd(a, b); }
static inline td t8_sqrt(td a) { return _mm256_sqrt_pd(a); }
static inline td t8_k(double v) { return _mm256_set1_pd(v); }
static inline td t8_zero(void) { return _mm256_setzero_pd(); }
static inline td t8_abs(td a) { return _mm256_andnot_pd(t8_k(-0.0), a); }
static inline td t8_neg(td a) { return _mm256_xor_pd(a, t8_k(-0.0)); }
static inline void t8_store(double *p, td a) { _mm256_storeu_pd(p, a); }
#define t8_cmp(a, b, pred) _mm256_cmp_pd((a), (b), (pred))
static inline tk tk_and(tk a, tk b) { return _mm256_and_pd(a, b); }
static inline tk tk_andnot(tk a, tk b) { return _mm256_andnot_pd(a, b); } /* b without a */
static inline int tk_bits(tk a) { return _mm256_movemask_pd(a); }
/* a ? b : c, lane by lane */
static inline td t8_pick(tk a, td b, td c) { return _mm256_blendv_pd(c, b, a); }
#endif

/* (a0 * b0 + a1 * b1) + a2 * b2 */
static inline td t8_dot(const td *a, const td *b)
{
    return t8_add(t8_add(t8_mul(a[0], b[0]), t8_mul(a[1], b[1])), t8_mul(a[2], b[2]));
}

/* The clip to the box enlarged by 1% (ext), axis by axis; a lane whose
 * direction is 0 on an axis keeps its range there, or is dropped from
 * *keep when its origin lies outside the slab. */
static inline void t8_clip(const td *o, const td *d, const double *ext, td *t0, td *t1, tk *keep)
{
    for (int a = 0; a < 3; a++) {
        tk flat = t8_cmp(d[a], t8_zero(), _CMP_EQ_OQ);
        tk out = t8_cmp(t8_abs(o[a]), t8_k(ext[a]), _CMP_GT_OQ);
        *keep = tk_andnot(tk_and(flat, out), *keep);
        td inv = t8_div(t8_k(1.0), d[a]);
        td ta = t8_mul(t8_sub(t8_k(-ext[a]), o[a]), inv);
        td tb = t8_mul(t8_sub(t8_k(ext[a]), o[a]), inv);
        tk swap = t8_cmp(ta, tb, _CMP_GT_OQ);
        td lo = t8_pick(swap, tb, ta), hi = t8_pick(swap, ta, tb);
        td n0 = t8_pick(t8_cmp(lo, *t0, _CMP_GT_OQ), lo, *t0);
        td n1 = t8_pick(t8_cmp(hi, *t1, _CMP_LT_OQ), hi, *t1);
        *t0 = t8_pick(flat, *t0, n0);
        *t1 = t8_pick(flat, *t1, n1);
    }
    *keep = tk_and(*keep, t8_cmp(*t0, *t1, _CMP_LT_OQ));
}

/* The cylinders' test: drops lanes whose segment stays inside the inner
 * one or outside the outer one. */
static inline tk t8_cylinders(const td *o, const td *d, td t0, td t1, double inner, double outer,
                              tk keep)
{
    const td two = t8_k(2.0);
    td qa = t8_add(t8_mul(d[0], d[0]), t8_mul(d[2], d[2]));
    td qb = t8_add(t8_mul(o[0], d[0]), t8_mul(o[2], d[2]));
    td qc = t8_add(t8_mul(o[0], o[0]), t8_mul(o[2], o[2]));
    td e0 = t8_add(qc, t8_mul(t0, t8_add(t8_mul(two, qb), t8_mul(t0, qa))));
    td e1 = t8_add(qc, t8_mul(t1, t8_add(t8_mul(two, qb), t8_mul(t1, qa))));
    tk in = tk_and(t8_cmp(e0, t8_k(inner), _CMP_LT_OQ), t8_cmp(e1, t8_k(inner), _CMP_LT_OQ));
    keep = tk_andnot(in, keep);
    td tv = t8_div(t8_neg(qb), qa);
    tv = t8_pick(t8_cmp(qa, t8_zero(), _CMP_GT_OQ), tv, t0);
    td clamped = t8_pick(t8_cmp(tv, t1, _CMP_GT_OQ), t1, tv);
    tv = t8_pick(t8_cmp(tv, t0, _CMP_LT_OQ), t0, clamped);
    td ev = t8_add(qc, t8_mul(tv, t8_add(t8_mul(two, qb), t8_mul(tv, qa))));
    return tk_and(keep, t8_cmp(ev, t8_k(outer), _CMP_NGT_UQ));
}

/* Lanes base .. base + TORUS_LANES - 1 of r (those in active, from bit
 * 0): the ones whose segment survives, with q[0 ..) set for them. */
static inline int torus_lanes_setup(const struct torus *s, const ray8 *r, int base, int active,
                                    torus_quartic *q)
{
    if (!active)
        return 0;
    double R = s->major, rm = s->minor;
    double ext[3] = {1.01 * (R + rm), 1.01 * rm, 1.01 * (R + rm)};
    td o[3] = {t8_sub(t8_load(r->ox + base), t8_k(s->center.x)),
               t8_sub(t8_load(r->oy + base), t8_k(s->center.y)),
               t8_sub(t8_load(r->oz + base), t8_k(s->center.z))};
    td d[3] = {t8_load(r->dx + base), t8_load(r->dy + base), t8_load(r->dz + base)};
    td dd = t8_dot(d, d), od = t8_dot(o, d), oo = t8_dot(o, o);
    tk keep = t8_cmp(t8_mul(od, od), t8_mul(dd, t8_sub(oo, t8_k(ext[0] * ext[0]))), _CMP_NLT_UQ);
    td t0 = t8_load(r->tmin + base), t1 = t8_load(r->tmax + base);
    t8_clip(o, d, ext, &t0, &t1, &keep);
    double inner = R > rm ? (R - rm) * (R - rm) * 0.999 : 0.0, outer = (R + rm) * (R + rm) * 1.001;
    keep = t8_cylinders(o, d, t0, t1, inner, outer, keep);
    int live = active & tk_bits(keep);
    if (!live)
        return 0;
    td len = t8_sqrt(dd), u[3], p[3];
    for (int a = 0; a < 3; a++) {
        u[a] = t8_div(d[a], len);
        p[a] = t8_add(o[a], t8_mul(t0, d[a]));
    }
    td b = t8_dot(p, u), b4 = t8_mul(t8_k(4.0), b);
    td beta = t8_sub(t8_add(t8_dot(p, p), t8_k(R * R)), t8_k(rm * rm));
    double k = 4.0 * R * R;
    td c[4];
    c[3] = b4;
    c[2] = t8_sub(t8_add(t8_mul(b4, b), t8_mul(t8_k(2.0), beta)),
                  t8_mul(t8_k(k), t8_add(t8_mul(u[0], u[0]), t8_mul(u[2], u[2]))));
    c[1] = t8_sub(t8_mul(b4, beta),
                  t8_mul(t8_k(2.0 * k), t8_add(t8_mul(p[0], u[0]), t8_mul(p[2], u[2]))));
    c[0] = t8_sub(t8_mul(beta, beta),
                  t8_mul(t8_k(k), t8_add(t8_mul(p[0], p[0]), t8_mul(p[2], p[2]))));
    double cv[4][TORUS_LANES], t0v[TORUS_LANES], lenv[TORUS_LANES], hiv[TORUS_LANES];
    double pyv[TORUS_LANES], uyv[TORUS_LANES];
    for (int i = 0; i < 4; i++)
        t8_store(cv[i], c[i]);
    t8_store(t0v, t0);
    t8_store(lenv, len);
    t8_store(hiv, t8_mul(t8_sub(t1, t0), len));
    t8_store(pyv, p[1]);
    t8_store(uyv, u[1]);
    for (int m = live; m; m &= m - 1) {
        int j = __builtin_ctz((unsigned)m);
        q[j] = (torus_quartic){{cv[0][j], cv[1][j], cv[2][j], cv[3][j], 1.0},
                               t0v[j], lenv[j], hiv[j], pyv[j], uyv[j]};
    }
    return live;
}

/* torus_lanes_setup for the eight lanes: those whose segment survives. */
static inline int torus8_setup(const struct torus *s, const ray8 *r, int active, torus_quartic q[8])
{
#if TORUS_LANES == 8
    return torus_lanes_setup(s, r, 0, active, q);
#else
    return torus_lanes_setup(s, r, 0, active & 15, q) |
           torus_lanes_setup(s, r, 4, active >> 4 & 15, q + 4) << 4;
#endif
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
