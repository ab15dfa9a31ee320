/* csg: constructive solid geometry. A tree whose inner nodes are union,
 * intersection and difference (the first operand minus all the others)
 * and whose leaves are closed solids (shape_is_solid), each with its own
 * transform and material. Nested csg objects are flattened into one tree,
 * so a leaf is never itself a csg.
 *
 * The method is Roth's ray classification (S. D. Roth, "Ray Casting for
 * Modeling Solids", Computer Graphics and Image Processing 18(2), 1982):
 * each leaf classifies the ray's line against itself, giving the places
 * where the line crosses its boundary, each marked entering or leaving
 * (shape_crossings); the tree combines the classifications. Rather than
 * merging interval lists node by node, the crossings of all leaves are
 * walked in order of t with each leaf's in/out state, and the tree is
 * evaluated on those states after each distinct t; the first t at which
 * the tree's answer changes is the hit. This is the same classification,
 * evaluated lazily (a tree of at most CSG_TABLE_LEAVES leaves looks its
 * answer up in a table made once, by csg_finish). Because each crossing
 * says which way it goes (rather than toggling a parity), a ray that
 * starts inside operands, crossings counted twice where a ray meets an
 * edge of a mesh, and operands sharing a surface (a - a is empty, a & a
 * is a) all come out right, and a ray starting inside the result gets its
 * way out.
 *
 * A surface keeps its leaf's material. At a leaf inside an odd number of
 * subtracted operands the result's outside is the leaf's inside, so its
 * normal turns (the wall of a hole faces into the hole). */
#ifndef GLINT_GEOM_CSG_H
#define GLINT_GEOM_CSG_H

#include <stdint.h>
#include "core/aabb.h"
#include "core/mat4.h"
#include "geom/shape.h"

/* Bounds on one csg: its solids in all, and the crossings one solid may
 * report per query (more are fetched by querying again further on). */
#define CSG_MAX_LEAVES 256
#define CSG_LEAF_CROSSINGS 4
#define CSG_TABLE_LEAVES 8

typedef enum csg_op { CSG_UNION, CSG_INTERSECTION, CSG_DIFFERENCE, CSG_OP_COUNT } csg_op;

/* Their names in the scene format, NULL-terminated. */
extern const char *const csg_op_names[CSG_OP_COUNT + 1];

typedef struct csg_leaf {
    shape shape;  /* a solid, not a csg */
    bool moved;   /* x applies */
    xform x;      /* the leaf's space -> the csg's space */
    aabb bounds;  /* in the csg's space */
    int material; /* the scene's; -1: a mesh's own */
    bool flip;    /* normals turn (by csg_finish) */
} csg_leaf;

typedef struct csg_node {
    csg_op op;
    int first, count; /* operands: kids[first .. first + count) */
} csg_node;

/* An operand reference: a leaf (>= 0) or a node (CSG_NODE(k)). */
#define CSG_NODE(k) (-1 - (k))

typedef struct csg {
    csg_leaf *leaves;
    int nleaves, cap_leaves;
    csg_node *nodes; /* operands before the nodes using them: the root is last */
    int nnodes, cap_nodes;
    int32_t *kids;
    int nkids, cap_kids;
    aabb bounds; /* of the root, by csg_finish */
    /* By csg_finish, for a tree of at most CSG_TABLE_LEAVES leaves: its
     * answer for every set of leaves the point is inside (bit s: inside
     * leaf i where bit i of s is set), read instead of walking the nodes. */
    uint64_t table[4];
} csg;

/* Building: leaves and nodes in any order that adds a node's operands
 * before it; each returns the new operand's reference, or CSG_FULL when
 * the csg would pass CSG_MAX_LEAVES, or CSG_NOMEM. x may be NULL. */
#define CSG_FULL INT32_MIN
#define CSG_NOMEM (INT32_MIN + 1)
int32_t csg_add_leaf(csg *c, const shape *s, const xform *x, int material);
int32_t csg_add_node(csg *c, csg_op op, const int32_t *operands, int count);
/* Once the root (the last node) is added: flips and bounds. A union's
 * bound is its operands' union, an intersection's their overlap, a
 * difference's its first operand's. */
void csg_finish(csg *c);
void csg_free(csg *c);

bool csg_intersect(const csg *c, const ray *r, shape_hit *hit);

/* Eight rays against one leaf, from their tmin on, as csg_intersect's
 * first round of crossings finds each ray's (csg8.h works them out in
 * vector registers). bounded has bit k when ray k passes the leaf's
 * bounds (aabb_hit); spanned, those of them whose span of the leaf is
 * here: met when the line meets the leaf, with the entry's t and part in
 * tin, pin, the exit's in tout, pout. A ray bounded but not spanned asks
 * the leaf itself (shape_crossings). */
typedef struct csg_leaf8 {
    float tin[8], tout[8];
    int32_t pin[8], pout[8];
    uint8_t bounded, spanned, met;
} csg_leaf8;

typedef struct csg_spans8 {
    csg_leaf8 leaf[CSG_MAX_LEAVES];
} csg_spans8;

/* csg_intersect for r, which is ray k of a packet whose first round of
 * crossings pre holds: the same hit, from the one classification. */
bool csg_hit_lane(const csg *c, const ray *r, const csg_spans8 *pre, int k, shape_hit *hit);

/* csg_intersect against the rays of active, each within its own range:
 * returns the rays hit, with hit[k] as csg_intersect sets it (the rest of
 * it zero); csg8_occluded returns the rays that meet the csg, which is
 * shape_occluded's answer. On the eight-wide paths (geom/csg8.h). */
int csg8_hit_avx2(const csg *c, const ray8 *r, int active, shape_hit *hit);
int csg8_hit_avx512(const csg *c, const ray8 *r, int active, shape_hit *hit);
int csg8_occluded_avx2(const csg *c, const ray8 *r, int active);
int csg8_occluded_avx512(const csg *c, const ray8 *r, int active);
/* The hit leaf's surface, with (u, v) where uv is set (shape_surface), else
 * without (shape_surface_no_uv). */
void csg_surface(const csg *c, const ray *r, const shape_hit *hit, bool uv, surface *out);
/* Membership of a point, for tests: the tree on the leaves' answers. */
bool csg_contains(const csg *c, const bool *leaf_inside);

#endif
