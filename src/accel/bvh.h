/* bvh: a bounding volume hierarchy over primitives known only by their
 * boxes. Nodes live in one flat array in depth-first order: an interior
 * node's first child follows it directly and `index` names the second; a
 * leaf's primitives are prims[index .. index + count). (pbrt-v3, section
 * 4.3.4, "Compact BVH for Traversal".)
 *
 * The build is the binned surface-area-heuristic build of Wald, "On fast
 * Construction of SAH-based Bounding Volume Hierarchies" (IEEE RT 2007),
 * with 32 bins on each of the three axes, binned in one pass. Near the root
 * the two halves of a split are built at the same time on threads of their
 * own (as many as the CPUs the process may run on), each into its own node
 * array, then joined in depth-first order: the tree is the same whatever
 * the number of threads.
 * Rays never traverse this binary tree: bvhw_from_bvh (wide.h) collapses
 * it into the four- or eight-wide hierarchy they do traverse, with stacks
 * sized by the depth bound below. */
#ifndef GLINT_ACCEL_BVH_H
#define GLINT_ACCEL_BVH_H

#include <stdint.h>
#include "glint.h"
#include "core/aabb.h"

/* No path from the root is longer than this, so traversal stacks of this
 * size never overflow. */
#define BVH_MAX_DEPTH 64

typedef struct bvh_node {
    aabb box;
    int32_t index;  /* leaf: first primitive; interior: second child */
    uint16_t count; /* primitives in a leaf; 0 for an interior node */
    uint8_t axis;   /* interior: the split axis, for front-to-back order */
    uint8_t pad;
} bvh_node;

typedef struct bvh {
    bvh_node *nodes;
    int nnodes;
    int32_t *prims; /* primitive indices, in leaf order */
    int nprims;
} bvh;

/* Builds over n primitives with the given boxes (none may be empty). An
 * n of 0 gives an empty hierarchy (nnodes 0). */
glint_rc bvh_build(bvh *out, const aabb *boxes, int n, glint_error *err);
/* The same with at most max_leaf primitives to a leaf (bvh_build allows
 * four): 1 suits primitives that cost several node visits to test. */
glint_rc bvh_build_leaves(bvh *out, const aabb *boxes, int n, int max_leaf, glint_error *err);
/* The same for primitives that are tested `block` at a time (a mesh's
 * triangles, four to a tri4): the cost model counts a leaf's blocks, not
 * its primitives, so leaves fill up to a whole block. */
glint_rc bvh_build_blocked(bvh *out, const aabb *boxes, int n, int block, glint_error *err);
/* The same on as many threads as cpus CPUs warrant (0: the CPUs in the
 * process's affinity mask; 1: the calling thread alone). */
glint_rc bvh_build_threads(bvh *out, const aabb *boxes, int n, int block, int cpus,
                           glint_error *err);
void bvh_free(bvh *b);

#endif
