/* mesh_assimp: one model file through assimp into a mesh_data.
 *
 * Runs wherever mesh_import puts it: in a child process for untrusted files
 * (mesh_isolate.h), in the calling process for trusted ones and in the fuzz
 * target. Every file assimp opens (the model and whatever it names: an
 * OBJ's .mtl, a glTF's buffers) goes through an opener that refuses
 * anything but a regular file without blocking, so a FIFO named by a model
 * cannot hang the import.
 *
 * What is kept: triangles (points and lines are dropped), placed by the node
 * hierarchy; skinned meshes posed by their bones in the file's rest pose;
 * per-vertex normals (the file's, else computed with the crease angle),
 * the first UV set and colour set; per material the diffuse and specular
 * colours, shininess, opacity under the format's convention and the diffuse
 * texture (a path as written, or the bytes of one held in the file). */
#ifndef GLINT_LOAD_MESH_ASSIMP_H
#define GLINT_LOAD_MESH_ASSIMP_H

#include <stddef.h>
#include "glint.h"
#include "load/mesh_data.h"

typedef struct mesh_assimp_opts {
    float smooth_angle;    /* degrees: crease angle for computed normals */
    uint64_t max_triangles; /* more is an error before the arrays are made */
} mesh_assimp_opts;

/* The file at path (data NULL), or the size bytes at data with the format
 * told by name's extension. Errors are GLINT_ERR_INPUT naming name, or
 * GLINT_ERR_NOMEM. Not thread-safe: callers serialise (mesh_import.c). */
glint_rc mesh_assimp_read(const char *name, const void *data, size_t size,
                          const mesh_assimp_opts *opts, mesh_data *out, glint_error *err);

#endif
