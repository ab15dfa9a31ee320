/* mesh_join: vertices equal in every attribute made one.
 *
 * Most formats' importers hand back a vertex for every face corner (OBJ's
 * and STL's always); the corners that share a position, normal, texture
 * coordinate and colour, bit for bit, become one vertex again, numbered in
 * the order of their first appearance. Vertices no triangle uses are
 * dropped (glTF primitives sharing one vertex buffer each bring all of
 * it). */
#ifndef GLINT_LOAD_MESH_JOIN_H
#define GLINT_LOAD_MESH_JOIN_H

#include <stdbool.h>
#include <stdint.h>
#include "load/mesh_data.h"

/* Joins vertices [v0, v0 + *nv) of md, which triangles [t0, t1) index
 * (and no others); the vertices are compacted in place, the triangles
 * renumbered and *nv set to the new count. Every attribute array md has
 * counts. Returns false when out of memory (md unchanged). *nv must be at
 * most UINT32_MAX / 2. */
bool mesh_join_vertices(mesh_data *md, uint32_t v0, uint32_t *nv, uint32_t t0, uint32_t t1);

#endif
