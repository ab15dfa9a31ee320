/* wide: a BVH with four or eight children per node, made by collapsing a
 * binary one (accel/bvh.h), so that one SIMD box test decides all of a
 * node's children at once (Dammertz et al., "Shallow Bounding Volume
 * Hierarchies for Fast SIMD Ray Tracing of Incoherent Rays", EGSR 2008;
 * Wald et al., "Getting Rid of Packets", IEEE RT 2008). Four wide for SSE
 * and the scalar path, eight wide for AVX2 and AVX-512 (accel/isa.h picks;
 * accel/traverse.h walks either).
 *
 * Each node keeps its children's boxes per axis, one lane per child
 * (structure of arrays). A child is an interior node (child >= 0), a leaf
 * (child < 0: primitives prims[-1 - child .. + count)) or empty (count 0
 * with an inverted box that no ray can hit). Collapsing opens the child
 * with the largest area until the node is full, so both widths are made of
 * the binary tree's own boxes. */
#ifndef GLINT_ACCEL_WIDE_H
#define GLINT_ACCEL_WIDE_H

#include <stddef.h>
#include <stdint.h>
#include "glint.h"
#include "accel/bvh.h"
#include "accel/isa.h"

typedef struct bvh4_node {
    float box[6][4]; /* lo x, hi x, lo y, hi y, lo z, hi z; one lane per child */
    int32_t child[4];
    uint32_t count[4];
} __attribute__((aligned(64))) bvh4_node;

typedef struct bvh8_node {
    float box[6][8];
    int32_t child[8];
    uint32_t count[8];
} __attribute__((aligned(64))) bvh8_node;

typedef struct bvhw {
    int width; /* 4 or 8 */
    accel_isa isa; /* the kernels it was laid out for */
    union {
        bvh4_node *n4;
        bvh8_node *n8;
    };
    int nnodes;
    int32_t *prims; /* taken over from the binary BVH */
    int nprims;
    aabb bounds;
    /* Where an owner that renumbers leaves keeps leaf i's data: at
     * leaf_data + i * leaf_stride, fetched early by traversal (NULL: no
     * such store). */
    const void *leaf_data;
    size_t leaf_stride;
    /* Traversal fetches children ahead (traverse.h) when the nodes are
     * more than WIDE_FETCH_BYTES: a smaller tree stays in the cache. */
    bool fetch_ahead;
    /* The whole tree is one leaf (lane 0 of node 0): an owner may test its
     * primitives without a traversal (scene.c does). */
    bool leaf_root;
    /* Room in the node and primitive arrays, which bvhw_rebuild reuses (0:
     * none known). */
    int cap_nodes, cap_prims;
    /* The direct build's working array (split.h's primrefs, 32 bytes an
     * object), kept for the next bvhw_rebuild: fresh memory that size
     * would be cleared by the kernel first, a tenth of a rebuild's time. */
    struct primref *refs;
    int cap_refs;
} bvhw;

#define WIDE_FETCH_BYTES (256u * 1024u)

/* Collapses b into out for the kernels of isa, taking over b's primitive
 * array. b is freed in every case, failure included. Optimal chooses the
 * wide nodes that the surface area heuristic expects rays to visit least
 * (fuller nodes, fewer of them; worth its time and memory, about 45 bytes
 * a binary node, where many rays follow one build: a mesh); otherwise
 * each node opens its largest children first. */
glint_rc bvhw_from_bvh(bvhw *out, bvh *b, accel_isa isa, bool optimal, glint_error *err);
/* The tree that bvh_build_leaves (max_leaf) followed by bvhw_from_bvh
 * makes over boxes[ids[i]] for i < n (ids NULL: boxes[i]), built directly
 * (accel/bvh.c), with ranges of at most `bundle` primitives (0: none)
 * taken whole: each primitive a lane of its own, in a node of its own or
 * in its parent's if they fit. prims are the ids. cpus as for
 * bvh_build_threads. */
glint_rc bvhw_build(bvhw *out, const aabb *boxes, const int32_t *ids, int n, int max_leaf,
                    int bundle, accel_isa isa, int cpus, glint_error *err);
/* The same into b, which holds a tree (or is zeroed): its arrays are
 * reused where they are large enough (memory the kernel would otherwise
 * clear first), the rest freed. */
glint_rc bvhw_rebuild(bvhw *b, const aabb *boxes, const int32_t *ids, int n, int max_leaf,
                      int bundle, accel_isa isa, int cpus, glint_error *err);
/* A node's children before they are stored: lane k's box, child (a node,
 * or -1 - first for a leaf) and count; an empty lane has an empty box,
 * child -1 and count 0. */
typedef struct bvhw_lanes {
    aabb box[8];
    int32_t child[8];
    uint32_t count[8];
} bvhw_lanes;

/* Every lane of l empty. */
void bvhw_lanes_empty(bvhw_lanes *l);
/* Stores l as node `at` of a node array of the given width (bvh4_node or
 * bvh8_node), boxes per axis and lane. */
void bvhw_store(void *nodes, int width, int at, const bvhw_lanes *l);
void bvhw_free(bvhw *b);
/* Bytes of the nodes. */
size_t bvhw_node_bytes(const bvhw *b);

/* Child k of node i, for owners that renumber leaves. */
static inline int32_t *bvhw_child(bvhw *b, int i, int k)
{
    return b->width == 8 ? &b->n8[i].child[k] : &b->n4[i].child[k];
}

static inline uint32_t bvhw_count(const bvhw *b, int i, int k)
{
    return b->width == 8 ? b->n8[i].count[k] : b->n4[i].count[k];
}

#endif
