#include "bvh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

#define BINS 32
#define MAX_LEAF 4
#define COST_TRAVERSE 1.0f
#define COST_INTERSECT 1.0f

typedef struct build {
    const aabb *boxes;
    int block;
    vec3 *centers;
    int32_t *prims;
    bvh_node *nodes;
    int nnodes, cap;
} build;

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

/* The best binned SAH split of [lo, hi) over all three axes: sets *axis
 * and *plane (a centre coordinate) and returns its cost relative to the
 * parent's area, or INFINITY when no plane separates the centres. */
static float best_split(const build *b, int lo, int hi, aabb box, aabb cbox, int *axis,
                        float *plane)
{
    float best = INFINITY;
    float area = aabb_area(box);
    for (int a = 0; a < 3; a++) {
        float cmin = v3_at(cbox.lo, a), cext = v3_at(cbox.hi, a) - cmin;
        if (!(cext > 0.0f))
            continue;
        aabb bin_box[BINS];
        int bin_n[BINS] = {0};
        for (int i = 0; i < BINS; i++)
            bin_box[i] = aabb_empty();
        float scale = (float)BINS / cext;
        for (int i = lo; i < hi; i++) {
            /* compared as a float first: with an extent near the smallest
             * normal float, scale is infinite and so may be the product */
            float f = (v3_at(b->centers[b->prims[i]], a) - cmin) * scale;
            int k = f >= (float)BINS ? BINS - 1 : f > 0.0f ? (int)f : 0;
            bin_n[k]++;
            bin_box[k] = aabb_union(bin_box[k], b->boxes[b->prims[i]]);
        }
        /* Sweep from the right for the area and count right of each plane. */
        float right_area[BINS];
        int right_n[BINS];
        aabb acc = aabb_empty();
        int cnt = 0;
        for (int i = BINS - 1; i > 0; i--) {
            acc = aabb_union(acc, bin_box[i]);
            cnt += bin_n[i];
            right_area[i] = aabb_area(acc);
            right_n[i] = cnt;
        }
        acc = aabb_empty();
        cnt = 0;
        for (int i = 1; i < BINS; i++) {
            acc = aabb_union(acc, bin_box[i - 1]);
            cnt += bin_n[i - 1];
            if (cnt == 0 || right_n[i] == 0)
                continue;
            float cost = aabb_area(acc) * leaf_cost(b, cnt) + right_area[i] * leaf_cost(b, right_n[i]);
            cost = area > 0.0f ? COST_TRAVERSE + cost / area : INFINITY;
            if (cost < best) {
                best = cost;
                *axis = a;
                *plane = cmin + (float)i / scale;
            }
        }
    }
    return best;
}

static int build_node(build *b, int lo, int hi, int depth)
{
    int self = new_node(b);
    if (self < 0)
        return -1;
    aabb box = aabb_empty(), cbox = aabb_empty();
    for (int i = lo; i < hi; i++) {
        box = aabb_union(box, b->boxes[b->prims[i]]);
        cbox = aabb_grow(cbox, b->centers[b->prims[i]]);
    }
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
            if (n <= MAX_LEAF)
                goto leaf;
            goto split_median;
        }
        if (n <= MAX_LEAF && leaf_cost(b, n) <= split)
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
    if (build_node(b, lo, mid, depth + 1) < 0)
        return -1;
    int second = build_node(b, mid, hi, depth + 1);
    if (second < 0)
        return -1;
    b->nodes[self].index = second;
    return self;
}

glint_rc bvh_build(bvh *out, const aabb *boxes, int n, glint_error *err)
{
    return bvh_build_blocked(out, boxes, n, 1, err);
}

glint_rc bvh_build_blocked(bvh *out, const aabb *boxes, int n, int block, glint_error *err)
{
    memset(out, 0, sizeof *out);
    if (n <= 0)
        return GLINT_OK;
    build b = {boxes, block > 0 ? block : 1, NULL, NULL, NULL, 0, 0};
    b.centers = malloc(sizeof *b.centers * (size_t)n);
    b.prims = malloc(sizeof *b.prims * (size_t)n);
    b.cap = 2 * (n / MAX_LEAF + 1) + 1;
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
