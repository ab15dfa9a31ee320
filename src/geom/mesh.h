/* mesh: a triangle mesh stored once and placed by any number of objects
 * (instances, each with its own transform and material): vertex arrays,
 * triangles as index triples, and the mesh's own BVH. A scene's BVH over
 * objects sits on top of these, making a two-level hierarchy. */
#ifndef GLINT_GEOM_MESH_H
#define GLINT_GEOM_MESH_H

#include <stdint.h>
#include "glint.h"
#include "accel/wide.h"
#include "core/ray.h"

struct surface;
struct shape_hit;
struct crossing;

typedef struct mesh {
    vec3 *pos;
    vec3 *nrm;        /* per vertex, unit; NULL: flat shading */
    float (*uv)[2];   /* per vertex; NULL: (u, v) are the barycentrics */
    vec3 *col;        /* per vertex colour, multiplying the material's; or NULL */
    uint32_t (*tri)[3];
    int32_t *tri_material; /* per triangle scene material, or NULL */
    int nverts, ntris;
    bvhw bvh;         /* triangles are stored in leaf order; a leaf names its
                         first tri4 block (bvh.prims is not kept) */
    struct tri4 *blocks; /* each leaf's triangles, four to a block */
    int nblocks;
    aabb bounds;
} mesh;

/* Takes the arrays (allocated with malloc) and builds the BVH on up to
 * `threads` threads (0: one per CPU, cpus.h). Triangles with zero area or
 * non-finite corners are dropped first; *dropped (when non-null) tells how
 * many. Fails when none remain. name is for messages. */
glint_rc mesh_init(mesh *m, const char *name, int threads, int *dropped, glint_error *err);
void mesh_free(mesh *m);

bool mesh_intersect(const mesh *m, const ray *r, struct shape_hit *hit);
bool mesh_occluded(const mesh *m, const ray *r);
/* The nearest hits of the rays of active (bit k: ray k of r) at once:
 * returns the rays that hit, with hit[k] for each. Each gets the hit that
 * mesh_intersect gives it, to the bit; rays that cannot share a walk
 * (mesh_packet.h) are traced one at a time. */
int mesh_intersect8(const mesh *m, const ray8 *r, int active, struct shape_hit *hit);
/* Every triangle crossing after r->tmin, nearest first, entering where
 * the triangle faces the ray (see shape_crossings). */
int mesh_crossings(const mesh *m, const ray *r, struct crossing *out, int max, bool *more);
/* hit->part is the triangle; b1, b2 its barycentrics. */
void mesh_surface(const mesh *m, vec3 p, const struct shape_hit *hit, struct surface *out);

/* How many edges (vertices at one position counted as one) do not join
 * exactly two triangles running along them in opposite directions: 0 for a
 * closed, consistently wound surface, which bounds a solid. -1 when memory
 * runs out. */
int mesh_open_edges(const mesh *m);

/* Bytes held by the mesh and its BVH. */
size_t mesh_bytes(const mesh *m);

#endif
