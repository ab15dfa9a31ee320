/* split: what the BVH builders share (accel/bvh.c, the binary tree;
 * accel/wide_build.c, the wide one): primitives as the builds move them,
 * the binned SAH split of a range, and partitioning it.
 *
 * The split is the binned surface-area-heuristic one of Wald, "On fast
 * Construction of SAH-based Bounding Volume Hierarchies" (IEEE RT 2007):
 * BINS bins on each of the three axes, binned in one pass. */
#ifndef GLINT_ACCEL_SPLIT_H
#define GLINT_ACCEL_SPLIT_H

#include <float.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>
#include "accel/isa.h"
#include "accel/v4.h"
#include "core/aabb.h"

#define BINS 32
#define COST_TRAVERSE 1.2f /* a node visit against one leaf test (or block) */
#define COST_INTERSECT 1.0f

/* A primitive as the build moves it, in 32 bytes so that each pass over a
 * node reads its primitives in sequence rather than gathering them through
 * their indices from all over memory: its box as lo and -hi (so that a
 * union is two minima), +inf in lo's fourth lane (where bins count, below)
 * and the index in -hi's. */
typedef struct primref {
    float lo[4];  /* x y z +inf */
    float nhi[3]; /* -hi */
    int32_t id;
} __attribute__((aligned(32))) primref;

/* A box as lo and -hi; lane 3 of lo counts primitives in bins. */
typedef struct box4 {
    v4 lo, nhi;
} box4;

static inline box4 box4_empty(void) { return (box4){v4_splat(FLT_MAX), v4_splat(FLT_MAX)}; }
static inline box4 box4_load(const primref *r) { return (box4){v4_load(r->lo), v4_load(r->nhi)}; }
static inline box4 box4_union(box4 a, box4 b)
{
    return (box4){v4_min(a.lo, b.lo), v4_min(a.nhi, b.nhi)};
}
/* The centre, (lo + hi) / 2, as aabb_center computes it (first three lanes). */
static inline v4 box4_center(box4 b) { return v4_mul(v4_sub(b.lo, b.nhi), v4_splat(0.5f)); }

static inline aabb box4_aabb(box4 b)
{
    v4 hi = v4_neg(b.nhi);
    return (aabb){v3(v4_x(b.lo), v4_y(b.lo), v4_z(b.lo)), v3(v4_x(hi), v4_y(hi), v4_z(hi))};
}

/* aabb_area(box4_aabb(b)), with the same operations in the same order. */
static inline float box4_area(box4 b)
{
    v4 e = v4_sub(v4_neg(b.nhi), b.lo);
    float x = v4_x(e), y = v4_y(e), z = v4_z(e);
    if ((v4_lt(e, v4_splat(0.0f)) & 7) != 0)
        return 0.0f; /* empty */
    return 2.0f * (x * y + y * z + z * x);
}

/* A centre coordinate as aabb_center computes it. */
static inline float ref_center(const primref *r, int axis)
{
    return (r->lo[axis] - r->nhi[axis]) * 0.5f;
}

/* The bounds of a set of centres (first three lanes). */
typedef struct cbox {
    v4 lo, hi;
} cbox;

static inline cbox cbox_empty(void) { return (cbox){v4_splat(FLT_MAX), v4_splat(-FLT_MAX)}; }
static inline cbox cbox_grow(cbox a, v4 c) { return (cbox){v4_min(a.lo, c), v4_max(a.hi, c)}; }

/* What a range's split depends on, besides its primitives. */
typedef struct split_ctx {
    int block;    /* primitives tested block-wide at a time */
    int max_leaf; /* most primitives a leaf takes */
    primref *refs;
    int threads;  /* large ranges are binned on this many threads at once */
    bool avx2;    /* bin, partition and sweep with split_avx2.c's loops (the same tree) */
} split_ctx;

/* Cost of testing n primitives: they are tested block-wide at a time. */
static inline float leaf_cost(const split_ctx *b, int n)
{
    return COST_INTERSECT * (float)(b->block == 1 ? n : (n + b->block - 1) / b->block);
}

/* The box and the centre bounds of refs[lo, hi). */
void split_bounds(const split_ctx *b, int lo, int hi, box4 *box, cbox *cb);
/* The best binned SAH split of [lo, hi) over all three axes, its centres'
 * bounds cb: sets *axis and *plane (a centre coordinate) and returns its
 * cost relative to the range's area, or INFINITY when no plane separates
 * the centres; *box_out is the box of [lo, hi). */
float split_best(const split_ctx *b, int lo, int hi, cbox cb, box4 *box_out, int *axis,
                 float *plane);
/* What a range becomes. */
typedef enum split_kind {
    SPLIT_LEAF,   /* a leaf of all its primitives */
    SPLIT_PLANE,  /* two halves, by centre, at *plane on *axis */
    SPLIT_MEDIAN, /* two halves at the median on *axis (split_median) */
} split_kind;

/* What the builders make of refs[lo, hi), a range `depth` below the root
 * (given: its centre bounds, or NULL to work them out), and *box, its box:
 * a leaf at the depth limit or where the SAH finds it no dearer than the
 * best split (of at most max_leaf primitives); else that split; else,
 * where no plane separates the centres or a leaf's count would not fit in
 * 16 bits, the median on the axis of largest centre extent (or of the
 * split that was found). */
split_kind split_decide(const split_ctx *b, int lo, int hi, int depth, const cbox *given,
                        box4 *box, int *axis, float *plane);
/* Partitions refs[lo, hi) so that those with centre below `plane` on
 * `axis` come first; returns the first index of the upper part, and the
 * centre bounds of each part. */
int split_partition(split_ctx *b, int lo, int hi, int axis, float plane, cbox *below,
                    cbox *above);
/* split_partition with AVX2 (split_avx2.c), and its binning loop: the
 * primitives of refs[lo, hi) added to the first nb bins of each axis,
 * box[axis][bin], as split.c's bin_range adds them. */
int split_partition_avx2(split_ctx *b, int lo, int hi, int axis, float plane, cbox *below,
                         cbox *above);
void split_bin_avx2(const primref *refs, int lo, int hi, v4 cmin, v4 scale, int nb,
                    box4 (*box)[BINS]);
/* split.c's sweep_axis for a range of single primitives counted in their
 * bins (its fast case): the raw cost of the plane after each of the first
 * nb - 1 bins, INFINITY up to the next multiple of 8. */
void split_sweep_avx2(const box4 *bins, int nb, int n, float raw[BINS]);

/* The partition behind split_partition, for a `side` that tells whether
 * a primitive goes below and adds its centre to that side's bounds in
 * acc. No branch depends on the data, which goes either way: large ranges
 * are partitioned in place a block at a time (Edelkamp and Weiss,
 * "BlockQuicksort", ESA 2016): the primitives of a block at each end that
 * belong to the other side are noted, then swapped in pairs; what is
 * left, fewer than 2 * PART_BLOCK, goes through a buffer. Inlined into
 * each caller, so that `side` is too. */
#define PART_BLOCK 64

static inline __attribute__((always_inline)) int
split_partition_by(primref *r, int lo, int hi, void *acc, int (*side)(void *, const primref *))
{
    int l = lo, h = hi; /* [l, h) is not settled yet */
    unsigned char offl[PART_BLOCK], offh[PART_BLOCK];
    int nl = 0, nh = 0, sl = 0, sh = 0;
    while (h - l > 2 * PART_BLOCK) {
        if (nl == 0) {
            sl = 0;
            for (int k = 0; k < PART_BLOCK; k++) {
                offl[nl] = (unsigned char)k;
                nl += !side(acc, &r[l + k]);
            }
        }
        if (nh == 0) {
            sh = 0;
            for (int k = 0; k < PART_BLOCK; k++) {
                offh[nh] = (unsigned char)k;
                nh += side(acc, &r[h - 1 - k]);
            }
        }
        int num = nl < nh ? nl : nh;
        for (int j = 0; j < num; j++) {
            primref *x = &r[l + offl[sl + j]], *y = &r[h - 1 - offh[sh + j]];
            primref t = *x;
            *x = *y;
            *y = t;
        }
        nl -= num;
        nh -= num;
        sl += num;
        sh += num;
        if (nl == 0)
            l += PART_BLOCK;
        if (nh == 0)
            h -= PART_BLOCK;
    }
    /* The rest through a buffer: below from its start, above from its end. */
    primref tmp[2 * PART_BLOCK];
    int m = h - l, a = 0, z = m - 1;
    for (int i = 0; i < m; i++) {
        int s = side(acc, &r[l + i]);
        tmp[s ? a : z] = r[l + i];
        a += s;
        z -= 1 - s;
    }
    memcpy(&r[l], tmp, sizeof *tmp * (size_t)m);
    return l + a;
}

/* The fallback when binning cannot separate the centres: the lower half
 * by centre on axis (ties by index) to [lo, mid), mid the middle. */
void split_median(split_ctx *b, int lo, int hi, int axis, int *mid);

#endif
