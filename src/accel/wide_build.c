#include "wide.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "accel/split.h"
#include "core/array.h"
#include "core/cpus.h"
#include "core/error.h"

/* ---- The wide hierarchy built directly ----
 *
 * bvhw_build makes the tree that bvh_build followed by bvhw_from_bvh
 * makes, without the binary nodes in between: a wide node takes the two
 * halves of its range's split, then splits the one of largest area that
 * may be split and fits (a bundle's primitives each take a lane) until it
 * has width of them, as the collapse opens binary nodes. A range is
 * evaluated (its box, and whether and where it splits) when it becomes a
 * kid, since its area decides which kid opens next; it is partitioned
 * when it opens. */

enum { KID_LEAF, KID_BUNDLE, KID_INNER, KID_PRIM };

typedef struct wkid {
    box4 box;
    int lo, hi, depth;
    int kind;
    int axis;    /* KID_INNER: the split axis */
    float plane; /* and plane (a centre coordinate) */
    bool median; /* split at the median on axis instead */
} wkid;

typedef struct wbuild {
    split_ctx s;
    int bundle; /* ranges of at most this many are bundles (0: none) */
    int width;
    size_t node_size;
    char *nodes;
    int nnodes, cap;
} wbuild;

/* What build_node decides for the range of k (given: its centre bounds,
 * or NULL), but for partitioning it. */
static void eval_kid(const wbuild *w, wkid *k, const cbox *given)
{
    int lo = k->lo, hi = k->hi, n = hi - lo;
    if (n <= w->bundle && n > 1) {
        cbox cb;
        split_bounds(&w->s, lo, hi, &k->box, &cb);
        k->kind = KID_BUNDLE;
        return;
    }
    float plane = 0.0f;
    int axis;
    split_kind kind = split_decide(&w->s, lo, hi, k->depth, given, &k->box, &axis, &plane);
    k->kind = kind == SPLIT_LEAF ? KID_LEAF : KID_INNER;
    k->axis = axis;
    k->plane = plane;
    k->median = kind == SPLIT_MEDIAN;
}

/* Splits inner kid k into its two halves, evaluated. */
static void open_kid(wbuild *w, const wkid *k, wkid *left, wkid *right)
{
    cbox lb, ub;
    int mid = k->lo;
    bool gathered = false;
    if (!k->median) {
        mid = split_partition(&w->s, k->lo, k->hi, k->axis, k->plane, &lb, &ub);
        gathered = mid != k->lo && mid != k->hi;
    }
    if (!gathered)
        split_median(&w->s, k->lo, k->hi, k->axis, &mid);
    *left = (wkid){.lo = k->lo, .hi = mid, .depth = k->depth + 1};
    *right = (wkid){.lo = mid, .hi = k->hi, .depth = k->depth + 1};
    eval_kid(w, left, gathered ? &lb : NULL);
    eval_kid(w, right, gathered ? &ub : NULL);
}

/* Room for `need` nodes. */
static bool wreserve(wbuild *w, int need)
{
    int cap = w->cap;
    while (cap < need)
        cap *= 2;
    char *n = array_alloc_big(w->node_size * (size_t)cap);
    if (!n)
        return false;
    memcpy(n, w->nodes, w->node_size * (size_t)w->nnodes);
    free(w->nodes);
    w->nodes = n;
    w->cap = cap;
    return true;
}

static int wnew(wbuild *w)
{
    if (w->nnodes == w->cap && !wreserve(w, w->cap + 1))
        return -1;
    return w->nnodes++;
}

/* A lane's box as stored: zeros of either sign stored as +0, so that the
 * stored boxes are the same whichever order their unions were taken in. */
static inline aabb lane_box(box4 b)
{
    v4 lo = v4_add(b.lo, v4_splat(0.0f)), hi = v4_add(v4_neg(b.nhi), v4_splat(0.0f));
    return (aabb){v3(v4_x(lo), v4_y(lo), v4_z(lo)), v3(v4_x(hi), v4_y(hi), v4_z(hi))};
}

/* A wide node of bundle k's primitives, a lane each. */
static int wbundle(wbuild *w, const wkid *k)
{
    int self = wnew(w);
    if (self < 0)
        return -1;
    bvhw_lanes l;
    bvhw_lanes_empty(&l);
    for (int i = 0; i < k->hi - k->lo; i++) {
        l.box[i] = lane_box(box4_load(&w->s.refs[k->lo + i]));
        l.child[i] = -1 - (k->lo + i);
        l.count[i] = 1;
    }
    bvhw_store(w->nodes, w->width, self, &l);
    return self;
}

/* The kids of a wide node made from inner kid k: its halves, then the
 * kid of largest area that may open (an inner kid, or a bundle whose
 * primitives fit), opened until there are width of them. */
static int wgather(wbuild *w, const wkid *k, wkid kids[8])
{
    float area[8];
    open_kid(w, k, &kids[0], &kids[1]);
    int nk = 2;
    for (int i = 0; i < 2; i++)
        area[i] = kids[i].kind == KID_INNER || kids[i].kind == KID_BUNDLE ? box4_area(kids[i].box)
                                                                          : -1.0f;
    while (nk < w->width) {
        int best = -1;
        float best_area = -1.0f;
        for (int i = 0; i < nk; i++) {
            int adds = kids[i].kind == KID_BUNDLE ? kids[i].hi - kids[i].lo - 1 : 1;
            if (area[i] > best_area && nk + adds <= w->width) {
                best_area = area[i];
                best = i;
            }
        }
        if (best < 0)
            break;
        wkid o = kids[best];
        if (o.kind == KID_BUNDLE) {
            for (int i = 0; i < o.hi - o.lo; i++) {
                int at = i == 0 ? best : nk++;
                kids[at] = (wkid){.lo = o.lo + i, .hi = o.lo + i + 1, .kind = KID_PRIM};
                area[at] = -1.0f;
            }
            continue;
        }
        open_kid(w, &o, &kids[best], &kids[nk]);
        for (int i = 0; i < 2; i++) {
            int at = i == 0 ? best : nk;
            area[at] = kids[at].kind == KID_INNER || kids[at].kind == KID_BUNDLE
                           ? box4_area(kids[at].box)
                           : -1.0f;
        }
        nk++;
    }
    return nk;
}

static int wnode(wbuild *w, const wkid *k);

/* The subtree of kid k: a lane of its own (-1 - first primitive, with
 * *count) or a wide node (its index). */
static int wlane(wbuild *w, const wkid *k, uint32_t *count)
{
    switch (k->kind) {
    case KID_PRIM:
    case KID_LEAF:
        *count = (uint32_t)(k->hi - k->lo);
        return -1 - k->lo;
    case KID_BUNDLE:
        *count = 0;
        return wbundle(w, k);
    default:
        *count = 0;
        return wnode(w, k);
    }
}

/* A kid's subtree built into a node array of its own (wtask), on one of
 * the threads of a wpool. */
typedef struct wtask {
    wbuild own;
    wbuild *w; /* own, or for the first the parent's array, which it extends in place */
    wkid kid;
    int root; /* -1: out of memory */
} wtask;

typedef struct wpool {
    wtask *task;
    int order[8]; /* largest first, so that the threads finish together */
    int ntasks;
    atomic_int next;
} wpool;

static void *wpool_run(void *arg)
{
    wpool *p = arg;
    for (int i; (i = atomic_fetch_add(&p->next, 1)) < p->ntasks;) {
        wtask *t = &p->task[p->order[i]];
        uint32_t count;
        t->root = wlane(t->w, &t->kid, &count);
    }
    return NULL;
}

/* Appends t's nodes to w's, renumbering its children; returns where its
 * root went, or -1. */
static int wadopt(wbuild *w, const wtask *t)
{
    if (t->root < 0)
        return -1;
    if (t->w == w)
        return t->root;
    const wbuild *o = &t->own;
    if (w->nnodes + o->nnodes > w->cap && !wreserve(w, w->nnodes + o->nnodes))
        return -1;
    int base = w->nnodes, wd = w->width;
    memcpy(w->nodes + (size_t)base * w->node_size, o->nodes, (size_t)o->nnodes * w->node_size);
    for (int i = 0; i < o->nnodes; i++) {
        int32_t *child = (int32_t *)(void *)(w->nodes + (size_t)(base + i) * w->node_size +
                                             6 * (size_t)wd * sizeof(float));
        for (int k = 0; k < wd; k++)
            child[k] += child[k] >= 0 ? base : 0;
    }
    w->nnodes += o->nnodes;
    return base + t->root;
}

/* The subtrees of kids[0, nk) that are nodes, built on `threads` threads
 * at once, then appended in order: the same nodes in the same order as
 * one thread makes. Sets child[i] for them. */
static bool wkids_par(wbuild *w, const wkid *kids, int nk, int threads, int32_t *child)
{
    wtask task[8];
    wpool pool = {task, {0}, 0, 0};
    int of[8];
    bool ok = true;
    for (int i = 0; i < nk; i++) {
        of[i] = -1;
        if (kids[i].kind != KID_INNER && kids[i].kind != KID_BUNDLE)
            continue;
        wtask *t = &task[pool.ntasks];
        *t = (wtask){*w, &t->own, kids[i], -1};
        t->own.s.threads = 1;
        t->own.nnodes = 0;
        t->own.nodes = NULL;
        if (pool.ntasks == 0) { /* right after this node: in place */
            t->w = w;
        } else {
            t->own.cap = (kids[i].hi - kids[i].lo) / 2 + 16;
            t->own.nodes = array_alloc_big(t->own.node_size * (size_t)t->own.cap);
            ok = ok && t->own.nodes;
        }
        of[i] = pool.ntasks;
        int j = pool.ntasks++, size = kids[i].hi - kids[i].lo;
        for (; j > 0 && task[pool.order[j - 1]].kid.hi - task[pool.order[j - 1]].kid.lo < size; j--)
            pool.order[j] = pool.order[j - 1];
        pool.order[j] = of[i];
    }
    int par = w->s.threads;
    w->s.threads = 1; /* the threads are busy with the kids */
    if (ok)
        cpus_share(threads < pool.ntasks ? threads : pool.ntasks, wpool_run, &pool);
    w->s.threads = par;
    for (int i = 0; i < nk; i++)
        if (of[i] >= 0 && ok)
            ok = (child[i] = wadopt(w, &task[of[i]])) >= 0;
    for (int i = 0; i < pool.ntasks; i++)
        free(task[i].own.nodes);
    return ok;
}

/* threads > 1: the kids' subtrees are built on that many threads. */
static int wnode_on(wbuild *w, const wkid *k, int threads)
{
    int self = wnew(w);
    if (self < 0)
        return -1;
    wkid kids[8];
    int nk = wgather(w, k, kids);
    bvhw_lanes l;
    bvhw_lanes_empty(&l);
    for (int i = 0; i < nk; i++) {
        l.box[i] = lane_box(kids[i].kind == KID_PRIM ? box4_load(&w->s.refs[kids[i].lo])
                                                     : kids[i].box);
        if (threads > 1 && (kids[i].kind == KID_INNER || kids[i].kind == KID_BUNDLE))
            continue; /* below */
        l.child[i] = wlane(w, &kids[i], &l.count[i]);
        if (l.child[i] == -1 && l.count[i] == 0)
            return -1;
    }
    if (threads > 1 && !wkids_par(w, kids, nk, threads, l.child))
        return -1;
    bvhw_store(w->nodes, w->width, self, &l);
    return self;
}

static int wnode(wbuild *w, const wkid *k) { return wnode_on(w, k, 1); }

/* Trees smaller than this are built on one thread. */
#define PAR_MIN 16384

/* The tree of a root that does not split: one node, whose first lane is
 * the leaf, or whose lanes are the bundle's primitives. */
static bool wsingle(wbuild *w, const wkid *root)
{
    int self = wnew(w), n = root->hi - root->lo;
    if (self < 0)
        return false;
    bvhw_lanes l;
    bvhw_lanes_empty(&l);
    if (root->kind == KID_LEAF) {
        l.box[0] = lane_box(root->box);
        l.count[0] = (uint32_t)n;
    } else
        for (int i = 0; i < n; i++) {
            l.box[i] = lane_box(box4_load(&w->s.refs[i]));
            l.child[i] = -1 - i;
            l.count[i] = 1;
        }
    bvhw_store(w->nodes, w->width, self, &l);
    return true;
}

/* The arrays of the last build (old) large enough for n primitives go to
 * w and out, the others are freed, and those missing are allocated:
 * false when out of memory. */
static bool wtake_arrays(bvhw *old, bvhw *out, wbuild *w, int n)
{
    if (old->width == out->width && old->cap_nodes >= w->cap) {
        w->nodes = (char *)(old->width == 8 ? (void *)old->n8 : (void *)old->n4);
        w->cap = old->cap_nodes;
        old->n8 = NULL;
    }
    if (old->cap_prims >= n) {
        out->prims = old->prims;
        out->cap_prims = old->cap_prims;
        old->prims = NULL;
    }
    if (old->cap_refs >= n) {
        w->s.refs = old->refs;
        out->cap_refs = old->cap_refs;
        old->refs = NULL;
    }
    bvhw_free(old);
    if (!w->s.refs) {
        w->s.refs = array_alloc_big(sizeof *w->s.refs * (size_t)n);
        out->cap_refs = n;
    }
    if (!out->prims) {
        out->prims = malloc(sizeof *out->prims * (size_t)n);
        out->cap_prims = n;
    }
    if (!w->nodes)
        w->nodes = array_alloc_big(w->node_size * (size_t)w->cap);
    return w->s.refs && out->prims && w->nodes;
}

glint_rc bvhw_build(bvhw *out, const aabb *boxes, const int32_t *ids, int n, int max_leaf,
                    int bundle, accel_isa isa, int cpus, glint_error *err)
{
    memset(out, 0, sizeof *out);
    return bvhw_rebuild(out, boxes, ids, n, max_leaf, bundle, isa, cpus, err);
}

glint_rc bvhw_rebuild(bvhw *out, const aabb *boxes, const int32_t *ids, int n, int max_leaf,
                      int bundle, accel_isa isa, int cpus, glint_error *err)
{
    bvhw old = *out;
    memset(out, 0, sizeof *out);
    out->isa = isa;
    out->width = accel_isa_width(isa);
    out->bounds = aabb_empty();
    int threads = n >= PAR_MIN ? cpus_threads(cpus, 1024) : 1;
    /* Room for as many nodes as half the primitives (a tree of bundles
     * makes about 0.29 per primitive, eight wide); pages never written
     * cost nothing, and a larger tree grows it. */
    wbuild w = {{1, max_leaf, NULL, threads, isa >= ACCEL_AVX2},
                bundle < out->width ? bundle : out->width,
                out->width,
                out->width == 8 ? sizeof(bvh8_node) : sizeof(bvh4_node),
                NULL,
                0,
                n / 2 + 16};
    if (n <= 0) {
        bvhw_free(&old);
        return GLINT_OK;
    }
    if (!wtake_arrays(&old, out, &w, n))
        goto nomem;
    for (int i = 0; i < n; i++) {
        int id = ids ? ids[i] : i;
        const aabb *bx = &boxes[id];
        w.s.refs[i] = (primref){{bx->lo.x, bx->lo.y, bx->lo.z, INFINITY},
                                {-bx->hi.x, -bx->hi.y, -bx->hi.z}, id};
    }
    wkid root = {.lo = 0, .hi = n, .depth = 0};
    eval_kid(&w, &root, NULL);
    if (root.kind == KID_INNER) {
        if (wnode_on(&w, &root, threads) < 0)
            goto nomem;
    } else if (wsingle(&w, &root)) {
        out->leaf_root = root.kind == KID_LEAF;
    } else {
        goto nomem;
    }
    for (int i = 0; i < n; i++)
        out->prims[i] = w.s.refs[i].id;
    out->refs = w.s.refs;
    if (out->width == 8)
        out->n8 = (bvh8_node *)(void *)w.nodes;
    else
        out->n4 = (bvh4_node *)(void *)w.nodes;
    out->nnodes = w.nnodes;
    out->cap_nodes = w.cap;
    out->fetch_ahead = bvhw_node_bytes(out) > WIDE_FETCH_BYTES;
    out->nprims = n;
    out->bounds = lane_box(root.box);
    return GLINT_OK;
nomem:
    free(w.s.refs);
    free(out->prims);
    free(w.nodes);
    memset(out, 0, sizeof *out);
    return err_nomem(err);
}

