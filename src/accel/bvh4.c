#include "bvh4.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

typedef struct collapse {
    const bvh *src;
    bvh4_node *nodes;
    int nnodes, cap;
} collapse;

static void set_lane(bvh4_node *n, int k, aabb b)
{
    n->box[0][k] = b.lo.x;
    n->box[1][k] = b.hi.x;
    n->box[2][k] = b.lo.y;
    n->box[3][k] = b.hi.y;
    n->box[4][k] = b.lo.z;
    n->box[5][k] = b.hi.z;
}

/* Makes a bvh4 node from binary node `bin` (an interior node); returns its
 * index or -1 when out of memory. Children are gathered by opening the
 * largest interior child until there are four. */
static int collapse_node(collapse *c, int bin)
{
    if (c->nnodes == c->cap) {
        int cap = c->cap * 2;
        bvh4_node *n = aligned_alloc(64, sizeof *n * (size_t)cap);
        if (!n)
            return -1;
        memcpy(n, c->nodes, sizeof *n * (size_t)c->nnodes);
        free(c->nodes);
        c->nodes = n;
        c->cap = cap;
    }
    int self = c->nnodes++;
    const bvh_node *bn = c->src->nodes;
    int kids[4] = {bin + 1, bn[bin].index, -1, -1}, nk = 2;
    while (nk < 4) {
        int best = -1;
        float best_area = -1.0f;
        for (int k = 0; k < nk; k++)
            if (bn[kids[k]].count == 0 && aabb_area(bn[kids[k]].box) > best_area) {
                best_area = aabb_area(bn[kids[k]].box);
                best = k;
            }
        if (best < 0)
            break;
        int open = kids[best];
        kids[best] = open + 1;
        kids[nk++] = bn[open].index;
    }
    bvh4_node tmp;
    memset(&tmp, 0, sizeof tmp);
    for (int k = 0; k < 4; k++) {
        if (k >= nk) {
            set_lane(&tmp, k, (aabb){v3s(INFINITY), v3s(-INFINITY)});
            tmp.child[k] = -1;
            tmp.count[k] = 0;
            continue;
        }
        const bvh_node *kid = &bn[kids[k]];
        set_lane(&tmp, k, kid->box);
        if (kid->count) {
            tmp.child[k] = -1 - kid->index;
            tmp.count[k] = kid->count;
        } else {
            int sub = collapse_node(c, kids[k]);
            if (sub < 0)
                return -1;
            tmp.child[k] = sub;
            tmp.count[k] = 0;
        }
    }
    c->nodes[self] = tmp;
    return self;
}

glint_rc bvh4_from_bvh(bvh4 *out, bvh *b, glint_error *err)
{
    memset(out, 0, sizeof *out);
    out->bounds = aabb_empty();
    if (b->nnodes == 0) {
        bvh_free(b);
        return GLINT_OK;
    }
    collapse c = {b, NULL, 0, b->nnodes / 2 + 2};
    c.nodes = aligned_alloc(64, sizeof *c.nodes * (size_t)c.cap);
    if (!c.nodes) {
        bvh_free(b);
        return err_nomem(err);
    }
    if (b->nodes[0].count) {
        /* A single leaf: one node with one lane. */
        bvh4_node *n = &c.nodes[0];
        memset(n, 0, sizeof *n);
        for (int k = 0; k < 4; k++) {
            set_lane(n, k, k == 0 ? b->nodes[0].box : (aabb){v3s(INFINITY), v3s(-INFINITY)});
            n->child[k] = -1;
        }
        n->child[0] = -1 - b->nodes[0].index;
        n->count[0] = b->nodes[0].count;
        c.nnodes = 1;
    } else if (collapse_node(&c, 0) < 0) {
        free(c.nodes);
        bvh_free(b);
        return err_nomem(err);
    }
    out->nodes = c.nodes;
    out->nnodes = c.nnodes;
    out->prims = b->prims;
    out->nprims = b->nprims;
    out->bounds = b->nodes[0].box;
    b->prims = NULL;
    bvh_free(b);
    return GLINT_OK;
}

void bvh4_free(bvh4 *b)
{
    free(b->nodes);
    free(b->prims);
    memset(b, 0, sizeof *b);
}
