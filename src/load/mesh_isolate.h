/* mesh_isolate: running the importer in a child process.
 *
 * Model files are untrusted, and the importer (assimp) is a large C++
 * library that aborts, loops or allocates without bound on some bad files.
 * So the import runs in a forked child under setrlimit: address space
 * (GLINT_MESH_MEMORY), CPU time (GLINT_MESH_SECONDS) and no core files; its
 * output goes to /dev/null. It hands back the mesh in mesh_data's wire form
 * through a pipe; the parent reads it against a wall-clock deadline (twice
 * the CPU limit), kills a child that overstays, and checks the buffer whole
 * before using it (mesh_data_decode). Whatever happens in the child becomes
 * one line naming the file:
 *
 *   model.ply: the importer failed (truncated or corrupt file?)
 *   model.ply: the importer used more than 60 s of CPU time (GLINT_MESH_SECONDS raises the limit)
 *   model.ply: the importer did not finish within 120 s (GLINT_MESH_SECONDS raises the limit)
 *   model.ply: the importer ran out of its 4096 MiB of memory (GLINT_MESH_MEMORY raises the limit)
 *
 * The import itself is mesh_assimp_read; with GLINT_MESH_TRUSTED=1 the
 * caller runs that directly instead. Builds with AddressSanitizer, whose
 * shadow memory fills the address space, leave out the memory limit. */
#ifndef GLINT_LOAD_MESH_ISOLATE_H
#define GLINT_LOAD_MESH_ISOLATE_H

#include <pthread.h>
#include <stddef.h>
#include "glint.h"
#include "load/mesh_assimp.h"
#include "load/mesh_data.h"
#include "load/mesh_limits.h"

/* As mesh_assimp_read (name, data, size, opts), in a child under lim.
 * lock, held by the caller, is released once the child is started.
 * Errors are GLINT_ERR_INPUT naming name, GLINT_ERR_NOMEM, or GLINT_ERR_IO
 * when no child could be started. */
glint_rc mesh_isolate_read(const char *name, const void *data, size_t size,
                           const mesh_assimp_opts *opts, const mesh_limits *lim,
                           pthread_mutex_t *lock, mesh_data *out, glint_error *err);

#endif
