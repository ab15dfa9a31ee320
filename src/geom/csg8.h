/* csg8: a csg against eight rays at once (csg.h). Each leaf's bounds
 * test, and the span of a sphere, box or cylinder leaf (carried by its
 * own transform where it has one), are worked out for the eight rays in
 * vector registers: the first round of crossings csg_intersect gathers.
 * Each lane does the one-ray routines' operations in the same order
 * (aabb_hit, mat4_point, mat4_vector, sphere_span, box_span,
 * cylinder_span; no fused multiply-adds), so its spans are the same to
 * the bit; branches become masks. The rays whose crossings are all such
 * spans, in a tree with a table, are classified together (csg8_classify,
 * the hit csg.c's classification finds). Any other leaf is asked ray by
 * ray (shape_crossings), and those rays' crossings are classified by
 * csg.c's one routine (csg_hit_lane). For translation units compiled with
 * AVX2 (geom/shape8_<isa>.c). */
#ifndef GLINT_GEOM_CSG8_H
#define GLINT_GEOM_CSG8_H

#include <immintrin.h>
#include "geom/csg.h"
#include "geom/shape8.h"

/* glibc's fminf, which the spans call: the other operand where one is
 * NaN, the first where they compare equal (-0 and +0 keep their order). */
static inline __m256 fmin8(__m256 x, __m256 y)
{
    return _mm256_blendv_ps(_mm256_min_ps(y, x), y, _mm256_cmp_ps(x, x, _CMP_UNORD_Q));
}

/* fmaxf likewise. */
static inline __m256 fmax8(__m256 x, __m256 y)
{
    return _mm256_blendv_ps(_mm256_max_ps(y, x), y, _mm256_cmp_ps(x, x, _CMP_UNORD_Q));
}

/* c ? b : a, lane by lane, for the ternaries of the one-ray code. */
static inline __m256 pick8(__m256 c, __m256 b, __m256 a) { return _mm256_blendv_ps(a, b, c); }

/* aabb_hit(b, o, inv, tmin, INFINITY): the rays whose slab interval
 * reaches their tmin (minf and maxf are min_ps and max_ps exactly). */
static inline int aabb8_hit(aabb b, const __m256 *o, const __m256 *inv, __m256 tmin)
{
    const float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    __m256 t0[3], t1[3];
    for (int a = 0; a < 3; a++) {
        t0[a] = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(lo[a]), o[a]), inv[a]);
        t1[a] = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(hi[a]), o[a]), inv[a]);
    }
    __m256 near = _mm256_max_ps(_mm256_min_ps(t0[1], t1[1]), _mm256_min_ps(t0[2], t1[2]));
    near = _mm256_max_ps(_mm256_max_ps(_mm256_min_ps(t0[0], t1[0]), near), tmin);
    __m256 far = _mm256_min_ps(_mm256_max_ps(t0[1], t1[1]), _mm256_max_ps(t0[2], t1[2]));
    far = _mm256_min_ps(_mm256_max_ps(t0[0], t1[0]), far);
    const float grow = 1.0f + 2.0f * 3.0f * 0x1p-24f / (1.0f - 3.0f * 0x1p-24f);
    far = _mm256_min_ps(_mm256_mul_ps(far, _mm256_set1_ps(grow)), _mm256_set1_ps(INFINITY));
    return _mm256_movemask_ps(_mm256_cmp_ps(near, far, _CMP_LE_OQ));
}

/* The rays in leaf l's space (csg.c's leaf_ray): row by row of its
 * inverse, ((a0 x + a1 y) + a2 z) + a3 as mat4_point adds them. */
static inline void leaf8_rays(const csg_leaf *l, const __m256 *o, const __m256 *d, __m256 *lo,
                              __m256 *ld)
{
    for (int i = 0; i < 3; i++) {
        if (!l->moved) {
            lo[i] = o[i], ld[i] = d[i];
            continue;
        }
        const float *a = l->x.inv.m[i];
        __m256 a0 = _mm256_set1_ps(a[0]), a1 = _mm256_set1_ps(a[1]), a2 = _mm256_set1_ps(a[2]);
        lo[i] = _mm256_add_ps(dot8(a0, a1, a2, o[0], o[1], o[2]), _mm256_set1_ps(a[3]));
        ld[i] = dot8(a0, a1, a2, d[0], d[1], d[2]);
    }
}

/* sphere_span: the rays whose line meets the sphere, with the entry's
 * and the exit's t. */
static inline int sphere8_span(const struct sphere *s, const __m256 *o, const __m256 *d,
                               __m256 *tin, __m256 *tout)
{
    const __m256 zero = _mm256_setzero_ps(), sign = _mm256_set1_ps(-0.0f);
    __m256 fx = _mm256_sub_ps(o[0], _mm256_set1_ps(s->center.x));
    __m256 fy = _mm256_sub_ps(o[1], _mm256_set1_ps(s->center.y));
    __m256 fz = _mm256_sub_ps(o[2], _mm256_set1_ps(s->center.z));
    __m256 a = dot8(d[0], d[1], d[2], d[0], d[1], d[2]);
    __m256 b = _mm256_xor_ps(dot8(fx, fy, fz, d[0], d[1], d[2]), sign);
    __m256 ba = _mm256_div_ps(b, a);
    __m256 lx = _mm256_add_ps(fx, _mm256_mul_ps(d[0], ba));
    __m256 ly = _mm256_add_ps(fy, _mm256_mul_ps(d[1], ba));
    __m256 lz = _mm256_add_ps(fz, _mm256_mul_ps(d[2], ba));
    __m256 rr = _mm256_set1_ps(s->radius * s->radius);
    __m256 disc = _mm256_mul_ps(a, _mm256_sub_ps(rr, dot8(lx, ly, lz, lx, ly, lz)));
    int met = ~_mm256_movemask_ps(_mm256_cmp_ps(disc, zero, _CMP_LT_OQ)) & 0xff;
    __m256 c = _mm256_sub_ps(dot8(fx, fy, fz, fx, fy, fz), rr);
    __m256 q = _mm256_add_ps(b, copysign8(_mm256_sqrt_ps(disc), b));
    __m256 q0 = _mm256_cmp_ps(q, zero, _CMP_EQ_OQ); /* q != 0 ? ... : 0 */
    __m256 t0 = _mm256_andnot_ps(q0, _mm256_div_ps(c, q));
    __m256 t1 = _mm256_andnot_ps(q0, _mm256_div_ps(q, a));
    *tin = fmin8(t0, t1);
    *tout = fmax8(t0, t1);
    return met;
}

/* box_span likewise, with the faces in pin, pout: the slabs in the same
 * order, a lane parallel to a slab missing when outside it. */
static inline int box8_span(const struct box *s, const __m256 *o, const __m256 *d, __m256 *tin,
                            __m256 *tout, __m256 *pin, __m256 *pout)
{
    const __m256 zero = _mm256_setzero_ps();
    const float lo[3] = {s->lo.x, s->lo.y, s->lo.z}, hi[3] = {s->hi.x, s->hi.y, s->hi.z};
    __m256 tnear = _mm256_set1_ps(-INFINITY), tfar = _mm256_set1_ps(INFINITY);
    __m256 nf = _mm256_set1_ps(-1.0f), ff = nf, miss = zero;
    for (int a = 0; a < 3; a++) {
        __m256 l = _mm256_set1_ps(lo[a]), h = _mm256_set1_ps(hi[a]);
        __m256 flat = _mm256_cmp_ps(d[a], zero, _CMP_EQ_OQ);
        __m256 out = _mm256_or_ps(_mm256_cmp_ps(o[a], l, _CMP_LT_OQ),
                                  _mm256_cmp_ps(o[a], h, _CMP_GT_OQ));
        miss = _mm256_or_ps(miss, _mm256_and_ps(flat, out));
        __m256 t0 = _mm256_div_ps(_mm256_sub_ps(l, o[a]), d[a]);
        __m256 t1 = _mm256_div_ps(_mm256_sub_ps(h, o[a]), d[a]);
        __m256 f0 = _mm256_set1_ps((float)(2 * a)), f1 = _mm256_set1_ps((float)(2 * a + 1));
        __m256 swap = _mm256_cmp_ps(t0, t1, _CMP_GT_OQ);
        __m256 tn = pick8(swap, t1, t0), tf = pick8(swap, t0, t1);
        __m256 fn = pick8(swap, f1, f0), fb = pick8(swap, f0, f1);
        __m256 up = _mm256_andnot_ps(flat, _mm256_cmp_ps(tn, tnear, _CMP_GT_OQ));
        tnear = pick8(up, tn, tnear);
        nf = pick8(up, fn, nf);
        __m256 down = _mm256_andnot_ps(flat, _mm256_cmp_ps(tf, tfar, _CMP_LT_OQ));
        tfar = pick8(down, tf, tfar);
        ff = pick8(down, fb, ff);
    }
    miss = _mm256_or_ps(miss, _mm256_cmp_ps(tnear, tfar, _CMP_NLE_UQ)); /* !(tnear <= tfar) */
    miss = _mm256_or_ps(miss, _mm256_cmp_ps(_mm256_min_ps(nf, ff), zero, _CMP_LT_OQ));
    *tin = tnear, *tout = tfar, *pin = nf, *pout = ff;
    return ~_mm256_movemask_ps(miss) & 0xff;
}

/* cylinder_span's side: the infinite cylinder's roots into *t0, *t1
 * where a > 0, the lanes that miss it into *miss. */
static inline void cylinder8_side(const struct cylinder *s, __m256 ox, __m256 oz,
                                  const __m256 *d, __m256 *t0, __m256 *t1, __m256 *miss)
{
    const __m256 zero = _mm256_setzero_ps(), sign = _mm256_set1_ps(-0.0f);
    __m256 rr = _mm256_set1_ps(s->radius * s->radius);
    __m256 a = dot2_8(d[0], d[2], d[0], d[2]);
    __m256 side = _mm256_cmp_ps(a, zero, _CMP_GT_OQ);
    __m256 b = _mm256_xor_ps(dot2_8(ox, oz, d[0], d[2]), sign);
    __m256 ba = _mm256_div_ps(b, a);
    __m256 lx = _mm256_add_ps(ox, _mm256_mul_ps(d[0], ba));
    __m256 lz = _mm256_add_ps(oz, _mm256_mul_ps(d[2], ba));
    __m256 disc = _mm256_mul_ps(a, _mm256_sub_ps(rr, dot2_8(lx, lz, lx, lz)));
    __m256 cc = dot2_8(ox, oz, ox, oz), c = _mm256_sub_ps(cc, rr);
    __m256 q = _mm256_add_ps(b, copysign8(_mm256_sqrt_ps(disc), b));
    __m256 ra = _mm256_andnot_ps(_mm256_cmp_ps(q, zero, _CMP_EQ_OQ), _mm256_div_ps(c, q));
    __m256 rb = _mm256_div_ps(q, a);
    *t0 = pick8(side, fmin8(ra, rb), *t0);
    *t1 = pick8(side, fmax8(ra, rb), *t1);
    __m256 off = pick8(side, _mm256_cmp_ps(disc, zero, _CMP_LT_OQ),
                       _mm256_cmp_ps(cc, rr, _CMP_GT_OQ)); /* a <= 0: outside the disc */
    *miss = _mm256_or_ps(*miss, off);
}

/* cylinder_span likewise: the side, then the slab of the caps, each end
 * keeping the part that bounds it. */
static inline int cylinder8_span(const struct cylinder *s, const __m256 *o, const __m256 *d,
                                 __m256 *tin, __m256 *tout, __m256 *pin, __m256 *pout)
{
    const __m256 zero = _mm256_setzero_ps(), sign = _mm256_set1_ps(-0.0f);
    __m256 ox = _mm256_sub_ps(o[0], _mm256_set1_ps(s->base.x));
    __m256 oy = _mm256_sub_ps(o[1], _mm256_set1_ps(s->base.y));
    __m256 oz = _mm256_sub_ps(o[2], _mm256_set1_ps(s->base.z));
    __m256 t0 = _mm256_set1_ps(-INFINITY), t1 = _mm256_set1_ps(INFINITY), miss = zero;
    cylinder8_side(s, ox, oz, d, &t0, &t1, &miss);
    __m256 height = _mm256_set1_ps(s->height), p0 = zero, p1 = zero;
    __m256 ends = _mm256_cmp_ps(d[1], zero, _CMP_NEQ_UQ);
    __m256 ya = _mm256_div_ps(_mm256_xor_ps(oy, sign), d[1]);
    __m256 yb = _mm256_div_ps(_mm256_sub_ps(height, oy), d[1]);
    __m256 swap = _mm256_cmp_ps(ya, yb, _CMP_GT_OQ);
    __m256 one = _mm256_set1_ps(1.0f), two = _mm256_set1_ps(2.0f);
    __m256 lo = pick8(swap, yb, ya), hi = pick8(swap, ya, yb);
    __m256 plo = pick8(swap, two, one), phi = pick8(swap, one, two);
    __m256 up = _mm256_and_ps(ends, _mm256_cmp_ps(lo, t0, _CMP_GT_OQ));
    __m256 down = _mm256_and_ps(ends, _mm256_cmp_ps(hi, t1, _CMP_LT_OQ));
    t0 = pick8(up, lo, t0), p0 = pick8(up, plo, p0);
    t1 = pick8(down, hi, t1), p1 = pick8(down, phi, p1);
    __m256 beside = _mm256_or_ps(_mm256_cmp_ps(oy, zero, _CMP_LT_OQ),
                                 _mm256_cmp_ps(oy, height, _CMP_GT_OQ));
    miss = _mm256_or_ps(miss, _mm256_andnot_ps(ends, beside));
    miss = _mm256_or_ps(miss, _mm256_cmp_ps(t0, t1, _CMP_NLE_UQ)); /* !(t0 <= t1) */
    *tin = t0, *tout = t1, *pin = p0, *pout = p1;
    return ~_mm256_movemask_ps(miss) & 0xff;
}

/* Leaf l against the rays of active (o, d, inv: theirs in the csg's
 * space, tmin their start): the first round of crossings csg_hit_lane
 * reads (csg.h). */
static inline void csg8_leaf(const csg_leaf *l, const __m256 *o, const __m256 *d,
                             const __m256 *inv, __m256 tmin, int active, csg_leaf8 *out)
{
    shape_kind kind = l->shape.kind;
    out->bounded = (uint8_t)(active & aabb8_hit(l->bounds, o, inv, tmin));
    out->spanned = out->met = 0;
    if (!out->bounded || (kind != SHAPE_SPHERE && kind != SHAPE_BOX && kind != SHAPE_CYLINDER))
        return;
    __m256 lo[3], ld[3], tin, tout, pin = _mm256_setzero_ps(), pout = pin;
    leaf8_rays(l, o, d, lo, ld);
    const shape *sh = &l->shape;
    int met;
    if (kind == SHAPE_SPHERE)
        met = sphere8_span(&sh->sphere, lo, ld, &tin, &tout);
    else if (kind == SHAPE_BOX)
        met = box8_span(&sh->box, lo, ld, &tin, &tout, &pin, &pout);
    else
        met = cylinder8_span(&sh->cylinder, lo, ld, &tin, &tout, &pin, &pout);
    out->spanned = out->bounded;
    out->met = (uint8_t)(out->bounded & met);
    _mm256_storeu_ps(out->tin, tin);
    _mm256_storeu_ps(out->tout, tout);
    _mm256_storeu_si256((__m256i *)out->pin, _mm256_cvttps_epi32(pin));
    _mm256_storeu_si256((__m256i *)out->pout, _mm256_cvttps_epi32(pout));
}

/* Every leaf against the rays of active. Returns the rays that may cross
 * a leaf's boundary: a ray that meets no leaf's bounds, or only spans it
 * misses, has no crossing to classify, and so no hit. */
static inline int csg8_spans(const csg *c, const ray8 *r, int active, csg_spans8 *pre)
{
    rays8 rs = rays8_load(r);
    const __m256 one = _mm256_set1_ps(1.0f);
    __m256 o[3] = {rs.ox, rs.oy, rs.oz}, d[3] = {rs.dx, rs.dy, rs.dz};
    __m256 inv[3] = {_mm256_div_ps(one, d[0]), _mm256_div_ps(one, d[1]), _mm256_div_ps(one, d[2])};
    int crosses = 0;
    for (int i = 0; i < c->nleaves; i++) {
        csg_leaf8 *l = &pre->leaf[i];
        csg8_leaf(&c->leaves[i], o, d, inv, rs.tmin, active, l);
        crosses |= (l->bounded & ~l->spanned) | l->met;
    }
    return crosses;
}

/* The rays of m whose crossings are all in pre, as spans in order (tin <=
 * tout, no NaN), of a tree with a table (csg.h): every leaf their bounds
 * meet is spanned; and whose tmax is a number. csg8_classify takes them. */
static inline int csg8_spanned(const csg *c, const ray8 *r, const csg_spans8 *pre, int m)
{
    if (c->nleaves > CSG_TABLE_LEAVES)
        return 0;
    __m256 tmax = _mm256_loadu_ps(r->tmax);
    m &= _mm256_movemask_ps(_mm256_cmp_ps(tmax, tmax, _CMP_ORD_Q));
    for (int i = 0; i < c->nleaves && m; i++) {
        const csg_leaf8 *l = &pre->leaf[i];
        m &= ~(l->bounded & ~l->spanned);
        if (l->met)
            m &= ~l->met | _mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(l->tin),
                                                            _mm256_loadu_ps(l->tout), _CMP_LE_OQ));
    }
    return m;
}

/* The tree's table (csg.h) at each lane's set of leaves (bit i: inside
 * leaf i): all-ones lanes where the point is inside the csg. */
static inline __m256i csg8_answer(const csg *c, __m256i bits)
{
    __m256i table = _mm256_loadu_si256((const __m256i *)c->table); /* bit s of word s >> 5 */
    __m256i word = _mm256_permutevar8x32_epi32(table, _mm256_srli_epi32(bits, 5));
    __m256i bit = _mm256_srlv_epi32(word, _mm256_and_si256(bits, _mm256_set1_epi32(31)));
    __m256i one = _mm256_set1_epi32(1);
    return _mm256_cmpeq_epi32(_mm256_and_si256(bit, one), one);
}

/* The crossings of the rays of csg8_classify's lanes, leaf by leaf: the
 * spans' entries (valid in enters, after tmin) and exits (in exits), and
 * the rays inside each leaf at tmin (start). */
typedef struct csg8_crossings {
    __m256 tin[CSG_TABLE_LEAVES], tout[CSG_TABLE_LEAVES];
    __m256i enters[CSG_TABLE_LEAVES], exits[CSG_TABLE_LEAVES], start[CSG_TABLE_LEAVES];
} csg8_crossings;

/* Of the crossings at the hits' t (best) on the rays of found, the cause
 * csg.c picks (cause, event_hit), each ray's hit made from it. was: the
 * tree's answer at tmin, all-ones lanes inside. */
static inline void csg8_cause(const csg *c, const csg_spans8 *pre, const csg8_crossings *x,
                              __m256 best, __m256i was, int found, shape_hit *hit)
{
    const __m256i ones = _mm256_set1_epi32(-1);
    __m256i first = ones, made = ones, any = _mm256_setzero_si256(), makes = any;
    __m256 first_t = best, made_t = best; /* the cause's own t: -0 and +0 are one t */
    for (int e = 0; e < 2 * c->nleaves; e++) {
        int j = e >> 1;
        __m256i valid = e & 1 ? x->exits[j] : x->enters[j];
        __m256 t = e & 1 ? x->tout[j] : x->tin[j];
        __m256i at = _mm256_and_si256(
            valid, _mm256_castps_si256(_mm256_cmp_ps(t, best, _CMP_EQ_OQ)));
        /* the answer after it is the one at tmin's opposite: it makes the
         * change where entering (it enters, or leaves a flipped leaf) is
         * becoming inside */
        bool enters_solid = !(e & 1) != c->leaves[j].flip;
        __m256i make = _mm256_and_si256(at, enters_solid ? _mm256_xor_si256(was, ones) : was);
        __m256i code = _mm256_set1_epi32(e);
        __m256i now_first = _mm256_andnot_si256(any, at);
        __m256i now_made = _mm256_andnot_si256(makes, make);
        first = _mm256_blendv_epi8(first, code, now_first);
        made = _mm256_blendv_epi8(made, code, now_made);
        first_t = _mm256_blendv_ps(first_t, t, _mm256_castsi256_ps(now_first));
        made_t = _mm256_blendv_ps(made_t, t, _mm256_castsi256_ps(now_made));
        any = _mm256_or_si256(any, at);
        makes = _mm256_or_si256(makes, make);
    }
    int32_t cause[8];
    _mm256_storeu_si256((__m256i *)cause, _mm256_blendv_epi8(first, made, makes));
    float tb[8];
    _mm256_storeu_ps(tb, _mm256_blendv_ps(first_t, made_t, _mm256_castsi256_ps(makes)));
    for (int m = found; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m), j = cause[k] >> 1;
        const csg_leaf8 *l = &pre->leaf[j];
        hit[k] = (shape_hit){0};
        hit[k].t = tb[k];
        hit[k].part = cause[k] & 1 ? l->pout[k] : l->pin[k];
        hit[k].leaf = j;
    }
}

/* csg_hit_lane's classification (csg.c: rounds) for the rays of lanes,
 * which csg8_spanned keeps, all at once. Their crossings are the spans'
 * entries and exits after tmin; csg.c sorts them by t and walks them,
 * and the hit is the first t after which the tree's answer differs from
 * its answer at tmin. The set of leaves a ray is inside after t depends
 * only on which crossings lie at or before t, so each crossing's t is
 * tried as it stands, and the least t that changes the answer (below
 * tmax) is the hit, with csg.c's cause (csg8_cause). */
static inline int csg8_classify(const csg *c, const ray8 *r, const csg_spans8 *pre, int lanes,
                                shape_hit *hit)
{
    const __m256i zero = _mm256_setzero_si256(), ones = _mm256_set1_epi32(-1);
    __m256 t0 = _mm256_loadu_ps(r->tmin), best = _mm256_loadu_ps(r->tmax);
    csg8_crossings x;
    __m256i bits0 = zero;
    int n = c->nleaves;
    for (int i = 0; i < n; i++) {
        const csg_leaf8 *l = &pre->leaf[i];
        __m256i met = _mm256_castps_si256(packet_lanes(l->met & lanes));
        x.tin[i] = _mm256_loadu_ps(l->tin), x.tout[i] = _mm256_loadu_ps(l->tout);
        __m256i later = _mm256_castps_si256(_mm256_cmp_ps(x.tin[i], t0, _CMP_GT_OQ));
        x.enters[i] = _mm256_and_si256(met, later);
        x.exits[i] = _mm256_and_si256(
            met, _mm256_castps_si256(_mm256_cmp_ps(x.tout[i], t0, _CMP_GT_OQ)));
        x.start[i] = _mm256_andnot_si256(later, x.exits[i]); /* inside at tmin */
        bits0 = _mm256_or_si256(bits0, _mm256_and_si256(x.start[i], _mm256_set1_epi32(1 << i)));
    }
    __m256i was = csg8_answer(c, bits0);
    /* each crossing in csg.c's order (leaf j's entry, then its exit) */
    for (int e = 0; e < 2 * n; e++) {
        int j = e >> 1;
        __m256i valid = e & 1 ? x.exits[j] : x.enters[j];
        if (_mm256_testz_si256(valid, valid))
            continue;
        __m256 t = e & 1 ? x.tout[j] : x.tin[j];
        __m256i bits = zero;
        for (int i = 0; i < n; i++) {
            __m256i in = _mm256_blendv_epi8(
                x.start[i], ones,
                _mm256_and_si256(x.enters[i],
                                 _mm256_castps_si256(_mm256_cmp_ps(x.tin[i], t, _CMP_LE_OQ))));
            in = _mm256_andnot_si256(
                _mm256_and_si256(x.exits[i],
                                 _mm256_castps_si256(_mm256_cmp_ps(x.tout[i], t, _CMP_LE_OQ))),
                in);
            bits = _mm256_or_si256(bits, _mm256_and_si256(in, _mm256_set1_epi32(1 << i)));
        }
        __m256i change = _mm256_andnot_si256(_mm256_cmpeq_epi32(csg8_answer(c, bits), was), valid);
        change = _mm256_and_si256(
            change, _mm256_castps_si256(_mm256_cmp_ps(t, best, _CMP_LT_OQ)));
        best = _mm256_blendv_ps(best, t, _mm256_castsi256_ps(change));
    }
    int found = lanes & _mm256_movemask_ps(_mm256_cmp_ps(best, _mm256_loadu_ps(r->tmax),
                                                         _CMP_LT_OQ));
    if (found)
        csg8_cause(c, pre, &x, best, was, found, hit);
    return found;
}

/* csg_intersect against the rays of active: the spans at once, then the
 * classification of the rays whose crossings are all spans, at once, and
 * of each other ray that crosses a leaf. */
static inline int csg8_hit(const csg *c, const ray8 *r, int active, shape_hit *hit)
{
    csg_spans8 pre;
    int crosses = csg8_spans(c, r, active, &pre), spanned = csg8_spanned(c, r, &pre, crosses);
    int found = spanned ? csg8_classify(c, r, &pre, spanned, hit) : 0;
    for (int m = spanned & ~found; m; m &= m - 1)
        hit[__builtin_ctz((unsigned)m)] = (shape_hit){0};
    for (int m = crosses & ~spanned; m; m &= m - 1) {
        int k = __builtin_ctz((unsigned)m);
        ray one = ray8_get(r, k);
        hit[k] = (shape_hit){0};
        if (csg_hit_lane(c, &one, &pre, k, &hit[k]))
            found |= 1 << k;
    }
    return found;
}

/* shape_occluded for a csg, which is whether it is hit at all. */
static inline int csg8_occluded(const csg *c, const ray8 *r, int active)
{
    shape_hit h[8];
    return csg8_hit(c, r, active, h);
}

/* Defines csg8_hit_<isa> and csg8_occluded_<isa>. */
#define CSG8_KERNELS(isa)                                                                      \
    int csg8_hit_##isa(const csg *c, const ray8 *r, int active, shape_hit *hit)               \
    {                                                                                          \
        return csg8_hit(c, r, active, hit);                                                    \
    }                                                                                          \
    int csg8_occluded_##isa(const csg *c, const ray8 *r, int active)                           \
    {                                                                                          \
        return csg8_occluded(c, r, active);                                                    \
    }

#endif
