/* torus8: the torus's setup (torus.c) against a packet's rays in vector
 * registers, all eight lanes of doubles at once (one AVX-512 register, or
 * two AVX ones side by side): the line against the ball, the box, the two
 * cylinders, then the quartic about the entry point. Each
 * lane does the one-ray setup's operations in the same order (no fused
 * multiply-adds: ISO C contracts nothing), so its quartic is the same to
 * the bit; branches become masks. The search for the first root then
 * starts in the same registers (t8_first_root): the test that the quartic
 * stays above zero, and the Newton steps of roots_quartic's commonest
 * paths (from the entry, or from the first inflection, and on from the
 * second where the first piece has no root), all lanes
 * stepping together instead of one search after another, each with its
 * own data-dependent loop (row 8 of bench/README.md: as many instructions,
 * 9% less time). Lanes it leaves undecided, about one in twenty-five
 * there, go to torus_solve one by one. For
 * translation units compiled with AVX2 (geom/shape8.h). */
#ifndef GLINT_GEOM_TORUS8_H
#define GLINT_GEOM_TORUS8_H

#include <immintrin.h>
#include "core/ray.h"
#include "geom/shape.h"

/* The eight lanes' doubles: td holds them (one AVX-512 register, or two
 * AVX ones), tk the lanes a comparison keeps (a mask register, or
 * registers of all-ones lanes). */
#if defined(__AVX512F__)
typedef __m512d td;
typedef __mmask8 tk;
static inline td t8_load(const float *p) { return _mm512_cvtps_pd(_mm256_loadu_ps(p)); }
static inline td t8_widen(__m256 v) { return _mm512_cvtps_pd(v); }
static inline __m256 t8_narrow(td a) { return _mm512_cvtpd_ps(a); }
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
/* |a| with the sign of b */
static inline td t8_copysign(td a, td b)
{
    __m512i sign = _mm512_castpd_si512(t8_k(-0.0));
    return _mm512_castsi512_pd(_mm512_or_si512(_mm512_andnot_si512(sign, _mm512_castpd_si512(a)),
                                               _mm512_and_si512(sign, _mm512_castpd_si512(b))));
}
static inline tk tk_or(tk a, tk b) { return a | b; }
static inline tk tk_xor(tk a, tk b) { return a ^ b; }
static inline bool tk_any(tk a) { return a != 0; }
/* the lanes of bits (from bit 0) */
static inline tk tk_lanes(int bits) { return (tk)bits; }
#else
/* Two AVX registers side by side, lanes 0-3 and 4-7: the two halves'
 * operations are independent, so each step of one overlaps the other's. */
typedef struct td {
    __m256d lo, hi;
} td;
typedef td tk;
#define T8_BOTH(f, a, b) ((td){f((a).lo, (b).lo), f((a).hi, (b).hi)})
static inline td t8_load(const float *p)
{
    return (td){_mm256_cvtps_pd(_mm_loadu_ps(p)), _mm256_cvtps_pd(_mm_loadu_ps(p + 4))};
}
static inline td t8_widen(__m256 v)
{
    return (td){_mm256_cvtps_pd(_mm256_castps256_ps128(v)),
                _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1))};
}
static inline __m256 t8_narrow(td a)
{
    return _mm256_set_m128(_mm256_cvtpd_ps(a.hi), _mm256_cvtpd_ps(a.lo));
}
static inline td t8_add(td a, td b) { return T8_BOTH(_mm256_add_pd, a, b); }
static inline td t8_sub(td a, td b) { return T8_BOTH(_mm256_sub_pd, a, b); }
static inline td t8_mul(td a, td b) { return T8_BOTH(_mm256_mul_pd, a, b); }
static inline td t8_div(td a, td b) { return T8_BOTH(_mm256_div_pd, a, b); }
static inline td t8_sqrt(td a) { return (td){_mm256_sqrt_pd(a.lo), _mm256_sqrt_pd(a.hi)}; }
static inline td t8_k(double v) { return (td){_mm256_set1_pd(v), _mm256_set1_pd(v)}; }
static inline td t8_zero(void) { return (td){_mm256_setzero_pd(), _mm256_setzero_pd()}; }
static inline td t8_abs(td a) { return T8_BOTH(_mm256_andnot_pd, t8_k(-0.0), a); }
static inline td t8_neg(td a) { return T8_BOTH(_mm256_xor_pd, a, t8_k(-0.0)); }
static inline void t8_store(double *p, td a)
{
    _mm256_storeu_pd(p, a.lo);
    _mm256_storeu_pd(p + 4, a.hi);
}
#define t8_cmp(a, b, pred)                                                                     \
    ((tk){_mm256_cmp_pd((a).lo, (b).lo, (pred)), _mm256_cmp_pd((a).hi, (b).hi, (pred))})
static inline tk tk_and(tk a, tk b) { return T8_BOTH(_mm256_and_pd, a, b); }
static inline tk tk_andnot(tk a, tk b) { return T8_BOTH(_mm256_andnot_pd, a, b); } /* b without a */
static inline int tk_bits(tk a)
{
    return _mm256_movemask_pd(a.lo) | _mm256_movemask_pd(a.hi) << 4;
}
/* a ? b : c, lane by lane */
static inline td t8_pick(tk a, td b, td c)
{
    return (td){_mm256_blendv_pd(c.lo, b.lo, a.lo), _mm256_blendv_pd(c.hi, b.hi, a.hi)};
}
/* |a| with the sign of b */
static inline td t8_copysign(td a, td b)
{
    return T8_BOTH(_mm256_or_pd, t8_abs(a), T8_BOTH(_mm256_and_pd, t8_k(-0.0), b));
}
static inline tk tk_or(tk a, tk b) { return T8_BOTH(_mm256_or_pd, a, b); }
static inline tk tk_xor(tk a, tk b) { return T8_BOTH(_mm256_xor_pd, a, b); }
static inline bool tk_any(tk a)
{
    __m256d m = _mm256_or_pd(a.lo, a.hi);
    return !_mm256_testz_pd(m, m);
}
static inline tk tk_lanes(int bits)
{
    const __m256i bit = _mm256_setr_epi64x(1, 2, 4, 8);
    __m256i lo = _mm256_set1_epi64x(bits & 15), hi = _mm256_set1_epi64x(bits >> 4 & 15);
    return (tk){_mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(lo, bit), bit)),
                _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(hi, bit), bit))};
}
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
    /* the three reciprocals from one division, as torus.c's setup finds them */
    tk flat[3];
    td f[3];
    for (int a = 0; a < 3; a++) {
        flat[a] = t8_cmp(d[a], t8_zero(), _CMP_EQ_OQ);
        f[a] = t8_pick(flat[a], t8_k(1.0), d[a]);
    }
    td f01 = t8_mul(f[0], f[1]), all = t8_div(t8_k(1.0), t8_mul(f01, f[2]));
    td invs[3] = {t8_mul(t8_mul(f[1], f[2]), all), t8_mul(t8_mul(f[0], f[2]), all),
                  t8_mul(f01, all)};
    for (int a = 0; a < 3; a++) {
        tk out = t8_cmp(t8_abs(o[a]), t8_k(ext[a]), _CMP_GT_OQ);
        *keep = tk_andnot(tk_and(flat[a], out), *keep);
        td inv = invs[a];
        td ta = t8_mul(t8_sub(t8_k(-ext[a]), o[a]), inv);
        td tb = t8_mul(t8_sub(t8_k(ext[a]), o[a]), inv);
        tk swap = t8_cmp(ta, tb, _CMP_GT_OQ);
        td lo = t8_pick(swap, tb, ta), hi = t8_pick(swap, ta, tb);
        td n0 = t8_pick(t8_cmp(lo, *t0, _CMP_GT_OQ), lo, *t0);
        td n1 = t8_pick(t8_cmp(hi, *t1, _CMP_LT_OQ), hi, *t1);
        *t0 = t8_pick(flat[a], *t0, n0);
        *t1 = t8_pick(flat[a], *t1, n1);
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
    td nqb = t8_neg(qb);
    tk vertex = tk_and(t8_cmp(qa, t8_zero(), _CMP_GT_OQ),
                       tk_and(t8_cmp(t8_mul(t0, qa), nqb, _CMP_LT_OQ),
                              t8_cmp(nqb, t8_mul(t1, qa), _CMP_LT_OQ)));
    td least = t8_pick(vertex, t8_sub(t8_mul(qa, qc), t8_mul(qb, qb)),
                       t8_pick(t8_cmp(e0, e1, _CMP_LT_OQ), e0, e1));
    td bound = t8_pick(vertex, t8_mul(t8_k(outer), qa), t8_k(outer));
    return tk_and(keep, t8_cmp(least, bound, _CMP_NGT_UQ));
}

/* Where the search for a lane's first root got to in registers
 * (t8_first_root): no root at all, or the root x[k]; the other lanes are
 * left to torus_solve. */
typedef struct torus_first {
    int miss, root;
    double x[8];
} torus_first;

/* No lane decided yet. x is left unset: it is read only for the lanes of
 * root, for which t8_first_root has stored it (clearing it here made the
 * profile-guided build clear 80 bytes with rep stos on every call). */
static inline torus_first torus_first_none(void)
{
    torus_first f;
    f.miss = f.root = 0;
    return f;
}

/* roots_eval lane by lane (Horner's rule) */
static inline td t8_eval(const td *c, int degree, td x)
{
    td v = c[degree];
    for (int i = degree - 1; i >= 0; i--)
        v = t8_add(t8_mul(v, x), c[i]);
    return v;
}

/* roots_cubic_at and roots_quartic_at (core/roots.h) lane by lane */
static inline td t8_cubic_at(const td *c, td x)
{
    td x2 = t8_mul(x, x);
    return t8_add(t8_add(c[0], t8_mul(c[1], x)), t8_mul(x2, t8_add(c[2], t8_mul(c[3], x))));
}

static inline td t8_quartic_at(const td *c, td x)
{
    td x2 = t8_mul(x, x);
    td hi = t8_add(t8_add(c[2], t8_mul(c[3], x)), t8_mul(x2, c[4]));
    return t8_add(t8_add(c[0], t8_mul(c[1], x)), t8_mul(x2, hi));
}

/* roots_quartic_above (core/roots.h) for the lanes of `lanes`: those whose
 * quartic c provably stays above zero on [0, hi]. */
/* The quartic c's terms at hi (a[i] = c[i] hi^i) and the margin 1e-9
 * times the sum of their sizes, as roots_quartic_above and torus.c's
 * dips_below form them. */
static inline td t8_margin(const td *c, td hi, td a[5])
{
    td h2 = t8_mul(hi, hi);
    a[0] = c[0], a[1] = t8_mul(c[1], hi), a[2] = t8_mul(c[2], h2);
    a[3] = t8_mul(t8_mul(c[3], h2), hi), a[4] = t8_mul(t8_mul(c[4], h2), h2);
    td size = t8_abs(a[0]);
    for (int i = 1; i < 5; i++)
        size = t8_add(size, t8_abs(a[i]));
    return t8_mul(t8_k(1e-9), size);
}

static inline tk t8_above(const td *c, td hi, tk lanes)
{
    td a[5], m = t8_margin(c, hi, a);
    td b[5] = {a[0], t8_add(a[0], t8_mul(t8_k(0.25), a[1])),
               t8_add(t8_add(a[0], t8_mul(t8_k(0.5), a[1])), t8_mul(a[2], t8_k(1.0 / 6.0))),
               t8_add(t8_add(t8_add(a[0], t8_mul(t8_k(0.75), a[1])), t8_mul(t8_k(0.5), a[2])),
                      t8_mul(t8_k(0.25), a[3])),
               t8_add(t8_add(t8_add(t8_add(a[0], a[1]), a[2]), a[3]), a[4])};
    tk above = tk_and(lanes, t8_cmp(hi, t8_k(1e-4), _CMP_GE_OQ));
    for (int i = 0; i < 5; i++)
        above = tk_and(above, t8_cmp(b[i], m, _CMP_GT_OQ));
    return above;
}

/* convex_first (core/roots.c) for the lanes of act, from x, where p is
 * f, towards e: the lanes it finds without a root (it returns 0) join
 * *none, those with one (1) *root, the root in *found; the lanes it
 * leaves (-1) join neither. All lanes step together, each leaving the
 * loop where convex_first returns. */
static inline void t8_convex_first(const td *c, const td *dc, td x, td f, td e, tk act,
                                   tk *none, tk *root, td *found)
{
    const td zero = t8_zero(), one = t8_k(1.0), from = x;
    td sgn = t8_pick(t8_cmp(f, zero, _CMP_LT_OQ), t8_k(-1.0), one); /* of p where it starts */
    td df = t8_cubic_at(dc, x);
    for (int it = 0; it < 60 && tk_any(act); it++) {
        tk stop = tk_and(act, t8_cmp(t8_mul(sgn, df), zero, _CMP_NLT_UQ));
        *none = tk_or(*none, stop);
        act = tk_andnot(stop, act);
        td nx = t8_sub(x, t8_div(f, df));
        stop = tk_and(act, t8_cmp(nx, e, _CMP_NLT_UQ));
        *none = tk_or(*none, stop);
        act = tk_andnot(stop, act);
        td anx = t8_abs(nx);
        td scale = t8_pick(t8_cmp(anx, one, _CMP_GT_OQ), anx, one);
        tk conv = tk_and(act, t8_cmp(t8_abs(t8_sub(nx, x)), t8_mul(t8_k(1e-7), scale),
                                     _CMP_LE_OQ));
        act = tk_andnot(conv, act);
        conv = tk_and(conv, t8_cmp(nx, from, _CMP_GT_OQ)); /* else rounded onto its start */
        td nf = t8_quartic_at(c, nx), ndf = t8_cubic_at(dc, nx); /* p' at the next x */
        tk hit = tk_or(conv, tk_and(act, t8_cmp(nf, zero, _CMP_EQ_OQ)));
        *root = tk_or(*root, hit);
        *found = t8_pick(hit, nx, *found);
        act = tk_andnot(hit, act);
        act = tk_andnot(t8_cmp(t8_mul(sgn, nf), zero, _CMP_LT_OQ), act); /* bracketed */
        x = t8_pick(act, nx, x);
        f = t8_pick(act, nf, f);
        df = t8_pick(act, ndf, df);
    }
}

/* torus_solve's first steps for the lanes of `lanes`, with the quartic
 * c[0] + ... + c[3] x^3 + x^4 on (0, hi): roots_quartic_above, then
 * roots_quartic(c, 0, hi, .., 1) where it takes convex_first's path, from
 * 0 or from the first inflection, and on from the second
 * (past_first_piece) where the first piece has no root (core/roots.c),
 * with the same doubles in
 * the same order lane by lane, the lanes stepping together and each
 * leaving the loop where convex_first returns. Lanes whose search leaves
 * that path (the general search, a bracket, a root rounded onto its
 * start) are in neither out->miss nor out->root. */
static inline void t8_first_root(const td *cq, td hi, tk lanes, torus_first *out)
{
    const td zero = t8_zero(), one = t8_k(1.0);
    const td c[5] = {cq[0], cq[1], cq[2], cq[3], one}; /* torus_quartic's c[4] */
    tk above = t8_above(c, hi, lanes);
    /* the derivatives; convex_first from 0 where p bends towards zero
     * there (toward), or from p's first inflection where it bends away
     * from zero up to it (roots_quartic) */
    td dc[4] = {c[1], t8_mul(t8_k(2.0), c[2]), t8_mul(t8_k(3.0), c[3]), t8_mul(t8_k(4.0), c[4])};
    td ddc[3] = {dc[1], t8_mul(t8_k(2.0), dc[2]), t8_mul(t8_k(3.0), dc[3])};
    td f0 = t8_eval(c, 4, zero), found = zero;
    tk some = tk_andnot(above, tk_and(lanes, t8_cmp(ddc[2], zero, _CMP_NEQ_UQ)));
    some = tk_and(some, t8_cmp(f0, zero, _CMP_NEQ_UQ));
    out->miss |= tk_bits(above);
    if (!tk_any(some))
        return;
    tk pos = t8_cmp(f0, zero, _CMP_GT_OQ);
    td pp = t8_eval(ddc, 2, zero);
    tk toward = tk_andnot(tk_xor(pos, t8_cmp(pp, zero, _CMP_GT_OQ)), some);
    /* p's inflections in (0, hi): the roots of p'' by roots_quadratic */
    td disc = t8_sub(t8_mul(ddc[1], ddc[1]), t8_mul(t8_mul(t8_k(4.0), ddc[2]), ddc[0]));
    tk real = t8_cmp(disc, zero, _CMP_NLT_UQ);
    td q = t8_mul(t8_k(-0.5), t8_add(ddc[1], t8_copysign(t8_sqrt(disc), ddc[1])));
    td r0 = t8_div(q, ddc[2]), r1 = t8_div(ddc[0], q);
    tk two = t8_cmp(q, zero, _CMP_NEQ_UQ);
    tk swap = tk_and(two, t8_cmp(r0, r1, _CMP_GT_OQ));
    td lo_r = t8_pick(swap, r1, r0), hi_r = t8_pick(swap, r0, r1);
    tk in0 = tk_and(real, tk_and(t8_cmp(lo_r, zero, _CMP_GT_OQ), t8_cmp(lo_r, hi, _CMP_LT_OQ)));
    tk in1 = tk_and(tk_and(real, two),
                    tk_and(t8_cmp(hi_r, zero, _CMP_GT_OQ), t8_cmp(hi_r, hi, _CMP_LT_OQ)));
    tk bends = tk_or(in0, in1), both = tk_and(in0, in1);
    td bend = t8_pick(in0, lo_r, t8_pick(in1, hi_r, hi)); /* the first, or hi */
    tk away = tk_andnot(toward, tk_and(tk_and(some, bends), t8_cmp(pp, zero, _CMP_NEQ_UQ)));
    td x = t8_pick(away, bend, zero), from = x;
    td f = t8_pick(away, t8_eval(c, 4, bend), f0);
    td e = t8_pick(toward, bend, t8_pick(both, hi_r, hi));
    td pm = t8_eval(ddc, 2, t8_mul(t8_k(0.5), t8_add(from, e))); /* p'' inside the piece */
    tk act = tk_and(tk_or(toward, away), t8_cmp(f, zero, _CMP_NEQ_UQ));
    act = tk_andnot(tk_xor(t8_cmp(f, zero, _CMP_GT_OQ), pos), act);
    act = tk_and(act, t8_cmp(pm, zero, _CMP_NEQ_UQ));
    act = tk_andnot(tk_xor(t8_cmp(pm, zero, _CMP_GT_OQ), pos), act);
    if (!tk_any(act))
        return;
    /* no root past the piece either: no more inflections */
    tk last = tk_or(tk_andnot(bends, toward), tk_andnot(both, away));
    tk none = tk_andnot(act, act), root = none;
    t8_convex_first(c, dc, x, f, e, act, &none, &root, &found);
    /* past_first_piece (core/roots.c): on from p's second inflection where
     * the first piece, from 0, had no root and the one between the
     * inflections can have none */
    tk again = tk_and(none, tk_and(toward, both));
    if (tk_any(again)) {
        const td half = t8_k(0.5);
        td f2 = t8_eval(c, 4, hi_r);
        td bent = t8_eval(ddc, 2, t8_mul(half, t8_add(lo_r, hi_r)));
        td pm2 = t8_eval(ddc, 2, t8_mul(half, t8_add(hi_r, hi)));
        again = tk_and(again, tk_and(t8_cmp(f2, zero, _CMP_NEQ_UQ),
                                     tk_and(t8_cmp(bent, zero, _CMP_NEQ_UQ),
                                            t8_cmp(pm2, zero, _CMP_NEQ_UQ))));
        again = tk_andnot(tk_xor(t8_cmp(f2, zero, _CMP_GT_OQ), pos), again);
        again = tk_and(tk_xor(t8_cmp(bent, zero, _CMP_GT_OQ), pos), again);
        again = tk_andnot(tk_xor(t8_cmp(pm2, zero, _CMP_GT_OQ), pos), again);
        none = tk_andnot(again, none);
        t8_convex_first(c, dc, hi_r, f2, hi, again, &none, &root, &found);
        last = tk_or(last, again);
    }
    out->miss |= tk_bits(tk_and(last, none));
    out->root |= tk_bits(root);
    t8_store(out->x, found);
}

/* torus_blocks_at_once (torus.c) for the lanes of `lanes`, from the
 * quartic cq (its c[4] 1), the segment (t0, t1; hi long) and the entry
 * point's and the direction's y: the same doubles and floats lane by
 * lane. */
static inline int t8_blocks_at_once(const td *cq, td hi, td t0, td t1, td py, td uy,
                                    const ray8 *r, int lanes)
{
    const td zero = t8_zero();
    __m256 from = t8_narrow(t0), to = t8_narrow(t8_add(t1, t8_mul(t8_k(1e-9), t8_abs(t1))));
    lanes &= _mm256_movemask_ps(_mm256_cmp_ps(from, _mm256_loadu_ps(r->tmin), _CMP_GT_OQ)) &
             _mm256_movemask_ps(_mm256_cmp_ps(to, _mm256_loadu_ps(r->tmax), _CMP_LT_OQ));
    if (!lanes)
        return 0;
    td x = t8_div(t8_neg(py), uy);
    tk in = tk_and(t8_cmp(uy, zero, _CMP_NEQ_UQ), t8_cmp(x, zero, _CMP_GT_OQ));
    in = tk_and(in, t8_cmp(x, hi, _CMP_LT_OQ));
    /* dips_below */
    const td c[5] = {cq[0], cq[1], cq[2], cq[3], t8_k(1.0)};
    td a[5], m = t8_margin(c, hi, a);
    in = tk_and(in, tk_and(t8_cmp(cq[0], m, _CMP_GT_OQ),
                           t8_cmp(t8_eval(c, 4, x), t8_neg(m), _CMP_LT_OQ)));
    return lanes & tk_bits(in);
}

/* The rays of active against the torus's bounds: those whose segment
 * survives, with q[k] set for them; with first, the search for each one's
 * first root begun (t8_first_root); with at_once, the lanes
 * torus_blocks_at_once finds blocked put there and left out of the
 * search. */
static inline int torus8_setup(const struct torus *s, const ray8 *r, int active, torus_quartic *q,
                               torus_first *first, int *at_once)
{
    if (!active)
        return 0;
    double R = s->major, rm = s->minor;
    double ext[3] = {1.01 * (R + rm), 1.01 * rm, 1.01 * (R + rm)};
    td o[3] = {t8_sub(t8_load(r->ox), t8_k(s->center.x)),
               t8_sub(t8_load(r->oy), t8_k(s->center.y)),
               t8_sub(t8_load(r->oz), t8_k(s->center.z))};
    td d[3] = {t8_load(r->dx), t8_load(r->dy), t8_load(r->dz)};
    td dd = t8_dot(d, d), od = t8_dot(o, d), oo = t8_dot(o, o);
    tk keep = t8_cmp(t8_mul(od, od), t8_mul(dd, t8_sub(oo, t8_k(ext[0] * ext[0]))), _CMP_NLT_UQ);
    if (!(active & tk_bits(keep))) /* every ray passes by the ball: 18% of row 8's packets */
        return 0;
    td t0 = t8_load(r->tmin), t1 = t8_load(r->tmax);
    t8_clip(o, d, ext, &t0, &t1, &keep);
    double inner = R > rm ? (R - rm) * (R - rm) * 0.999 : 0.0, outer = (R + rm) * (R + rm) * 1.001;
    keep = t8_cylinders(o, d, t0, t1, inner, outer, keep);
    int live = active & tk_bits(keep);
    if (!live)
        return 0;
    td len = t8_sqrt(dd), il = t8_div(t8_k(1.0), len), u[3], p[3];
    for (int a = 0; a < 3; a++) {
        u[a] = t8_mul(d[a], il);
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
    td hi = t8_mul(t8_sub(t1, t0), len);
    int once = at_once ? t8_blocks_at_once(c, hi, t0, t1, p[1], u[1], r, live) : 0;
    if (at_once)
        *at_once = once;
    if (first)
        t8_first_root(c, hi, tk_lanes(live & ~once), first);
    double cv[4][8], t0v[8], t1v[8], lenv[8], hiv[8];
    double pyv[8], uyv[8];
    for (int i = 0; i < 4; i++)
        t8_store(cv[i], c[i]);
    t8_store(t0v, t0);
    t8_store(t1v, t1);
    t8_store(lenv, len);
    t8_store(hiv, hi);
    t8_store(pyv, p[1]);
    t8_store(uyv, u[1]);
    for (int m = live; m; m &= m - 1) {
        int j = __builtin_ctz((unsigned)m);
        q[j] = (torus_quartic){{cv[0][j], cv[1][j], cv[2][j], cv[3][j], 1.0},
                               t0v[j], lenv[j], hiv[j], t1v[j], pyv[j], uyv[j]};
    }
    return live;
}

/* Whether lane k's ray r meets its torus within its range: from where
 * t8_first_root left it, or by torus_solve (into hit unless NULL). */
static inline bool torus8_lane(const torus_first *f, int k, const torus_quartic *q, const ray *r,
                               shape_hit *hit)
{
    if (f->miss >> k & 1)
        return false;
    if (f->root >> k & 1) {
        float t = (float)(q->t0 + f->x[k] / q->len);
        if (ray_in_range(r, t)) {
            if (hit)
                hit->t = t; /* part 0 */
            return true;
        }
    }
    return torus_solve(q, r, hit);
}

/* torus_intersect against the rays of active, each within its own range. */
static inline int torus8_hit(const struct torus *s, const ray8 *r, int active, shape_hit *hit)
{
    torus_quartic q[8];
    torus_first first = torus_first_none();
    int live = torus8_setup(s, r, active, q, &first, NULL);
    int found = 0;
    for (int m = live; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray one = ray8_get(r, k);
        hit[k] = (shape_hit){0};
        if (torus8_lane(&first, k, &q[k], &one, &hit[k]))
            found |= 1 << k;
    }
    return found;
}

/* torus_occluded for the rays of active: those blocked. */
static inline int torus8_occluded(const struct torus *s, const ray8 *r, int active)
{
    torus_quartic q[8];
    torus_first first = torus_first_none();
    int once = 0, live = torus8_setup(s, r, active, q, &first, &once);
    int blocked = once;
    for (int m = live & ~once; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray one = ray8_get(r, k);
        blocked |= torus8_lane(&first, k, &q[k], &one, NULL) << k;
    }
    return blocked;
}

#endif
