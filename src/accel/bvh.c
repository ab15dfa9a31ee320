#define _GNU_SOURCE /* sched_getaffinity */
#include "bvh.h"

#include <float.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define BINS 32
#define MAX_LEAF 4
/* Primitives tested block-wide at a time (bvh_build_blocked) go up to this
 * many blocks to a leaf, when the SAH finds that cheaper than a split: on
 * the bunny that takes the eight-wide nodes from 5,280 to about 4,100 (mesh
 * and BVH from 80 to 75 bytes a triangle) for the same speed. */
#define LEAF_BLOCKS 2
#define COST_TRAVERSE 1.2f /* a node visit against one leaf test (or block) */
#define COST_INTERSECT 1.0f

typedef struct build {
    const aabb *boxes;
    int block;
    int max_leaf; /* most primitives a leaf takes */
    vec3 *centers;
    int32_t *prims;
    bvh_node *nodes;
    int nnodes, cap;
    int spawn_depth; /* a second child this deep or less is built on a thread of its own */
} build;

/* Subtrees smaller than this are not worth a thread. */
#define PAR_MIN 4096

static int new_node(build *b)
{
    if (b->nnodes == b->cap) {
        int cap = b->cap * 2;
        bvh_node *n = realloc(b->nodes, sizeof *n * (size_t)cap);
        if (!n)
            return -1;
        b->nodes = n;
        b->cap = cap;
    }
    b->nodes[b->nnodes].pad = 0;
    return b->nnodes++;
}

/* Partitions prims[lo, hi) so that those with centre below `split` on
 * `axis` come first; returns the first index of the upper part. */
static int partition(build *b, int lo, int hi, int axis, float split)
{
    int i = lo, j = hi - 1;
    while (i <= j) {
        if (v3_at(b->centers[b->prims[i]], axis) < split) {
            i++;
        } else {
            int32_t t = b->prims[i];
            b->prims[i] = b->prims[j];
            b->prims[j--] = t;
        }
    }
    return i;
}

/* Puts the median primitive by centre on axis at the middle of [lo, hi)
 * (quickselect); the fallback when binning cannot separate the centres. */
static void median_split(build *b, int lo, int hi, int axis, int *mid)
{
    int k = (lo + hi) / 2, l = lo, r = hi - 1;
    while (l < r) {
        float pivot = v3_at(b->centers[b->prims[(l + r) / 2]], axis);
        int i = l, j = r;
        while (i <= j) {
            while (v3_at(b->centers[b->prims[i]], axis) < pivot)
                i++;
            while (v3_at(b->centers[b->prims[j]], axis) > pivot)
                j--;
            if (i <= j) {
                int32_t t = b->prims[i];
                b->prims[i++] = b->prims[j];
                b->prims[j--] = t;
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

/* Cost of testing n primitives: they are tested block-wide at a time. */
static float leaf_cost(const build *b, int n)
{
    return COST_INTERSECT * (float)((n + b->block - 1) / b->block);
}

/* Boxes as the binning loops use them: with SSE, lo and hi in one
 * register each (the fourth lane unused), so that a union is two
 * instructions. Both forms give the same values. */
#if defined(__SSE2__)
typedef struct box4 {
    __m128 lo, hi;
} box4;

static inline box4 box4_empty(void) { return (box4){_mm_set1_ps(FLT_MAX), _mm_set1_ps(-FLT_MAX)}; }

/* aabb is six floats: lo.x lo.y lo.z hi.x hi.y hi.z; the two loads stay
 * inside it. */
static inline box4 box4_load(const aabb *b)
{
    __m128 hi = _mm_loadu_ps(&b->lo.z); /* lo.z hi.x hi.y hi.z */
    return (box4){_mm_loadu_ps(&b->lo.x), _mm_shuffle_ps(hi, hi, _MM_SHUFFLE(3, 3, 2, 1))};
}

/* A centre (a vec3 in an array padded by one float) as a point box. */
static inline __m128 point4_load(const vec3 *c) { return _mm_loadu_ps(&c->x); }

static inline box4 box4_union(box4 a, box4 b)
{
    return (box4){_mm_min_ps(a.lo, b.lo), _mm_max_ps(a.hi, b.hi)};
}

static inline box4 box4_grow(box4 a, __m128 p) { return (box4){_mm_min_ps(a.lo, p), _mm_max_ps(a.hi, p)}; }

static inline aabb box4_aabb(box4 b)
{
    float l[4], h[4];
    _mm_storeu_ps(l, b.lo);
    _mm_storeu_ps(h, b.hi);
    return (aabb){{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
}

/* Bin k on each axis of centre c: (c - cmin) * scale, truncated, in
 * [0, nbins - 1]; NaN (a zero extent's 0 * inf) goes to 0. */
static inline void bin_of(__m128 c, __m128 cmin, __m128 scale, __m128 top, int k[4])
{
    __m128 f = _mm_mul_ps(_mm_sub_ps(c, cmin), scale);
    f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), top); /* max_ps gives 0 for NaN */
    _mm_storeu_si128((__m128i *)k, _mm_cvttps_epi32(f));
}
#else
typedef aabb box4;
static inline box4 box4_empty(void) { return aabb_empty(); }
static inline box4 box4_load(const aabb *b) { return *b; }
static inline vec3 point4_load(const vec3 *c) { return *c; }
static inline box4 box4_union(box4 a, box4 b) { return aabb_union(a, b); }
static inline box4 box4_grow(box4 a, vec3 p) { return aabb_grow(a, p); }
static inline aabb box4_aabb(box4 b) { return b; }
static inline void bin_of(vec3 c, vec3 cmin, vec3 scale, vec3 top, int k[4])
{
    for (int a = 0; a < 3; a++) {
        float f = (v3_at(c, a) - v3_at(cmin, a)) * v3_at(scale, a);
        k[a] = f >= v3_at(top, a) ? (int)v3_at(top, a) : f > 0.0f ? (int)f : 0;
    }
}
#endif

/* Primitive counts and bounds per bin, on each of the three axes. */
typedef struct bins {
    int nbins;
    box4 box[3][BINS];
    int n[3][BINS];
} bins;

/* One pass over [lo, hi) fills the bins of all three axes (bin k of axis a
 * holds the centres in [cmin + k / scale, cmin + (k + 1) / scale)). */
static void bin_prims(const build *b, int lo, int hi, vec3 cmin, const float scale[3], bins *out)
{
    int nb = out->nbins;
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < nb; k++) {
            out->box[a][k] = box4_empty();
            out->n[a][k] = 0;
        }
    float top = (float)(nb - 1);
#if defined(__SSE2__)
    __m128 cmin4 = _mm_setr_ps(cmin.x, cmin.y, cmin.z, 0.0f);
    __m128 scale4 = _mm_setr_ps(scale[0], scale[1], scale[2], 0.0f), top4 = _mm_set1_ps(top);
#else
    vec3 cmin4 = cmin, scale4 = v3(scale[0], scale[1], scale[2]), top4 = v3s(top);
#endif
    for (int i = lo; i < hi; i++) {
        int32_t p = b->prims[i];
        int k[4];
        bin_of(point4_load(&b->centers[p]), cmin4, scale4, top4, k);
        box4 box = box4_load(&b->boxes[p]);
        for (int a = 0; a < 3; a++) {
            out->n[a][k[a]]++;
            out->box[a][k[a]] = box4_union(out->box[a][k[a]], box);
        }
    }
}

/* The planes between the bins of axis a, swept from both sides; keeps the
 * cheapest below *best (relative to the parent's area). */
static void sweep_axis(const build *b, const bins *bn, int a, float area, float cmin, float scale,
                       float *best, int *axis, float *plane)
{
    int nb = bn->nbins;
    float right_area[BINS];
    int right_n[BINS];
    box4 acc = box4_empty();
    int cnt = 0;
    for (int i = nb - 1; i > 0; i--) {
        acc = box4_union(acc, bn->box[a][i]);
        cnt += bn->n[a][i];
        right_area[i] = aabb_area(box4_aabb(acc));
        right_n[i] = cnt;
    }
    acc = box4_empty();
    cnt = 0;
    for (int i = 1; i < nb; i++) {
        acc = box4_union(acc, bn->box[a][i - 1]);
        cnt += bn->n[a][i - 1];
        if (cnt == 0 || right_n[i] == 0)
            continue;
        float cost = aabb_area(box4_aabb(acc)) * leaf_cost(b, cnt) +
                     right_area[i] * leaf_cost(b, right_n[i]);
        cost = area > 0.0f ? COST_TRAVERSE + cost / area : INFINITY;
        if (cost < *best) {
            *best = cost;
            *axis = a;
            *plane = cmin + (float)i / scale;
        }
    }
}

/* The best binned SAH split of [lo, hi) over all three axes: sets *axis
 * and *plane (a centre coordinate) and returns its cost relative to the
 * parent's area, or INFINITY when no plane separates the centres. A node
 * of n < BINS primitives gets max(n, 8) bins: more would mostly stay
 * empty, and sweeping them costs more than binning the primitives. */
static float best_split(const build *b, int lo, int hi, aabb box, aabb cbox, int *axis,
                        float *plane)
{
    float best = INFINITY, scale[3];
    bins bn;
    int n = hi - lo;
    bn.nbins = n >= BINS ? BINS : n > 8 ? n : 8;
    vec3 ext = aabb_extent(cbox);
    for (int a = 0; a < 3; a++)
        scale[a] = v3_at(ext, a) > 0.0f ? (float)bn.nbins / v3_at(ext, a) : 0.0f;
    bin_prims(b, lo, hi, cbox.lo, scale, &bn);
    for (int a = 0; a < 3; a++)
        if (v3_at(ext, a) > 0.0f)
            sweep_axis(b, &bn, a, aabb_area(box), v3_at(cbox.lo, a), scale[a], &best, axis, plane);
    return best;
}

static int build_node(build *b, int lo, int hi, int depth);

/* A subtree built on its own thread into its own node array. */
typedef struct subtree {
    build b;
    int lo, hi, depth, root;
} subtree;

static void *subtree_run(void *arg)
{
    subtree *t = arg;
    t->root = build_node(&t->b, t->lo, t->hi, t->depth);
    return NULL;
}

/* Appends t's nodes to b's (after b's own), renumbering its second
 * children; returns the index of t's root in b, or -1. */
static int adopt(build *b, const subtree *t)
{
    int at = b->nnodes;
    for (int i = 0; i < t->b.nnodes; i++) {
        int k = new_node(b);
        if (k < 0)
            return -1;
        b->nodes[k] = t->b.nodes[i];
        if (b->nodes[k].count == 0)
            b->nodes[k].index += at;
    }
    return at + t->root;
}

/* Builds [lo, mid) and [mid, hi) as the two children of the node just
 * made (the first follows it directly); returns the second's index. Near
 * the root the second is built on another thread at the same time and then
 * appended, so the nodes come out in the same order as on one thread. */
static int build_children(build *b, int lo, int mid, int hi, int depth)
{
    if (depth > b->spawn_depth || hi - mid < PAR_MIN || mid - lo < PAR_MIN) {
        if (build_node(b, lo, mid, depth) < 0)
            return -1;
        return build_node(b, mid, hi, depth);
    }
    subtree t = {*b, mid, hi, depth, -1};
    t.b.nnodes = 0;
    t.b.cap = 2 * ((hi - mid) / b->max_leaf + 1) + 1;
    t.b.nodes = malloc(sizeof *t.b.nodes * (size_t)t.b.cap);
    if (!t.b.nodes)
        return -1;
    pthread_t th;
    bool threaded = pthread_create(&th, NULL, subtree_run, &t) == 0;
    int first = build_node(b, lo, mid, depth);
    if (threaded)
        pthread_join(th, NULL);
    else
        subtree_run(&t);
    int second = first < 0 || t.root < 0 ? -1 : adopt(b, &t);
    free(t.b.nodes);
    return second;
}

static int build_node(build *b, int lo, int hi, int depth)
{
    int self = new_node(b);
    if (self < 0)
        return -1;
    box4 bx = box4_empty(), cbx = box4_empty();
    for (int i = lo; i < hi; i++) {
        int32_t p = b->prims[i];
        bx = box4_union(bx, box4_load(&b->boxes[p]));
        cbx = box4_grow(cbx, point4_load(&b->centers[p]));
    }
    aabb box = box4_aabb(bx), cbox = box4_aabb(cbx);
    int n = hi - lo, mid;
    b->nodes[self].box = box;
    /* The median fallback splits along the axis of largest centre extent. */
    vec3 ext = aabb_extent(cbox);
    int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
    if (n <= 1 || depth >= BVH_MAX_DEPTH - 1) {
    leaf:
        if (n > UINT16_MAX) /* a leaf's count must fit; median splits halve n */
            goto split_median;
        b->nodes[self].index = lo;
        b->nodes[self].count = (uint16_t)n;
        b->nodes[self].axis = 0;
        return self;
    }
    {
        float plane = 0.0f;
        float split = best_split(b, lo, hi, box, cbox, &axis, &plane);
        if (split == INFINITY) {
            if (n <= b->max_leaf)
                goto leaf;
            goto split_median;
        }
        if (n <= b->max_leaf && leaf_cost(b, n) <= split)
            goto leaf;
        mid = partition(b, lo, hi, axis, plane);
        if (mid == lo || mid == hi)
            goto split_median;
        goto recurse;
    }
split_median:
    median_split(b, lo, hi, axis, &mid);
recurse:
    b->nodes[self].axis = (uint8_t)axis;
    b->nodes[self].count = 0;
    int second = build_children(b, lo, mid, hi, depth + 1);
    if (second < 0)
        return -1;
    b->nodes[self].index = second;
    return self;
}

/* The deepest child that gets a thread of its own: with T CPUs to run on
 * (the process's affinity mask), the tree's top is cut into about 4T
 * subtrees built at once, so that uneven splits even out; with one CPU,
 * none (-1). */
static int spawn_depth(int cpus)
{
    if (cpus <= 0) {
#if defined(CPU_COUNT)
        cpu_set_t set;
        cpus = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 1;
#else
        cpus = (int)sysconf(_SC_NPROCESSORS_ONLN);
#endif
    }
    if (cpus <= 1)
        return -1;
    int d = 2;
    while ((1 << (d - 2)) < cpus && d < 8)
        d++;
    return d;
}

static glint_rc build_tree(bvh *out, const aabb *boxes, int n, int block, int max_leaf,
                           int cpus, glint_error *err);

glint_rc bvh_build(bvh *out, const aabb *boxes, int n, glint_error *err)
{
    return bvh_build_blocked(out, boxes, n, 1, err);
}

glint_rc bvh_build_leaves(bvh *out, const aabb *boxes, int n, int max_leaf, glint_error *err)
{
    max_leaf = max_leaf < 1 ? 1 : max_leaf > MAX_LEAF ? MAX_LEAF : max_leaf;
    return build_tree(out, boxes, n, 1, max_leaf, 0, err);
}

glint_rc bvh_build_blocked(bvh *out, const aabb *boxes, int n, int block, glint_error *err)
{
    return bvh_build_threads(out, boxes, n, block, 0, err);
}

glint_rc bvh_build_threads(bvh *out, const aabb *boxes, int n, int block, int cpus,
                           glint_error *err)
{
    block = block > 0 ? block : 1;
    return build_tree(out, boxes, n, block, block > 1 ? LEAF_BLOCKS * block : MAX_LEAF, cpus,
                      err);
}

static glint_rc build_tree(bvh *out, const aabb *boxes, int n, int block, int max_leaf,
                           int cpus, glint_error *err)
{
    memset(out, 0, sizeof *out);
    if (n <= 0)
        return GLINT_OK;
    build b = {boxes, block, max_leaf, NULL, NULL, NULL, 0, 0, spawn_depth(cpus)};
    b.centers = malloc(sizeof *b.centers * (size_t)n + sizeof(float)); /* point4_load reads 4 */
    b.prims = malloc(sizeof *b.prims * (size_t)n);
    b.cap = 2 * (n / b.max_leaf + 1) + 1;
    b.nodes = malloc(sizeof *b.nodes * (size_t)b.cap);
    if (!b.centers || !b.prims || !b.nodes)
        goto nomem;
    for (int i = 0; i < n; i++) {
        b.prims[i] = i;
        b.centers[i] = aabb_center(boxes[i]);
    }
    if (build_node(&b, 0, n, 0) < 0)
        goto nomem;
    free(b.centers);
    out->nodes = b.nodes;
    out->nnodes = b.nnodes;
    out->prims = b.prims;
    out->nprims = n;
    return GLINT_OK;
nomem:
    free(b.centers);
    free(b.prims);
    free(b.nodes);
    return err_nomem(err);
}

void bvh_free(bvh *b)
{
    free(b->nodes);
    free(b->prims);
    memset(b, 0, sizeof *b);
}
