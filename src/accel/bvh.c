#include "bvh.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/array.h"
#include "core/cpus.h"
#include "core/error.h"

#include "split.h"

#define MAX_LEAF 4
/* Primitives tested block-wide at a time (bvh_build_blocked) go up to this
 * many blocks to a leaf, when the SAH finds that cheaper than a split: on
 * the bunny that takes the eight-wide nodes from 5,280 to about 4,100 (mesh
 * and BVH from 80 to 75 bytes a triangle) for the same speed. */
#define LEAF_BLOCKS 2

typedef struct build {
    split_ctx s; /* the primitives, and what a split depends on */
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
    if (b->s.block > 1)
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

static int build_node(build *b, int lo, int hi, int depth, const cbox *given);

/* A subtree built on its own thread into its own node array. */
typedef struct subtree {
    build b;
    int lo, hi, depth, root;
    cbox given;
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
static int build_children(build *b, int lo, int mid, int hi, int depth, const cbox *lb,
                          const cbox *ub)
{
    if (depth > b->spawn_depth || hi - mid < PAR_MIN || mid - lo < PAR_MIN) {
        if (build_node(b, lo, mid, depth, lb) < 0)
            return -1;
        return build_node(b, mid, hi, depth, ub);
    }
    subtree t = {*b, mid, hi, depth, -1, cbox_empty(), ub != NULL};
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

static void set_box(bvh_node *n, box4 b) { n->box = box4_aabb(b); }

/* given: the centre bounds of refs[lo, hi) when the parent's partition
 * gathered them (NULL: worked out here). */
static int build_node(build *b, int lo, int hi, int depth, const cbox *given)
{
    int self = new_node(b);
    if (self < 0)
        return -1;
    int n = hi - lo, mid = lo, axis;
    float plane = 0.0f;
    box4 box;
    cbox lb, ub;
    bool gathered = false;
    split_kind kind = split_decide(&b->s, lo, hi, depth, given, &box, &axis, &plane);
    set_box(&b->nodes[self], box);
    if (kind == SPLIT_LEAF) {
        b->nodes[self].index = lo;
        b->nodes[self].count = (uint16_t)n;
        b->nodes[self].axis = 0;
        return self;
    }
    if (kind == SPLIT_PLANE) {
        mid = split_partition(&b->s, lo, hi, axis, plane, &lb, &ub);
        gathered = mid != lo && mid != hi;
    }
    if (!gathered)
        split_median(&b->s, lo, hi, axis, &mid);
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
    cpus = cpus_threads(cpus, 1024);
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
    build b = {{block, max_leaf, NULL, 1, accel_isa_active() >= ACCEL_AVX2}, NULL, 0, 0,
               spawn_depth(cpus)};
    b.s.refs = array_alloc_big(sizeof *b.s.refs * (size_t)n);
    out->prims = malloc(sizeof *out->prims * (size_t)n);
    b.cap = node_room(&b, n);
    b.nodes = array_alloc_big(sizeof *b.nodes * (size_t)b.cap);
    if (!b.s.refs || !out->prims || !b.nodes)
        goto nomem;
    for (int i = 0; i < n; i++) {
        primref *r = &b.s.refs[i];
        *r = (primref){{boxes[i].lo.x, boxes[i].lo.y, boxes[i].lo.z, INFINITY},
                       {-boxes[i].hi.x, -boxes[i].hi.y, -boxes[i].hi.z}, i};
    }
    if (build_node(&b, 0, n, 0, NULL) < 0)
        goto nomem;
    for (int i = 0; i < n; i++)
        out->prims[i] = b.s.refs[i].id;
    free(b.s.refs);
    out->nodes = b.nodes;
    out->nnodes = b.nnodes;
    out->nprims = n;
    return GLINT_OK;
nomem:
    free(b.s.refs);
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

