#include "split.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "bvh.h"
#include "core/cpus.h"

/* The order median_split sorts by: the centre on axis (the float's bits
 * made to sort as integers, so NaN has a place too), then the index, which
 * sets every tie: the two halves are the same whatever order the
 * primitives come in. */
static inline uint64_t median_key(const primref *r, int axis)
{
    float c = ref_center(r, axis);
    uint32_t u;
    memcpy(&u, &c, sizeof u);
    u = u & 0x80000000u ? ~u : u | 0x80000000u;
    return (uint64_t)u << 32 | (uint32_t)r->id;
}

/* Puts the primitives of the lower half by median_key in [lo, mid) and
 * the others in [mid, hi), mid the middle (quickselect); the fallback when
 * binning cannot separate the centres. */
void split_median(split_ctx *b, int lo, int hi, int axis, int *mid)
{
    primref *refs = b->refs;
    int k = (lo + hi) / 2, l = lo, r = hi - 1;
    while (l < r) {
        uint64_t pivot = median_key(&refs[(l + r) / 2], axis);
        int i = l, j = r;
        while (i <= j) {
            while (median_key(&refs[i], axis) < pivot)
                i++;
            while (median_key(&refs[j], axis) > pivot)
                j--;
            if (i <= j) {
                primref t = refs[i];
                refs[i++] = refs[j];
                refs[j--] = t;
            }
        }
        if (k <= j)
            r = j;
        else if (k >= i)
            l = i;
        else
            break;
    }
    *mid = k;
}

/* The box and the centre bounds of [lo, hi). */
void split_bounds(const split_ctx *b, int lo, int hi, box4 *box, cbox *cb)
{
    box4 bx = box4_empty();
    cbox c = cbox_empty();
    for (int i = lo; i < hi; i++) {
        box4 r = box4_load(&b->refs[i]);
        bx = box4_union(bx, r);
        c = cbox_grow(c, box4_center(r));
    }
    *box = bx;
    *cb = c;
}

/* The centre bounds of the parts below and above, and the plane. */
typedef struct part_acc {
    v4 lmin, lmax, umin, umax;
    v4 split;
    int axis;
} part_acc;

/* Whether r goes below the split, its centre added to that side's
 * bounds without a branch: c + -0 is c (whatever its sign), c + inf is
 * inf and c + -inf is -inf, which leave a minimum and a maximum as they
 * were; so adding one or the other selects. */
__attribute__((always_inline)) static inline int part_side(void *acc, const primref *r)
{
#define I_ INFINITY
    static const float add[2][4][4] __attribute__((aligned(16))) = {
        {{I_, I_, I_, I_}, {-I_, -I_, -I_, -I_}, {-0.f, -0.f, -0.f, -0.f}, {-0.f, -0.f, -0.f, -0.f}},
        {{-0.f, -0.f, -0.f, -0.f}, {-0.f, -0.f, -0.f, -0.f}, {I_, I_, I_, I_}, {-I_, -I_, -I_, -I_}}};
#undef I_
    part_acc *p = acc;
    v4 c = box4_center(box4_load(r));
    int below = (v4_lt(c, p->split) >> p->axis) & 1;
    const float(*t)[4] = add[below];
    p->lmin = v4_min(v4_add(c, v4_load(t[0])), p->lmin);
    p->lmax = v4_max(v4_add(c, v4_load(t[1])), p->lmax);
    p->umin = v4_min(v4_add(c, v4_load(t[2])), p->umin);
    p->umax = v4_max(v4_add(c, v4_load(t[3])), p->umax);
    return below;
}

int split_partition(split_ctx *b, int lo, int hi, int axis, float split, cbox *below,
                    cbox *above)
{
#if defined(GLINT_WIDE_KERNELS)
    if (b->avx2)
        return split_partition_avx2(b, lo, hi, axis, split, below, above);
#endif
    part_acc p = {v4_splat(FLT_MAX), v4_splat(-FLT_MAX), v4_splat(FLT_MAX), v4_splat(-FLT_MAX),
                  v4_splat(split), axis};
    int mid = split_partition_by(b->refs, lo, hi, &p, part_side);
    *below = (cbox){p.lmin, p.lmax};
    *above = (cbox){p.umin, p.umax};
    return mid;
}

/* Primitive counts and bounds per bin, on each of the three axes: lane 3
 * of a bin's lo counts its primitives, exactly as floats up to 2^24 (a
 * pass over more primitives bins them BIN_CHUNK at a time and keeps the
 * counts in n, `counted`). */
typedef struct bins {
    int nbins;
    bool counted;
    box4 box[3][BINS] __attribute__((aligned(32)));
    int n[3][BINS];
} bins;

#define BIN_CHUNK (1 << 23)

/* The count of bin k of axis a. */
static inline int bin_count(const bins *bn, int a, int k)
{
    return bn->counted ? bn->n[a][k] : (int)v4_w(bn->box[a][k].lo);
}

/* One pass over [lo, hi) fills the bins of all three axes (bin k of axis a
 * holds the centres in [cmin + k / scale, cmin + (k + 1) / scale)); bin k
 * of a centre is (c - cmin) * scale, truncated, in [0, nbins - 1], NaN (a
 * zero extent's 0 * inf) going to 0. */
/* The primitives of refs[lo, hi) added to the first nb bins of each axis,
 * one at a time (split_bin_avx2 adds them as this does, two at a time). */
static void bin_range(const primref *refs, int lo, int hi, v4 cmin, v4 scale, int nb,
                      box4 (*box)[BINS])
{
    v4 top = v4_splat((float)(nb - 1)), one = v4_set(0.0f, 0.0f, 0.0f, 1.0f);
    for (int i = lo; i < hi; i++) {
        box4 r = box4_load(&refs[i]);
        v4 f = v4_mul(v4_sub(box4_center(r), cmin), scale);
        f = v4_min(v4_max(f, v4_splat(0.0f)), top); /* max gives 0 for NaN */
        int k[3];
        v4_trunc3(f, k);
        box4 *b0 = &box[0][k[0]], *b1 = &box[1][k[1]], *b2 = &box[2][k[2]];
        b0->lo = v4_add(v4_min(b0->lo, r.lo), one);
        b0->nhi = v4_min(b0->nhi, r.nhi);
        b1->lo = v4_add(v4_min(b1->lo, r.lo), one);
        b1->nhi = v4_min(b1->nhi, r.nhi);
        b2->lo = v4_add(v4_min(b2->lo, r.lo), one);
        b2->nhi = v4_min(b2->nhi, r.nhi);
    }
}

static void bin_prims(const split_ctx *b, int lo, int hi, v4 cmin, v4 scale, bins *out)
{
    int nb = out->nbins;
    v4 empty_lo = v4_set(FLT_MAX, FLT_MAX, FLT_MAX, 0.0f), empty_nhi = v4_splat(FLT_MAX);
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < nb; k++)
            out->box[a][k] = (box4){empty_lo, empty_nhi};
    out->counted = hi - lo > BIN_CHUNK;
    if (out->counted)
        memset(out->n, 0, sizeof out->n);
    for (int start = lo; start < hi; start += BIN_CHUNK) {
        int end = hi - start > BIN_CHUNK ? start + BIN_CHUNK : hi;
#if defined(GLINT_WIDE_KERNELS)
        if (b->avx2)
            split_bin_avx2(b->refs, start, end, cmin, scale, nb, out->box);
        else
#endif
            bin_range(b->refs, start, end, cmin, scale, nb, out->box);
        if (out->counted)
            for (int a = 0; a < 3; a++)
                for (int k = 0; k < nb; k++) {
                    box4 *bin = &out->box[a][k];
                    out->n[a][k] += (int)v4_w(bin->lo);
                    bin->lo = v4_set(v4_x(bin->lo), v4_y(bin->lo), v4_z(bin->lo), 0.0f);
                }
    }
}

/* Ranges of at least this many primitives are binned on several threads,
 * each a part of the range into bins of its own, then merged: minima and
 * exact counts are the same whatever the parts. */
#define BIN_PAR_MIN 65536
#define BIN_PAR_MAX 8

/* The parts of [lo, lo + n), t of them, binned by whichever thread takes
 * each next. */
typedef struct bin_job {
    const split_ctx *b;
    int lo, t;
    long n;
    v4 cmin, scale;
    bins *part[BIN_PAR_MAX];
    atomic_int next;
} bin_job;

static void *bin_run(void *arg)
{
    bin_job *j = arg;
    for (int i; (i = atomic_fetch_add(&j->next, 1)) < j->t;)
        bin_prims(j->b, j->lo + (int)(j->n * i / j->t), j->lo + (int)(j->n * (i + 1) / j->t),
                  j->cmin, j->scale, j->part[i]);
    return NULL;
}

static void bin_prims_par(const split_ctx *b, int lo, int hi, v4 cmin, v4 scale, bins *out)
{
    int t = b->threads < BIN_PAR_MAX ? b->threads : BIN_PAR_MAX;
    bins part[BIN_PAR_MAX];
    bin_job j = {b, lo, t, hi - lo, cmin, scale, {NULL}, 0};
    for (int i = 0; i < t; i++) {
        part[i].nbins = out->nbins;
        j.part[i] = i == 0 ? out : &part[i];
    }
    cpus_share(t, bin_run, &j);
    for (int i = 1; i < t; i++) { /* merged in order: the same floats however they ran */
        for (int a = 0; a < 3; a++)
            for (int k = 0; k < out->nbins; k++) {
                box4 *o = &out->box[a][k], p = part[i].box[a][k];
                float count = v4_w(o->lo) + v4_w(p.lo);
                v4 m = v4_min(o->lo, p.lo);
                o->lo = v4_set(v4_x(m), v4_y(m), v4_z(m), count);
                o->nhi = v4_min(o->nhi, p.nhi);
            }
    }
}

/* The areas of four boxes at once, as box4_area computes each but for the
 * test of an empty box (the unions swept here are of at least one box,
 * or are not used). hi - lo is -(-hi + lo) exactly, and the signs cancel
 * in the products. */
static inline v4 area4(const v4 *lo, const v4 *nhi)
{
    v4 x = v4_add(nhi[0], lo[0]), y = v4_add(nhi[1], lo[1]);
    v4 z = v4_add(nhi[2], lo[2]), w = v4_add(nhi[3], lo[3]);
    v4_transpose(&x, &y, &z, &w); /* x: the four x extents, and so on */
    return v4_mul(v4_splat(2.0f), v4_add(v4_add(v4_mul(x, y), v4_mul(y, z)), v4_mul(z, x)));
}

/* The candidate planes of a node: raw[a][k] the cost of the plane after
 * bin k of axis a before it is made relative to the node's area, INFINITY
 * where there is none. */
typedef struct cands {
    float raw[3][BINS] __attribute__((aligned(16)));
} cands;

/* The cheapest candidate's cost relative to the node's area (COST_TRAVERSE
 * + raw / area), with its axis and plane (a centre coordinate: the upper
 * end of its bin, cmin + (bin + 1) / scale); INFINITY when there is none
 * or the area is 0. Of equal raw costs, the first in the order a sweep
 * meets them (axis by axis, each from low to high) is kept. m: the
 * candidates of each axis, a multiple of 4. */
static float pick_split(const cands *c, int m, float area, v4 cmin, const float scale[3],
                        int *axis, float *plane)
{
    if (!(area > 0.0f))
        return INFINITY;
    v4 best = v4_splat(INFINITY);
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < m; k += 4)
            best = v4_min(v4_load(&c->raw[a][k]), best);
    best = v4_min(best, v4_min(v4_shuffle(best, 1, 0, 3, 2), v4_shuffle(best, 2, 3, 0, 1)));
    best = v4_min(best, v4_shuffle(best, 2, 3, 0, 1));
    float cost = COST_TRAVERSE + v4_x(best) / area;
    if (!(cost < INFINITY))
        return INFINITY;
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < m; k += 4) {
            int eq = v4_eq(v4_load(&c->raw[a][k]), best);
            if (eq) {
                int bin = k + __builtin_ctz((unsigned)eq);
                *axis = a;
                *plane = v4_at(cmin, a) + (float)(bin + 1) / scale[a];
                return cost;
            }
        }
    return INFINITY;
}

/* The planes after bins 0 .. nb - 2 of axis a: the boxes of the bins
 * below and above each, swept from both ends, then their areas four at a
 * time. Bins that hold nothing change no union, so the planes between two
 * bins that hold something all cost the same, and the first of them wins
 * (pick_split); a plane with nothing on one side is no candidate. */
static void sweep_axis(const split_ctx *b, const bins *bn, int a, int n, cands *c)
{
    bool fast = b->block == 1 && !bn->counted;
#if defined(GLINT_WIDE_KERNELS)
    if (fast && b->avx2) {
        split_sweep_avx2(bn->box[a], bn->nbins, n, c->raw[a]);
        return;
    }
#endif
    int nb = bn->nbins, m = nb - 1, m4 = (m + 3) & ~3;
    v4 llo[BINS], lnh[BINS], rlo[BINS], rnh[BINS], lcnt[BINS];
    const v4 big = v4_splat(FLT_MAX), zero = v4_splat(0.0f);
    const box4 *bin = bn->box[a];
    box4 acc = box4_empty();
    v4 cnt = zero; /* lane 3: the primitives below */
    for (int k = 0; k < m; k++) {
        acc = box4_union(acc, bin[k]);
        cnt = v4_add(cnt, bin[k].lo);
        llo[k] = acc.lo;
        lnh[k] = acc.nhi;
        lcnt[k] = cnt;
    }
    acc = box4_empty();
    for (int k = m; k > 0; k--) {
        acc = box4_union(acc, bin[k]);
        rlo[k - 1] = acc.lo;
        rnh[k - 1] = acc.nhi;
    }
    for (int k = m; k < m4; k++) {
        llo[k] = rlo[k] = lnh[k] = rnh[k] = big;
        lcnt[k] = zero;
    }
    v4 total = v4_splat((float)n);
    float lcs[BINS], rcs[BINS];
    if (!fast) /* leaf costs from integer counts */
        for (int k = 0, below = 0; k < m4; k++) {
            below += k < m ? bin_count(bn, a, k) : 0;
            lcs[k] = k < m ? leaf_cost(b, below) : 0.0f;
            rcs[k] = k < m ? leaf_cost(b, n - below) : 0.0f;
        }
    for (int k = 0; k < m4; k += 4) {
        v4 lc, rc;
        if (fast) { /* a leaf of n primitives costs n */
            lc = v4_lane3(lcnt[k], lcnt[k + 1], lcnt[k + 2], lcnt[k + 3]);
            rc = v4_sub(total, lc);
        } else {
            lc = v4_set(lcs[k], lcs[k + 1], lcs[k + 2], lcs[k + 3]);
            rc = v4_set(rcs[k], rcs[k + 1], rcs[k + 2], rcs[k + 3]);
        }
        v4 cost = v4_add(v4_mul(area4(&llo[k], &lnh[k]), lc), v4_mul(area4(&rlo[k], &rnh[k]), rc));
        /* no candidate where a side has no primitive (its cost 0, its
         * area infinite or 0), and none where the cost is NaN */
        v4_store(&c->raw[a][k], v4_select_gt0(v4_min(lc, rc), v4_nan_to(cost, INFINITY), INFINITY));
    }
}

/* best_split for two primitives, without the bins: on every axis where
 * their centres differ they fall into the first and the last of the eight
 * bins, so every such axis splits them alike, at the same cost, and the
 * first of them is kept, at the plane after its first bin. */
static float split_pair(const split_ctx *b, int lo, box4 *box_out, cbox cb, int *axis, float *plane)
{
    box4 p = box4_load(&b->refs[lo]), q = box4_load(&b->refs[lo + 1]);
    *box_out = box4_union(p, q);
    aabb cbx = {v3(v4_x(cb.lo), v4_y(cb.lo), v4_z(cb.lo)), v3(v4_x(cb.hi), v4_y(cb.hi), v4_z(cb.hi))};
    vec3 ext = aabb_extent(cbx);
    int a = v3_at(ext, 0) > 0.0f ? 0 : v3_at(ext, 1) > 0.0f ? 1 : v3_at(ext, 2) > 0.0f ? 2 : -1;
    if (a < 0)
        return INFINITY;
    bool p_first = ref_center(&b->refs[lo], a) <= ref_center(&b->refs[lo + 1], a);
    box4 first = p_first ? p : q, second = p_first ? q : p;
    float area = box4_area(*box_out);
    float cost = box4_area(first) * leaf_cost(b, 1) + box4_area(second) * leaf_cost(b, 1);
    cost = area > 0.0f ? COST_TRAVERSE + cost / area : INFINITY;
    if (!(cost < INFINITY))
        return INFINITY;
    float scale = 8.0f / v3_at(ext, a);
    *axis = a;
    *plane = v3_at(cbx.lo, a) + 1.0f / scale;
    return cost;
}

/* The bins of a range of n primitives. Primitives tested block-wide (a
 * mesh's triangles) get BINS from BINS primitives up, and max(n, 8) below
 * that: more would mostly stay empty, and sweeping them costs more than
 * binning the primitives. Single primitives (a scene's objects) get
 * 4 + n / 10, at least 8, at most BINS, as Embree maps them ("BinMapping"
 * in its binned SAH builder): on 10^6 random spheres the build is 9 %
 * faster and rays cost 0.6 % more instructions; mesh trees, which carry
 * far more rays per primitive, keep every bin. */
static int bins_for(const split_ctx *b, int n)
{
    int want = b->block == 1 ? 4 + n / 10 : n;
    return want >= BINS ? BINS : want > 8 ? want : 8;
}

/* The best binned SAH split of [lo, hi) over all three axes: sets *axis
 * and *plane (a centre coordinate) and returns its cost relative to the
 * parent's area, or INFINITY when no plane separates the centres; *box_out
 * is the box of [lo, hi), the union of the bins (bins_for says how
 * many). */
float split_best(const split_ctx *b, int lo, int hi, cbox cb, box4 *box_out, int *axis,
                        float *plane)
{
    float scale[3];
    bins bn;
    int n = hi - lo;
    if (n == 2)
        return split_pair(b, lo, box_out, cb, axis, plane);
    bn.nbins = bins_for(b, n);
    v4 ext = v4_sub(cb.hi, cb.lo);
    for (int a = 0; a < 3; a++)
        scale[a] = v4_at(ext, a) > 0.0f ? (float)bn.nbins / v4_at(ext, a) : 0.0f;
    v4 sc = v4_set(scale[0], scale[1], scale[2], 0.0f);
    if (b->threads > 1 && n >= BIN_PAR_MIN && n <= BIN_CHUNK)
        bin_prims_par(b, lo, hi, cb.lo, sc, &bn);
    else
        bin_prims(b, lo, hi, cb.lo, sc, &bn);
    box4 box = box4_empty();
    for (int k = 0; k < bn.nbins; k++)
        box = box4_union(box, bn.box[0][k]);
    *box_out = box;
    cands c;
    int m = (bn.nbins - 1 + 3) & ~3;
    for (int a = 0; a < 3; a++) {
        if (v4_at(ext, a) > 0.0f)
            sweep_axis(b, &bn, a, n, &c);
        else
            for (int k = 0; k < m; k++)
                c.raw[a][k] = INFINITY;
    }
    return pick_split(&c, m, box4_area(box), cb.lo, scale, axis, plane);
}

split_kind split_decide(const split_ctx *b, int lo, int hi, int depth, const cbox *given,
                        box4 *box, int *axis, float *plane)
{
    int n = hi - lo;
    cbox cb;
    if (given)
        cb = *given;
    else
        split_bounds(b, lo, hi, box, &cb);
    v4 ext = v4_sub(cb.hi, cb.lo);
    float ex = v4_x(ext), ey = v4_y(ext), ez = v4_z(ext);
    *axis = ex >= ey && ex >= ez ? 0 : ey >= ez ? 1 : 2;
    split_kind kind;
    if (n <= 1 || depth >= BVH_MAX_DEPTH - 1) {
        if (given)
            split_bounds(b, lo, hi, box, &cb);
        kind = SPLIT_LEAF;
    } else {
        float cost = split_best(b, lo, hi, cb, box, axis, plane);
        if (cost == INFINITY)
            kind = n <= b->max_leaf ? SPLIT_LEAF : SPLIT_MEDIAN;
        else
            kind = n <= b->max_leaf && leaf_cost(b, n) <= cost ? SPLIT_LEAF : SPLIT_PLANE;
    }
    return kind == SPLIT_LEAF && n > UINT16_MAX ? SPLIT_MEDIAN : kind;
}
