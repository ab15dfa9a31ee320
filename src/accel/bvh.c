#define _GNU_SOURCE /* sched_getaffinity */
#include "bvh.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/array.h"
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

/* A primitive as the build moves it: its box and its index in 32 bytes,
 * so that each pass over a node reads its primitives in sequence rather
 * than gathering them through their indices from all over memory. The
 * index takes the fourth lane of hi, which the box arithmetic masks off. */
typedef struct primref {
    float lo[4]; /* x y z 0 */
    float hi[3];
    int32_t id;
} __attribute__((aligned(16))) primref;

/* A centre coordinate as aabb_center computes it. */
static inline float ref_center(const primref *r, int axis) { return (r->lo[axis] + r->hi[axis]) * 0.5f; }

typedef struct build {
    int block;
    int max_leaf; /* most primitives a leaf takes */
    primref *refs;
    bvh_node *nodes;
    int nnodes, cap;
    int spawn_depth; /* a second child this deep or less is built on a thread of its own */
} build;

/* Subtrees smaller than this are not worth a thread. */
#define PAR_MIN 4096

/* Room for the nodes of a tree over n primitives, reserved at once so
 * that the array rarely moves (the pages of what stays unused are never
 * touched): at most 2n - 1 (leaves of one), which trees of single
 * primitives come close to (1.73n for 10^6 random spheres); trees of
 * blocks have leaves of several, and start at n / 2. */
static int node_room(const build *b, int n)
{
    if (b->block > 1)
        return n / 2 + 1;
    return n < INT_MAX / 2 ? 2 * n : INT_MAX;
}

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

/* Puts the median primitive by centre on axis at the middle of [lo, hi)
 * (quickselect); the fallback when binning cannot separate the centres. */
static void median_split(build *b, int lo, int hi, int axis, int *mid)
{
    primref *refs = b->refs;
    int k = (lo + hi) / 2, l = lo, r = hi - 1;
    while (l < r) {
        float pivot = ref_center(&refs[(l + r) / 2], axis);
        int i = l, j = r;
        while (i <= j) {
            while (ref_center(&refs[i], axis) < pivot)
                i++;
            while (ref_center(&refs[j], axis) > pivot)
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

/* Cost of testing n primitives: they are tested block-wide at a time. */
static float leaf_cost(const build *b, int n)
{
    return COST_INTERSECT * (float)(b->block == 1 ? n : (n + b->block - 1) / b->block);
}

/* Boxes as the binning loops use them: with SSE, lo and hi in one
 * register each (the fourth lane unused), so that a union is two
 * instructions. Both forms give the same values. */
#if defined(__SSE2__)
typedef struct box4 {
    __m128 lo, hi;
} box4;

static inline box4 box4_empty(void) { return (box4){_mm_set1_ps(FLT_MAX), _mm_set1_ps(-FLT_MAX)}; }

/* A primitive's box, the index masked off hi's fourth lane. */
static inline box4 box4_load(const primref *r)
{
    const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
    return (box4){_mm_load_ps(r->lo), _mm_and_ps(_mm_load_ps(r->hi), xyz)};
}

/* Its centre, as ref_center computes each coordinate. */
static inline __m128 box4_center(box4 b) { return _mm_mul_ps(_mm_add_ps(b.lo, b.hi), _mm_set1_ps(0.5f)); }

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

/* aabb_area(box4_aabb(b)), computed in the register with the same
 * operations in the same order. */
static inline float box4_area(box4 b)
{
    if (_mm_movemask_ps(_mm_cmpgt_ps(b.lo, b.hi)) & 7)
        return 0.0f; /* empty */
    __m128 e = _mm_sub_ps(b.hi, b.lo);                                  /* x y z */
    __m128 p = _mm_mul_ps(e, _mm_shuffle_ps(e, e, _MM_SHUFFLE(3, 0, 2, 1))); /* xy yz zx */
    float xy = _mm_cvtss_f32(p), yz = _mm_cvtss_f32(_mm_shuffle_ps(p, p, 1));
    float zx = _mm_cvtss_f32(_mm_shuffle_ps(p, p, 2));
    return 2.0f * (xy + yz + zx);
}

/* Bin k on each axis of centre c: (c - cmin) * scale, truncated, in
 * [0, nbins - 1]; NaN (a zero extent's 0 * inf) goes to 0. */
static inline void bin_of(__m128 c, __m128 cmin, __m128 scale, __m128 top, int k[3])
{
    __m128 f = _mm_mul_ps(_mm_sub_ps(c, cmin), scale);
    f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), top); /* max_ps gives 0 for NaN */
    __m128i i = _mm_cvttps_epi32(f);
    k[0] = _mm_cvtsi128_si32(i);
    k[1] = _mm_cvtsi128_si32(_mm_shuffle_epi32(i, _MM_SHUFFLE(1, 1, 1, 1)));
    k[2] = _mm_cvtsi128_si32(_mm_shuffle_epi32(i, _MM_SHUFFLE(2, 2, 2, 2)));
}
#else
typedef aabb box4;
static inline box4 box4_empty(void) { return aabb_empty(); }
static inline box4 box4_load(const primref *r)
{
    return (aabb){{r->lo[0], r->lo[1], r->lo[2]}, {r->hi[0], r->hi[1], r->hi[2]}};
}
static inline vec3 box4_center(box4 b) { return aabb_center(b); }
static inline box4 box4_union(box4 a, box4 b) { return aabb_union(a, b); }
static inline box4 box4_grow(box4 a, vec3 p) { return aabb_grow(a, p); }
static inline aabb box4_aabb(box4 b) { return b; }
static inline float box4_area(box4 b) { return aabb_area(b); }
static inline void bin_of(vec3 c, vec3 cmin, vec3 scale, vec3 top, int k[3])
{
    for (int a = 0; a < 3; a++) {
        float f = (v3_at(c, a) - v3_at(cmin, a)) * v3_at(scale, a);
        k[a] = f >= v3_at(top, a) ? (int)v3_at(top, a) : f > 0.0f ? (int)f : 0;
    }
}
#endif

/* The bounds of a node's primitives and of their centres. */
typedef struct bounds {
    box4 box, cbox;
} bounds;

static void bounds_of(const build *b, int lo, int hi, bounds *out)
{
    box4 bx = box4_empty(), cbx = box4_empty();
    for (int i = lo; i < hi; i++) {
        box4 box = box4_load(&b->refs[i]);
        bx = box4_union(bx, box);
        cbx = box4_grow(cbx, box4_center(box));
    }
    *out = (bounds){bx, cbx};
}

/* Partitions refs[lo, hi) so that those with centre below `split` on
 * `axis` come first; returns the first index of the upper part. The
 * bounds of each part are gathered on the way, which spares each child a
 * pass of its own over its primitives. */
static int partition(build *b, int lo, int hi, int axis, float split, bounds *below,
                     bounds *above)
{
    primref *r = b->refs;
    bounds l = {box4_empty(), box4_empty()}, u = l;
    int i = lo, j = hi - 1;
    while (i <= j) {
        box4 box = box4_load(&r[i]);
        if (ref_center(&r[i], axis) < split) {
            l.box = box4_union(l.box, box);
            l.cbox = box4_grow(l.cbox, box4_center(box));
            i++;
        } else {
            u.box = box4_union(u.box, box);
            u.cbox = box4_grow(u.cbox, box4_center(box));
            primref t = r[i];
            r[i] = r[j];
            r[j--] = t;
        }
    }
    *below = l;
    *above = u;
    return i;
}

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
        int k[3];
        box4 box = box4_load(&b->refs[i]);
        bin_of(box4_center(box), cmin4, scale4, top4, k);
        out->n[0][k[0]]++;
        out->box[0][k[0]] = box4_union(out->box[0][k[0]], box);
        out->n[1][k[1]]++;
        out->box[1][k[1]] = box4_union(out->box[1][k[1]], box);
        out->n[2][k[2]]++;
        out->box[2][k[2]] = box4_union(out->box[2][k[2]], box);
    }
}

/* The planes between the bins of axis a, swept from both sides; keeps the
 * cheapest below *best (relative to the parent's area). Only the bins that
 * hold something are visited: the planes between two of them in a row
 * divide the primitives alike and cost the same, and the first of them,
 * the one just after the lower bin, is the one kept (ties keep the first
 * plane), so this finds what a sweep over every plane would. */
static void sweep_axis(const build *b, const bins *bn, int a, float area, float cmin, float scale,
                       float *best, int *axis, float *plane)
{
    int used[BINS], m = 0;
    for (int k = 0; k < bn->nbins; k++) { /* without a branch, which would go either way */
        used[m] = k;
        m += bn->n[a][k] > 0;
    }
    float right_area[BINS];
    int right_n[BINS];
    box4 acc = box4_empty();
    int cnt = 0;
    for (int g = m - 1; g > 0; g--) {
        acc = box4_union(acc, bn->box[a][used[g]]);
        cnt += bn->n[a][used[g]];
        right_area[g] = box4_area(acc);
        right_n[g] = cnt;
    }
    acc = box4_empty();
    cnt = 0;
    for (int g = 0; g + 1 < m; g++) {
        acc = box4_union(acc, bn->box[a][used[g]]);
        cnt += bn->n[a][used[g]];
        float cost = box4_area(acc) * leaf_cost(b, cnt) +
                     right_area[g + 1] * leaf_cost(b, right_n[g + 1]);
        cost = area > 0.0f ? COST_TRAVERSE + cost / area : INFINITY;
        if (cost < *best) {
            *best = cost;
            *axis = a;
            *plane = cmin + (float)(used[g] + 1) / scale;
        }
    }
}

/* The best binned SAH split of [lo, hi) over all three axes: sets *axis
 * and *plane (a centre coordinate) and returns its cost relative to the
 * parent's area, or INFINITY when no plane separates the centres. A node
 * of n < BINS primitives gets max(n, 8) bins: more would mostly stay
 * empty, and sweeping them costs more than binning the primitives. */
/* best_split for two primitives, without the bins: on every axis where
 * their centres differ they fall into the first and the last of the eight
 * bins, so every such axis splits them alike, at the same cost, and the
 * first of them is kept, at the plane after its first bin. */
static float split_pair(const build *b, int lo, aabb box, aabb cbox, int *axis, float *plane)
{
    vec3 ext = aabb_extent(cbox);
    int a = v3_at(ext, 0) > 0.0f ? 0 : v3_at(ext, 1) > 0.0f ? 1 : v3_at(ext, 2) > 0.0f ? 2 : -1;
    if (a < 0)
        return INFINITY;
    box4 p = box4_load(&b->refs[lo]), q = box4_load(&b->refs[lo + 1]);
    bool p_first = ref_center(&b->refs[lo], a) <= ref_center(&b->refs[lo + 1], a);
    box4 first = p_first ? p : q, second = p_first ? q : p;
    float area = aabb_area(box);
    float cost = box4_area(box4_union(box4_empty(), first)) * leaf_cost(b, 1) +
                 box4_area(box4_union(box4_empty(), second)) * leaf_cost(b, 1);
    cost = area > 0.0f ? COST_TRAVERSE + cost / area : INFINITY;
    if (!(cost < INFINITY))
        return INFINITY;
    float scale = 8.0f / v3_at(ext, a);
    *axis = a;
    *plane = v3_at(cbox.lo, a) + 1.0f / scale;
    return cost;
}

static float best_split(const build *b, int lo, int hi, aabb box, aabb cbox, int *axis,
                        float *plane)
{
    float best = INFINITY, scale[3];
    bins bn;
    int n = hi - lo;
    if (n == 2)
        return split_pair(b, lo, box, cbox, axis, plane);
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

static int build_node(build *b, int lo, int hi, int depth, const bounds *given);

/* A subtree built on its own thread into its own node array. */
typedef struct subtree {
    build b;
    int lo, hi, depth, root;
    bounds given;
    bool has_bounds;
} subtree;

static void *subtree_run(void *arg)
{
    subtree *t = arg;
    t->root = build_node(&t->b, t->lo, t->hi, t->depth, t->has_bounds ? &t->given : NULL);
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
static int build_children(build *b, int lo, int mid, int hi, int depth, const bounds *lb,
                          const bounds *ub)
{
    if (depth > b->spawn_depth || hi - mid < PAR_MIN || mid - lo < PAR_MIN) {
        if (build_node(b, lo, mid, depth, lb) < 0)
            return -1;
        return build_node(b, mid, hi, depth, ub);
    }
    subtree t = {*b, mid, hi, depth, -1, {box4_empty(), box4_empty()}, ub != NULL};
    if (ub)
        t.given = *ub;
    t.b.nnodes = 0;
    t.b.cap = node_room(b, hi - mid);
    t.b.nodes = array_alloc_big(sizeof *t.b.nodes * (size_t)t.b.cap);
    if (!t.b.nodes)
        return -1;
    pthread_t th;
    bool threaded = pthread_create(&th, NULL, subtree_run, &t) == 0;
    int first = build_node(b, lo, mid, depth, lb);
    if (threaded)
        pthread_join(th, NULL);
    else
        subtree_run(&t);
    int second = first < 0 || t.root < 0 ? -1 : adopt(b, &t);
    free(t.b.nodes);
    return second;
}

/* given: the bounds of refs[lo, hi) when the parent's partition gathered
 * them (NULL: worked out here). */
static int build_node(build *b, int lo, int hi, int depth, const bounds *given)
{
    int self = new_node(b);
    if (self < 0)
        return -1;
    bounds bd;
    if (given)
        bd = *given;
    else
        bounds_of(b, lo, hi, &bd);
    aabb box = box4_aabb(bd.box), cbox = box4_aabb(bd.cbox);
    bounds lb, ub;
    bool gathered = false;
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
        mid = partition(b, lo, hi, axis, plane, &lb, &ub);
        if (mid == lo || mid == hi)
            goto split_median;
        gathered = true;
        goto recurse;
    }
split_median:
    median_split(b, lo, hi, axis, &mid);
recurse:
    b->nodes[self].axis = (uint8_t)axis;
    b->nodes[self].count = 0;
    int second = build_children(b, lo, mid, hi, depth + 1, gathered ? &lb : NULL,
                                gathered ? &ub : NULL);
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
    build b = {block, max_leaf, NULL, NULL, 0, 0, spawn_depth(cpus)};
    b.refs = array_alloc_big(sizeof *b.refs * (size_t)n);
    out->prims = malloc(sizeof *out->prims * (size_t)n);
    b.cap = node_room(&b, n);
    b.nodes = array_alloc_big(sizeof *b.nodes * (size_t)b.cap);
    if (!b.refs || !out->prims || !b.nodes)
        goto nomem;
    for (int i = 0; i < n; i++) {
        primref *r = &b.refs[i];
        *r = (primref){{boxes[i].lo.x, boxes[i].lo.y, boxes[i].lo.z, 0.0f},
                       {boxes[i].hi.x, boxes[i].hi.y, boxes[i].hi.z}, i};
    }
    if (build_node(&b, 0, n, 0, NULL) < 0)
        goto nomem;
    for (int i = 0; i < n; i++)
        out->prims[i] = b.refs[i].id;
    free(b.refs);
    out->nodes = b.nodes;
    out->nnodes = b.nnodes;
    out->nprims = n;
    return GLINT_OK;
nomem:
    free(b.refs);
    free(out->prims);
    free(b.nodes);
    memset(out, 0, sizeof *out);
    return err_nomem(err);
}

void bvh_free(bvh *b)
{
    free(b->nodes);
    free(b->prims);
    memset(b, 0, sizeof *b);
}
