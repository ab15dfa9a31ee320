/* mesh_import: triangle meshes from files (OBJ, PLY, STL, OFF, glTF, Collada,
 * FBX, 3DS and everything else assimp reads), flattened into one glint mesh
 * with the file's materials, textures and vertex colours.
 *
 * A model file is untrusted input. Before anything else the file must be a
 * regular file (a FIFO or device is refused without blocking), and what its
 * header declares is checked against its size (mesh_limits.h). The import
 * itself runs in a child process under memory and CPU limits
 * (mesh_isolate.h), unless GLINT_MESH_TRUSTED=1. The parent checks what comes
 * back, drops unusable triangles (counted in the warning) and reads the
 * textures the file names through the image readers of src/io. */
#ifndef GLINT_LOAD_MESH_IMPORT_H
#define GLINT_LOAD_MESH_IMPORT_H

#include "glint.h"
#include "core/error.h"
#include "geom/mesh.h"
#include "load/mesh_data.h"
#include "shade/material.h"

/* Crease angle for normals computed where a file has none, in degrees. */
#define MESH_DEFAULT_SMOOTH_ANGLE 30.0f

typedef struct mesh_options {
    float smooth_angle; /* 0 to 180 degrees; edges sharper than this stay hard */
    int threads;        /* for the mesh's BVH (mesh_init) */
} mesh_options;

typedef struct mesh_file {
    mesh *mesh;          /* initialised (mesh_init), heap-allocated */
    material *materials; /* the file's own materials; mesh->tri_material indexes these */
    int nmaterials;
    int dropped;         /* triangles left out */
    mesh_tex *textures;  /* what the materials name; materials[i].texture indexes these */
    int ntextures;
    char *dir;           /* folder of the model file, for textures it names; NULL: none */
    char *name;
    char warnings[1024]; /* lines for the user, each ending in '\n'; "" when none */
} mesh_file;

/* Reads path. The node hierarchy's transforms are applied (skinned meshes
 * in their rest pose), polygons are triangulated, vertex normals are kept
 * when the file has them and computed with the crease angle when not, and
 * texture coordinates and vertex colours are kept. opts NULL: defaults. */
glint_rc mesh_import(const char *path, const mesh_options *opts, mesh_file *out,
                     glint_error *err);
/* The same for a file already in memory; name (shown in messages) gives
 * the format by its extension. Files the mesh refers to (an OBJ's .mtl,
 * a glTF's external buffers, external textures) are not found this way. */
glint_rc mesh_import_memory(const void *data, size_t size, const char *name,
                            const mesh_options *opts, mesh_file *out, glint_error *err);
/* Reads the file's textures (a texture that cannot be read is left out,
 * with a warning), then adds its materials and mesh to s, renumbering the
 * triangles' materials to the scene's; the scene takes the mesh (f->mesh
 * becomes NULL). *index gets the mesh's place among the scene's meshes. */
glint_rc mesh_file_add(struct glint_scene *s, mesh_file *f, int *index, glint_error *err);
/* Adds one line to f->warnings (dropped when the buffer is full). */
void mesh_file_warn(mesh_file *f, const char *fmt, ...) GLINT_PRINTF(2, 3);
/* Frees what mesh_import returned and the caller did not take. */
void mesh_file_free(mesh_file *f);

/* Builds out from md (which it empties): the parent's checks, the
 * dropped-triangle count and the BVH (on `threads`, as mesh_init). Shared
 * with the fuzz target. */
glint_rc mesh_file_from_data(mesh_data *md, const char *name, int threads, mesh_file *out,
                             glint_error *err);

#endif
