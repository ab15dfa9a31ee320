/* mesh_limits: the bounds on importing a mesh file, and the checks made on
 * a file's own header before anything is allocated for what it declares.
 *
 * The limits come from the environment, so that they reach both the command
 * line and programs using the library:
 *
 *   GLINT_MESH_MEMORY     MiB of address space the importer may use (4096)
 *   GLINT_MESH_SECONDS    CPU seconds the importer may use (60); it is also
 *                         stopped after twice that in wall-clock time
 *   GLINT_MESH_TRIANGLES  triangles in one file (33554432, 2^25)
 *   GLINT_MESH_TRUSTED    1: import in the calling process, without the
 *                         child process and its limits (trusted files only)
 *
 * A value that is not a positive whole number is ignored (the default holds). */
#ifndef GLINT_LOAD_MESH_LIMITS_H
#define GLINT_LOAD_MESH_LIMITS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "glint.h"

#define MESH_DEFAULT_MEMORY_MIB 4096u
#define MESH_DEFAULT_SECONDS 60u
#define MESH_DEFAULT_TRIANGLES (1u << 25)

/* Bytes of a file's start given to mesh_precheck. */
#define MESH_HEAD_BYTES 65536u

typedef struct mesh_limits {
    uint64_t memory_mib;
    unsigned seconds;
    uint64_t triangles;
    bool trusted;
} mesh_limits;

void mesh_limits_get(mesh_limits *out);

/* Checks what the start of a file (head, n bytes; the whole file when
 * size <= n) declares against the file's size and the limits: PLY element
 * counts, OFF vertex and face counts, the facet count of a binary STL, and
 * a PLY header that never ends. A file that fails is GLINT_ERR_INPUT naming
 * name; anything the checks do not understand passes (the importer judges).
 * *hdr gets what the header declares, for the caller to warn when fewer
 * faces arrive (a truncated file that still parses). */
typedef struct mesh_header {
    uint64_t faces; /* faces declared; 0: none */
    uint64_t lines; /* an ASCII PLY: lines its elements take (one each), else 0 */
    uint64_t body;  /* where those lines start */
} mesh_header;

glint_rc mesh_precheck(const char *name, const char *head, size_t n, uint64_t size,
                       const mesh_limits *lim, mesh_header *hdr, glint_error *err);

/* Lines holding something other than white space in the n bytes at p, for
 * counting an ASCII PLY's elements; *open says whether the last one is
 * still open (carry it from one block of a file to the next, starting
 * false). */
uint64_t mesh_count_lines(const char *p, size_t n, bool *open);

#endif
