/* Constructive solid geometry by ray classification (csg.h). */
#include "csg.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/array.h"

const char *const csg_op_names[] = {"union", "intersection", "difference", NULL};
_Static_assert(sizeof csg_op_names / sizeof *csg_op_names == CSG_OP_COUNT + 1,
               "csg_op_names names every csg_op, in order");

int32_t csg_add_leaf(csg *c, const shape *s, const xform *x, int material)
{
    if (c->nleaves >= CSG_MAX_LEAVES)
        return CSG_FULL;
    int i = array_push((void **)&c->leaves, &c->nleaves, &c->cap_leaves, sizeof *c->leaves);
    if (i < 0)
        return CSG_NOMEM;
    c->leaves[i] = (csg_leaf){.shape = *s, .moved = x != NULL, .material = material};
    c->leaves[i].x = x ? *x : xform_identity();
    return i;
}

int32_t csg_add_node(csg *c, csg_op op, const int32_t *operands, int count)
{
    int first = c->nkids;
    for (int i = 0; i < count; i++) {
        int k = array_push((void **)&c->kids, &c->nkids, &c->cap_kids, sizeof *c->kids);
        if (k < 0)
            return CSG_NOMEM;
        c->kids[k] = operands[i];
    }
    int n = array_push((void **)&c->nodes, &c->nnodes, &c->cap_nodes, sizeof *c->nodes);
    if (n < 0)
        return CSG_NOMEM;
    c->nodes[n] = (csg_node){op, first, count};
    return CSG_NODE(n);
}

static aabb leaf_bounds(const csg_leaf *l)
{
    aabb b = shape_bounds(&l->shape);
    if (!l->moved || aabb_is_empty(b))
        return b;
    aabb r = aabb_empty();
    for (int i = 0; i < 8; i++) {
        vec3 p = v3(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z);
        r = aabb_grow(r, mat4_point(&l->x.fwd, p));
    }
    return r;
}

/* Flips and bounds below operand ref, whose normals turn when flip. */
static aabb finish(csg *c, int32_t ref, bool flip)
{
    if (ref >= 0) {
        c->leaves[ref].flip = flip;
        return c->leaves[ref].bounds = leaf_bounds(&c->leaves[ref]);
    }
    const csg_node *n = &c->nodes[-1 - ref];
    aabb b = aabb_empty();
    for (int i = 0; i < n->count; i++) {
        bool sub = n->op == CSG_DIFFERENCE && i > 0;
        aabb k = finish(c, c->kids[n->first + i], flip != sub);
        if (i == 0 || n->op == CSG_UNION)
            b = aabb_union(b, k);
        else if (n->op == CSG_INTERSECTION)
            b = (aabb){v3_max(b.lo, k.lo), v3_min(b.hi, k.hi)};
    }
    return b;
}

void csg_free(csg *c)
{
    if (!c)
        return;
    free(c->leaves);
    free(c->nodes);
    free(c->kids);
    memset(c, 0, sizeof *c);
}

/* An operand's state: a leaf's or an evaluated node's. */
static inline bool is_in(int32_t ref, const uint8_t *in, const uint8_t *node_in)
{
    return ref >= 0 ? in[ref] : node_in[-1 - ref];
}

/* The tree's answer for the leaves' states; nodes come after their
 * operands, so one pass in order suffices. Each node stops at the first
 * operand that settles it. */
static bool evaluate(const csg *c, const uint8_t *in, uint8_t *node_in)
{
    for (int k = 0; k < c->nnodes; k++) {
        const csg_node *n = &c->nodes[k];
        const int32_t *kid = c->kids + n->first;
        int i = 0;
        bool v = false;
        switch (n->op) {
        case CSG_UNION: /* any */
            while (i < n->count && !is_in(kid[i], in, node_in))
                i++;
            v = i < n->count;
            break;
        case CSG_INTERSECTION: /* all */
            while (i < n->count && is_in(kid[i], in, node_in))
                i++;
            v = i == n->count;
            break;
        case CSG_DIFFERENCE: /* the first and none of the others */
            if (n->count > 0 && is_in(kid[0], in, node_in))
                for (i = 1, v = true; v && i < n->count; i++)
                    v = !is_in(kid[i], in, node_in);
            break;
        case CSG_OP_COUNT:
            break;
        }
        node_in[k] = v;
    }
    return c->nnodes ? node_in[c->nnodes - 1] : false;
}

/* The tree's table (csg.h), when it is small enough for one. */
static void tabulate(csg *c)
{
    memset(c->table, 0, sizeof c->table);
    if (c->nleaves > CSG_TABLE_LEAVES)
        return;
    uint8_t in[CSG_TABLE_LEAVES], node_in[CSG_MAX_LEAVES];
    for (unsigned s = 0; s < 1u << c->nleaves; s++) {
        for (int i = 0; i < c->nleaves; i++)
            in[i] = s >> i & 1;
        if (evaluate(c, in, node_in))
            c->table[s >> 6] |= (uint64_t)1 << (s & 63);
    }
}

/* The tree's answer for the leaves' states in (bits: the same, for the
 * first CSG_TABLE_LEAVES leaves). */
static inline bool answer(const csg *c, const uint8_t *in, unsigned bits, uint8_t *node_in)
{
    if (c->nleaves <= CSG_TABLE_LEAVES)
        return c->table[bits >> 6] >> (bits & 63) & 1;
    return evaluate(c, in, node_in);
}

/* Leaf i's state set to v in both in and bits. */
static inline void set_in(uint8_t *in, unsigned *bits, int i, bool v)
{
    in[i] = v;
    if (i < CSG_TABLE_LEAVES)
        *bits = (*bits & ~(1u << i)) | (unsigned)v << i;
}

void csg_finish(csg *c)
{
    c->bounds = c->nnodes ? finish(c, CSG_NODE(c->nnodes - 1), false) : aabb_empty();
    if (aabb_is_empty(c->bounds)) /* an intersection of things apart: nothing */
        c->bounds = (aabb){v3s(0.0f), v3s(0.0f)};
    tabulate(c);
}

bool csg_contains(const csg *c, const bool *leaf_inside)
{
    uint8_t in[CSG_MAX_LEAVES], node_in[CSG_MAX_LEAVES];
    for (int i = 0; i < c->nleaves; i++)
        in[i] = leaf_inside[i];
    return evaluate(c, in, node_in);
}

typedef struct event {
    crossing x;
    int leaf;
} event;

static inline ray leaf_ray(const csg_leaf *l, const ray *r)
{
    if (!l->moved)
        return *r;
    return (ray){mat4_point(&l->x.inv, r->o), mat4_vector(&l->x.inv, r->d), r->tmin, r->tmax,
                 r->time};
}

/* Leaf i's crossings after t0 (at most CSG_LEAF_CROSSINGS), none when r
 * misses its bounds from t0 on. In a packet's first round (pre, for lane
 * k) the bounds test and, for the leaves csg8.h spans, the span are read
 * from pre, worked out there by the same operations; otherwise the leaf
 * is asked. */
static int leaf_crossings(const csg *c, int i, const ray *r, vec3 inv, float t0,
                          const csg_spans8 *pre, int k, crossing *x, bool *more)
{
    const csg_leaf *l = &c->leaves[i];
    *more = false;
    if (pre ? !(pre->leaf[i].bounded >> k & 1) : !aabb_hit(l->bounds, r->o, inv, t0, INFINITY))
        return 0;
    if (pre && pre->leaf[i].spanned >> k & 1) {
        const csg_leaf8 *s = &pre->leaf[i];
        shape_hit in = {.t = s->tin[k], .part = s->pin[k]};
        shape_hit out = {.t = s->tout[k], .part = s->pout[k]};
        return shape_span_crossings(s->met >> k & 1, in, out, t0, x, CSG_LEAF_CROSSINGS);
    }
    ray lr = leaf_ray(l, r);
    lr.tmin = t0;
    return shape_crossings(&l->shape, &lr, x, CSG_LEAF_CROSSINGS, more);
}

/* Every leaf's crossings after t0, sorted by t (then leaf), and each leaf's
 * state just after t0. *cut is where a leaf's list was cut short (INFINITY
 * when none was): events beyond it are not all known. */
static int gather(const csg *c, const ray *r, float t0, const csg_spans8 *pre, int k,
                  uint8_t *in, unsigned *bits, event *ev, float *cut)
{
    vec3 inv = v3(1.0f / r->d.x, 1.0f / r->d.y, 1.0f / r->d.z);
    int n = 0;
    *cut = INFINITY;
    *bits = 0;
    for (int i = 0; i < c->nleaves; i++) {
        crossing x[CSG_LEAF_CROSSINGS];
        bool more;
        in[i] = 0;
        int nx = leaf_crossings(c, i, r, inv, t0, pre, k, x, &more);
        if (nx == 0)
            continue;
        set_in(in, bits, i, !x[0].enter);
        if (more)
            *cut = fminf(*cut, x[nx - 1].h.t);
        for (int j = 0; j < nx; j++) {
            event e = {x[j], i};
            int m = n++;
            for (; m > 0 && ev[m - 1].x.h.t > e.x.h.t; m--)
                ev[m] = ev[m - 1];
            ev[m] = e;
        }
    }
    return n;
}

/* Of the crossings ev[0 .. n) (all at one t), one that makes the change
 * the tree made: into the result when became_inside, out of it otherwise. */
static const event *cause(const csg *c, const event *ev, int n, bool became_inside)
{
    for (int i = 0; i < n; i++)
        if ((ev[i].x.enter != c->leaves[ev[i].leaf].flip) == became_inside)
            return &ev[i];
    return &ev[0];
}

/* The classification: rounds of gathering the leaves' crossings from t0
 * on, each walked in order of t with the tree's answer after every
 * distinct t, until the answer changes (the hit), the range ends, or the
 * crossings known are all there are. Only the first round can come from
 * pre (csg_hit_lane); a round after a cut asks the leaves from the cut. */
static bool classify(const csg *c, const ray *r, const csg_spans8 *pre, int k, shape_hit *hit)
{
    uint8_t in[CSG_MAX_LEAVES], node_in[CSG_MAX_LEAVES];
    event ev[CSG_MAX_LEAVES * CSG_LEAF_CROSSINGS];
    float t0 = r->tmin;
    for (int round = 0; round < 64; round++, pre = NULL) {
        float cut;
        unsigned bits;
        int n = gather(c, r, t0, pre, k, in, &bits, ev, &cut);
        bool inside = answer(c, in, bits, node_in);
        for (int i = 0; i < n && ev[i].x.h.t <= cut;) {
            float t = ev[i].x.h.t;
            if (t >= r->tmax)
                return false;
            int j = i;
            for (; j < n && ev[j].x.h.t == t; j++)
                set_in(in, &bits, ev[j].leaf, ev[j].x.enter);
            bool now = answer(c, in, bits, node_in);
            if (now != inside) {
                const event *e = cause(c, ev + i, j - i, now);
                *hit = e->x.h;
                hit->leaf = e->leaf;
                return true;
            }
            i = j;
        }
        if (!(cut < r->tmax))
            return false;
        t0 = cut;
    }
    return false;
}

bool csg_intersect(const csg *c, const ray *r, shape_hit *hit)
{
    return classify(c, r, NULL, 0, hit);
}

bool csg_hit_lane(const csg *c, const ray *r, const csg_spans8 *pre, int k, shape_hit *hit)
{
    return classify(c, r, pre, k, hit);
}

/* The leaf's surface, carried into the csg's space and turned when the
 * leaf is flipped. */
void csg_surface(const csg *c, const ray *r, const shape_hit *hit, surface *out)
{
    const csg_leaf *l = &c->leaves[hit->leaf];
    ray lr = leaf_ray(l, r);
    shape_surface(&l->shape, &lr, hit, out);
    if (l->moved) {
        out->p = mat4_point(&l->x.fwd, out->p);
        out->n = v3_norm(xform_normal(&l->x, out->n));
        out->ng = v3_norm(xform_normal(&l->x, out->ng));
    }
    if (l->flip) {
        out->n = v3_neg(out->n);
        out->ng = v3_neg(out->ng);
    }
}
