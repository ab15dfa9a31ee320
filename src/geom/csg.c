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

static inline ray leaf_ray(const csg_leaf *l, const ray *r)
{
    if (!l->moved)
        return *r;
    return mat4_ray(&l->x.inv, r);
}

/* One crossing of a round: its t, and which leaf's which crossing it is.
 * Eight bytes, so that sorting the round moves a word per step rather
 * than a whole crossing, whose record stays where its leaf put it (or,
 * for a span read from pre, in pre). */
typedef struct event {
    float t;
    uint16_t leaf;
    uint8_t j; /* the leaf's x[j] */
    bool enter;
} event;

/* What one classification works in: the crossings of the leaves asked in
 * a round, leaf i's from x[i * CSG_LEAF_CROSSINGS] on; the round's events
 * in order of t, from ev[1] on, between two sentinels that end the loops
 * over them without counting (ev[0] at -INFINITY, below every t, and one
 * at NAN after the last, equal to none and in no range); and, for a tree
 * without a table, the leaves' states in in (a tree with one keeps them
 * in a word, bit i for leaf i). */
typedef struct walk {
    crossing x[CSG_MAX_LEAVES * CSG_LEAF_CROSSINGS];
    event ev[CSG_MAX_LEAVES * CSG_LEAF_CROSSINGS + 2];
    uint8_t in[CSG_MAX_LEAVES], node_in[CSG_MAX_LEAVES];
} walk;

/* Leaf i's state set to v; tabled: the tree has a table (a constant in
 * each copy of the classification, so the test costs nothing). */
static inline void set_in(bool tabled, walk *w, unsigned *bits, int i, bool v)
{
    if (tabled)
        *bits = (*bits & ~(1u << i)) | (unsigned)v << i;
    else
        w->in[i] = v;
}

/* The tree's answer for the leaves' states. */
static inline bool answer(bool tabled, const csg *c, walk *w, unsigned bits)
{
    if (tabled)
        return c->table[bits >> 6] >> (bits & 63) & 1;
    return evaluate(c, w->in, w->node_in);
}

/* e into ev[0 .. n), after those of t no greater (so crossings at one t
 * keep the order of their leaves, and a leaf's own their order); ev[-1]
 * is the sentinel below every t. */
static inline void insert(event *ev, int n, event e)
{
    for (; ev[n - 1].t > e.t; n--)
        ev[n] = ev[n - 1];
    ev[n] = e;
}

/* Lane k's span of leaf i, from pre, as events into ev[0 .. n): the
 * entry and the exit after t0, as shape_span_crossings keeps them.
 * Returns the new count, and sets *inside when the lane starts inside
 * the leaf (its first crossing leaves it). */
static inline int span_events(const csg_leaf8 *s, int k, int i, float t0, event *ev, int n,
                              bool *inside)
{
    if (!(s->met >> k & 1))
        return n;
    float tin = s->tin[k], tout = s->tout[k];
    if (tin > t0)
        insert(ev, n++, (event){tin, (uint16_t)i, 0, true});
    else
        *inside = tout > t0;
    if (tout > t0)
        insert(ev, n++, (event){tout, (uint16_t)i, 1, false});
    return n;
}

/* Leaf i asked for its crossings after t0 (at most CSG_LEAF_CROSSINGS),
 * as events into w->ev[0 .. n). Returns the new count, with *inside as
 * span_events, and *cut lowered to the last crossing when the leaf has
 * more. */
__attribute__((always_inline)) static inline int asked_events(const csg *c, int i, const ray *r,
                                                              float t0, walk *w, int n,
                                                              bool *inside, float *cut)
{
    const csg_leaf *l = &c->leaves[i];
    crossing *x = w->x + i * CSG_LEAF_CROSSINGS;
    ray lr = leaf_ray(l, r);
    lr.tmin = t0;
    bool more;
    int nx = shape_crossings(&l->shape, &lr, x, CSG_LEAF_CROSSINGS, &more);
    if (nx == 0)
        return n;
    *inside = !x[0].enter;
    if (more)
        *cut = fminf(*cut, x[nx - 1].h.t);
    for (int j = 0; j < nx; j++, n++)
        insert(w->ev + 1, n, (event){x[j].h.t, (uint16_t)i, (uint8_t)j, x[j].enter});
    return n;
}

/* asked_events out of line, for the packet's rounds, where other leaves
 * than those csg8.h spans are few and the loop stays in registers. */
__attribute__((noinline)) static int asked_lane(const csg *c, int i, const ray *r, walk *w, int n,
                                                bool *inside, float *cut)
{
    return asked_events(c, i, r, r->tmin, w, n, inside, cut);
}

/* A round's gathering: every leaf's crossings after t0 as events sorted
 * by t (then leaf), each leaf's state just after t0 (into *bits or
 * w->in), and in *cut where a leaf's list was cut short (INFINITY when
 * none was): events beyond it are not all known. Each leaf whose bounds
 * r meets from t0 on is asked. */
__attribute__((always_inline)) static inline int gather(bool tabled, const csg *c, const ray *r,
                                                        float t0, walk *w, unsigned *bits,
                                                        float *cut)
{
    vec3 inv = v3(1.0f / r->d.x, 1.0f / r->d.y, 1.0f / r->d.z);
    int n = 0;
    *cut = INFINITY;
    *bits = 0;
    for (int i = 0; i < c->nleaves; i++) {
        bool inside = false;
        if (aabb_hit(c->leaves[i].bounds, r->o, inv, t0, INFINITY))
            n = asked_events(c, i, r, t0, w, n, &inside, cut);
        set_in(tabled, w, bits, i, inside);
    }
    return n;
}

/* gather for a packet's first round (lane k of pre, from r->tmin): the
 * bounds tests and, for the leaves csg8.h spans, the spans are read from
 * pre, worked out there by the same operations; only the other leaves
 * within their bounds are asked. */
__attribute__((always_inline)) static inline int gather_lane(bool tabled, const csg *c,
                                                             const ray *r,
                                                             const csg_spans8 *pre, int k,
                                                             walk *w, unsigned *bits,
                                                             float *cut)
{
    int n = 0;
    *cut = INFINITY;
    *bits = 0;
    for (int i = 0; i < c->nleaves; i++) {
        const csg_leaf8 *s = &pre->leaf[i];
        bool inside = false;
        if (s->spanned >> k & 1) /* spanned lanes are bounded (csg.h) */
            n = span_events(s, k, i, r->tmin, w->ev + 1, n, &inside);
        else if (s->bounded >> k & 1)
            n = asked_lane(c, i, r, w, n, &inside, cut);
        set_in(tabled, w, bits, i, inside);
    }
    return n;
}

/* Of the crossings ev[0 .. n) (all at one t), one that makes the change
 * the tree made: into the result when became_inside, out of it otherwise. */
static const event *cause(const csg *c, const event *ev, int n, bool became_inside)
{
    if (n > 1) /* a crossing alone at its t is the cause */
        for (int i = 0; i < n; i++)
            if ((ev[i].enter != c->leaves[ev[i].leaf].flip) == became_inside)
                return &ev[i];
    return &ev[0];
}

/* Event e's crossing as the hit: from pre when it is a span read there
 * (an entry's or an exit's t and part), else the record its leaf made. */
static shape_hit event_hit(const walk *w, const csg_spans8 *pre, int k, event e)
{
    shape_hit h;
    if (pre && pre->leaf[e.leaf].spanned >> k & 1) {
        const csg_leaf8 *s = &pre->leaf[e.leaf];
        h = (shape_hit){.t = e.t, .part = e.enter ? s->pin[k] : s->pout[k]};
    } else {
        h = w->x[e.leaf * CSG_LEAF_CROSSINGS + e.j].h;
    }
    h.leaf = e.leaf;
    return h;
}

/* The classification: rounds of gathering the leaves' crossings from t0
 * on, each walked in order of t with the tree's answer after every
 * distinct t, until the answer changes (the hit), the range ends, or the
 * crossings known are all there are. Only the first round can come from
 * pre (csg_hit_lane); a round after a cut asks the leaves from the cut.
 * Made twice, for trees with a table (tabled) and without. */
__attribute__((always_inline)) static inline bool rounds(bool tabled, const csg *c, const ray *r,
                                                         const csg_spans8 *pre, int k,
                                                         shape_hit *hit)
{
    walk w;
    event *ev = w.ev + 1;
    w.ev[0].t = -INFINITY;
    float t0 = r->tmin;
    for (int round = 0; round < 64; round++, pre = NULL) {
        float cut;
        unsigned bits;
        int n = pre ? gather_lane(tabled, c, r, pre, k, &w, &bits, &cut)
                    : gather(tabled, c, r, t0, &w, &bits, &cut);
        if (n == 0 || ev[0].t >= r->tmax) /* nothing in the range changes */
            return false;
        ev[n].t = NAN;
        bool inside = answer(tabled, c, &w, bits);
        for (int i = 0; ev[i].t <= cut;) {
            float t = ev[i].t;
            if (t >= r->tmax)
                return false;
            int j = i;
            for (; ev[j].t == t; j++)
                set_in(tabled, &w, &bits, ev[j].leaf, ev[j].enter);
            bool now = answer(tabled, c, &w, bits);
            if (now != inside) {
                *hit = event_hit(&w, pre, k, *cause(c, ev + i, j - i, now));
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

static bool classify(const csg *c, const ray *r, const csg_spans8 *pre, int k, shape_hit *hit)
{
    if (c->nleaves <= CSG_TABLE_LEAVES)
        return rounds(true, c, r, pre, k, hit);
    return rounds(false, c, r, pre, k, hit);
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
void csg_surface(const csg *c, const ray *r, const shape_hit *hit, bool uv, surface *out)
{
    const csg_leaf *l = &c->leaves[hit->leaf];
    ray lr = leaf_ray(l, r);
    (uv ? shape_surface : shape_surface_no_uv)(&l->shape, &lr, hit, out);
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
