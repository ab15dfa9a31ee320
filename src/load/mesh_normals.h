/* mesh_normals: vertex normals for meshes whose file gives none, with a
 * crease angle, as modelling tools compute them.
 *
 * Corners at the same position are welded (whatever their texture
 * coordinates). A corner's normal is the sum of the unit normals of the
 * triangles around its position whose normal lies within the crease angle
 * of its own triangle's, each weighted by its angle at that corner, so edges sharper than the angle stay hard
 * (a cube's twelve edges at 90 degrees) and gentler ones are smoothed. A
 * vertex whose corners get different normals is split. Positions shared by
 * more than MESH_NORMALS_MAX_FAN triangles take each triangle's own normal
 * (the cost would grow with the square of the fan). */
#ifndef GLINT_LOAD_MESH_NORMALS_H
#define GLINT_LOAD_MESH_NORMALS_H

#include <stdbool.h>
#include <stdint.h>
#include "load/mesh_data.h"

#define MESH_NORMALS_MAX_FAN 256u

/* Computes normals for vertices [v0, v0 + *nv) and triangles [t0, t1) of
 * md, which index only those vertices. The range may grow to
 * v0 + 3 * (t1 - t0) vertices (the caller has made room; *nv gets the new
 * count); triangles are renumbered. md->nrm must exist. angle in degrees.
 * Returns false when out of memory (md is unchanged but for normals). */
bool mesh_normals_crease(mesh_data *md, uint32_t v0, uint32_t *nv, uint32_t t0, uint32_t t1,
                         float angle);

#endif
