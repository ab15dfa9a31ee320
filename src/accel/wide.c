#include "wide.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/array.h"
#include "core/error.h"

/* The SAH-optimal choice of which binary nodes become wide nodes, the
 * binary tree's leaves kept as they are (Ylitie, Karras and Laine,
 * "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide
 * BVHs", HPG 2017, section 4.1). With the leaves fixed the SAH cost of the
 * leaves is the same whatever the choice, so what is minimised is the sum
 * of the wide nodes' surface areas: the expected number of node visits.
 * For binary node n and j slots of a wide node, cost[n][j] is the least
 * that n's subtree adds when it fills at most j lanes, pick[n][j] how: 0
 * as with j - 1 lanes, k > 0 its first child in k lanes and its second in
 * j - k; with one lane an interior node becomes a wide node of its own,
 * whose lanes split pick[n][0] : width - pick[n][0] between its children. */
typedef struct plan {
    int width;
    float *cost;  /* nnodes x (width + 1) */
    int8_t *pick; /* the same */
} plan;

typedef struct collapse {
    const bvh *src;
    const plan *plan; /* NULL: open the largest child first (gather) */
    int width;
    size_t node_size;
    char *nodes;
    int nnodes, cap;
} collapse;

void bvhw_lanes_empty(bvhw_lanes *l)
{
    for (int k = 0; k < 8; k++) {
        l->box[k] = (aabb){v3s(INFINITY), v3s(-INFINITY)};
        l->child[k] = -1;
        l->count[k] = 0;
    }
}

void bvhw_store(void *nodes, int width, int at, const bvhw_lanes *l)
{
    int w = width;
    size_t size = w == 8 ? sizeof(bvh8_node) : sizeof(bvh4_node);
    float *box = (float *)(void *)((char *)nodes + (size_t)at * size); /* box[6][w] */
    int32_t *child = (int32_t *)(box + 6 * w);
    uint32_t *count = (uint32_t *)(child + w);
    for (int k = 0; k < w; k++) {
        aabb b = l->box[k];
        box[0 * w + k] = b.lo.x;
        box[1 * w + k] = b.hi.x;
        box[2 * w + k] = b.lo.y;
        box[3 * w + k] = b.hi.y;
        box[4 * w + k] = b.lo.z;
        box[5 * w + k] = b.hi.z;
        child[k] = l->child[k];
        count[k] = l->count[k];
    }
}

static int new_node(collapse *c)
{
    if (c->nnodes == c->cap) {
        int cap = c->cap * 2;
        char *n = aligned_alloc(64, c->node_size * (size_t)cap);
        if (!n)
            return -1;
        memcpy(n, c->nodes, c->node_size * (size_t)c->nnodes);
        free(c->nodes);
        c->nodes = n;
        c->cap = cap;
    }
    return c->nnodes++;
}

/* The area of binary node i if it is an interior node (which may be
 * opened), else -1. Its second child, far away in the depth-first array,
 * is fetched now, in case it is opened. */
static inline float open_area(const bvh_node *bn, int i)
{
    if (bn[i].count != 0)
        return -1.0f;
    __builtin_prefetch(&bn[bn[i].index]);
    return aabb_area(bn[i].box);
}

/* The binary nodes that become node `bin`'s children: its two, then the
 * interior one of largest area opened until there are width of them. */
static int gather(const collapse *c, int bin, int kids[8])
{
    const bvh_node *bn = c->src->nodes;
    /* area[k]: kid k's area if it is an interior node, else -1 (never
     * opened); each worked out once. */
    float area[8];
    int nk = 2;
    kids[0] = bin + 1;
    kids[1] = bn[bin].index;
    for (int k = 0; k < 2; k++)
        area[k] = open_area(bn, kids[k]);
    while (nk < c->width) {
        int best = -1;
        float best_area = -1.0f;
        for (int k = 0; k < nk; k++)
            if (area[k] > best_area) {
                best_area = area[k];
                best = k;
            }
        if (best < 0)
            break;
        int open = kids[best];
        kids[best] = open + 1;
        kids[nk] = bn[open].index;
        area[best] = open_area(bn, open + 1);
        area[nk] = open_area(bn, kids[nk]);
        nk++;
    }
    return nk;
}

/* Works the plan out bottom up: in depth-first order every child comes
 * after its parent. */
static bool plan_make(plan *p, const bvh *b, int width)
{
    int w1 = width + 1;
    p->width = width;
    p->cost = malloc(sizeof *p->cost * (size_t)b->nnodes * (size_t)w1);
    p->pick = malloc(sizeof *p->pick * (size_t)b->nnodes * (size_t)w1);
    if (!p->cost || !p->pick)
        return false;
    for (int n = b->nnodes - 1; n >= 0; n--) {
        float *c = p->cost + (size_t)n * (size_t)w1;
        int8_t *k = p->pick + (size_t)n * (size_t)w1;
        memset(k, 0, (size_t)w1);
        if (b->nodes[n].count) {
            for (int j = 0; j < w1; j++)
                c[j] = 0.0f;
            continue;
        }
        const float *l = p->cost + (size_t)(n + 1) * (size_t)w1;
        const float *r = p->cost + (size_t)b->nodes[n].index * (size_t)w1;
        float own = INFINITY;
        for (int a = 1; a < width; a++)
            if (l[a] + r[width - a] < own) {
                own = l[a] + r[width - a];
                k[0] = (int8_t)a;
            }
        c[1] = aabb_area(b->nodes[n].box) + own;
        for (int j = 2; j < w1; j++) {
            c[j] = c[j - 1];
            for (int a = 1; a < j; a++)
                if (l[a] + r[j - a] < c[j]) {
                    c[j] = l[a] + r[j - a];
                    k[j] = (int8_t)a;
                }
        }
    }
    return true;
}

/* The binary nodes that fill j lanes for subtree n, by the plan. */
static int plan_lanes(const plan *p, const bvh *b, int n, int j, int *kids)
{
    const int8_t *k = p->pick + (size_t)n * (size_t)(p->width + 1);
    while (j > 1 && !b->nodes[n].count && k[j] == 0)
        j--;
    if (j == 1 || b->nodes[n].count) {
        kids[0] = n;
        return 1;
    }
    int got = plan_lanes(p, b, n + 1, k[j], kids);
    return got + plan_lanes(p, b, b->nodes[n].index, j - k[j], kids + got);
}

/* Makes a wide node from binary node `bin` (an interior node); returns its
 * index or -1 when out of memory. Nodes are numbered depth first. */
static int collapse_node(collapse *c, int bin)
{
    int self = new_node(c);
    if (self < 0)
        return -1;
    const bvh_node *bn = c->src->nodes;
    int kids[8], nk;
    if (c->plan) {
        int a = c->plan->pick[(size_t)bin * (size_t)(c->width + 1)];
        nk = plan_lanes(c->plan, c->src, bin + 1, a, kids);
        nk += plan_lanes(c->plan, c->src, c->src->nodes[bin].index, c->width - a, kids + nk);
    } else {
        nk = gather(c, bin, kids);
    }
    bvhw_lanes l;
    bvhw_lanes_empty(&l);
    for (int k = 0; k < nk; k++) {
        const bvh_node *kid = &bn[kids[k]];
        l.box[k] = kid->box;
        if (kid->count) {
            l.child[k] = -1 - kid->index;
            l.count[k] = kid->count;
        } else {
            int sub = collapse_node(c, kids[k]);
            if (sub < 0)
                return -1;
            l.child[k] = sub;
        }
    }
    bvhw_store(c->nodes, c->width, self, &l);
    return self;
}

glint_rc bvhw_from_bvh(bvhw *out, bvh *b, accel_isa isa, bool optimal, glint_error *err)
{
    memset(out, 0, sizeof *out);
    out->isa = isa;
    out->width = accel_isa_width(isa);
    out->bounds = aabb_empty();
    if (b->nnodes == 0) {
        bvh_free(b);
        return GLINT_OK;
    }
    /* Room for about as many wide nodes as a tree of small leaves makes
     * (a fifth of the binary nodes for eight-wide, half for four-wide);
     * pages never written cost nothing, and a larger tree grows it. */
    plan p = {0};
    bool planned = optimal && b->nnodes > 1;
    collapse c = {b, planned ? &p : NULL, out->width,
                  out->width == 8 ? sizeof(bvh8_node) : sizeof(bvh4_node),
                  NULL, 0, b->nnodes / (out->width == 8 ? 5 : 2) + 2};
    c.nodes = array_alloc_big(c.node_size * (size_t)c.cap);
    if (!c.nodes || (planned && !plan_make(&p, b, out->width))) {
        free(c.nodes), free(p.cost), free(p.pick);
        bvh_free(b);
        return err_nomem(err);
    }
    if (b->nodes[0].count) { /* a single leaf: one node with one lane */
        bvhw_lanes l;
        bvhw_lanes_empty(&l);
        l.box[0] = b->nodes[0].box;
        l.child[0] = -1 - b->nodes[0].index;
        l.count[0] = b->nodes[0].count;
        bvhw_store(c.nodes, c.width, new_node(&c), &l);
        out->leaf_root = true;
    } else if (collapse_node(&c, 0) < 0) {
        free(c.nodes), free(p.cost), free(p.pick);
        bvh_free(b);
        return err_nomem(err);
    }
    free(p.cost), free(p.pick);
    if (c.width == 8)
        out->n8 = (bvh8_node *)(void *)c.nodes;
    else
        out->n4 = (bvh4_node *)(void *)c.nodes;
    out->nnodes = c.nnodes;
    out->fetch_ahead = bvhw_node_bytes(out) > WIDE_FETCH_BYTES;
    out->prims = b->prims;
    out->nprims = b->nprims;
    out->bounds = b->nodes[0].box;
    b->prims = NULL;
    bvh_free(b);
    return GLINT_OK;
}

void bvhw_free(bvhw *b)
{
    free(b->width == 8 ? (void *)b->n8 : (void *)b->n4);
    free(b->prims);
    free(b->refs);
    memset(b, 0, sizeof *b);
}

size_t bvhw_node_bytes(const bvhw *b)
{
    return (size_t)b->nnodes * (b->width == 8 ? sizeof(bvh8_node) : sizeof(bvh4_node));
}
