/* mesh_import: triangle meshes from files (OBJ, PLY, STL, OFF, glTF and
 * everything else assimp reads), flattened into one glint mesh. */
#ifndef GLINT_LOAD_MESH_IMPORT_H
#define GLINT_LOAD_MESH_IMPORT_H

#include "glint.h"
#include "geom/mesh.h"
#include "shade/material.h"

typedef struct mesh_file {
    mesh *mesh;          /* initialised (mesh_init), heap-allocated */
    material *materials; /* the file's own materials; mesh->tri_material indexes these */
    int nmaterials;
    int dropped;         /* degenerate triangles skipped */
} mesh_file;

/* Reads path. The node hierarchy's transforms are applied, polygons are
 * triangulated, vertex normals are kept when the file has them and computed
 * (smooth) when not, and texture coordinates are kept. */
glint_rc mesh_import(const char *path, mesh_file *out, glint_error *err);
/* The same for a file already in memory; name (shown in messages) gives
 * the format by its extension. Files the mesh refers to (an OBJ's .mtl,
 * a glTF's external buffers) are not found this way. */
glint_rc mesh_import_memory(const void *data, size_t size, const char *name, mesh_file *out,
                            glint_error *err);
/* Frees what mesh_import returned and the caller did not take. */
void mesh_file_free(mesh_file *f);

#endif
