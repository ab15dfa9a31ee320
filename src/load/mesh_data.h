/* mesh_data: what an import hands back, as plain arrays, and its wire form.
 *
 * The importer (mesh_assimp.c) fills a mesh_data; when it runs in a child
 * process (mesh_isolate.c) the child encodes it into one buffer and writes
 * it down a pipe, and the parent decodes it. The child has parsed untrusted
 * bytes, so the parent trusts nothing in the buffer: mesh_data_decode checks
 * every count against the bytes present and every index against what it
 * indexes before a single array is allocated.
 *
 * Wire form (host byte order: both ends are the same program): the header
 * (magic, counts, flags), then pos, nrm, uv, col, tri, tri_mat when present,
 * then each material, then each texture's fixed part followed by its bytes. */
#ifndef GLINT_LOAD_MESH_DATA_H
#define GLINT_LOAD_MESH_DATA_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "glint.h"

enum {
    MESH_HAS_NORMALS = 1u << 0,
    MESH_HAS_UV = 1u << 1,
    MESH_HAS_COLORS = 1u << 2,
};

typedef enum mesh_tex_kind {
    MESH_TEX_FILE = 1,    /* bytes: the path as the model file wrote it */
    MESH_TEX_ENCODED = 2, /* bytes: an image file held inside the model (PNG, JPEG...) */
    MESH_TEX_TEXELS = 3,  /* bytes: width*height texels, 4 bytes each, B G R A, row 0 at the top */
} mesh_tex_kind;

typedef struct mesh_tex {
    uint32_t kind, width, height, size;
    uint8_t *bytes;
} mesh_tex;

typedef struct mesh_mat {
    float diffuse[3], specular[3];
    float shininess; /* Phong exponent, 0 when the file gives none */
    float opacity;   /* 1 opaque .. 0 invisible, each format's convention already applied */
    int32_t texture; /* diffuse texture: index into textures, or -1 */
} mesh_mat;

typedef struct mesh_data {
    uint32_t nverts, ntris, nmats, ntexs, flags;
    uint32_t dropped;   /* faces the importer left out (not triangles, bad indices) */
    uint32_t skinned;   /* meshes posed through their bones */
    float (*pos)[3];
    float (*nrm)[3];    /* MESH_HAS_NORMALS */
    float (*uv)[2];     /* MESH_HAS_UV */
    float (*col)[3];    /* MESH_HAS_COLORS: per-vertex colour */
    uint32_t (*tri)[3];
    uint32_t *tri_mat;  /* < nmats */
    mesh_mat *mats;     /* at least one */
    mesh_tex *texs;
} mesh_data;

/* Allocates the arrays for the counts and flags already set in md (zeroed);
 * mats and texs only when still NULL. On failure frees everything in md. */
glint_rc mesh_data_alloc(mesh_data *md, glint_error *err);
void mesh_data_free(mesh_data *md);

/* Bytes of md's wire form, or 0 when it would pass max_bytes. */
size_t mesh_data_wire_size(const mesh_data *md, size_t max_bytes);
/* Writes md's wire form into buf (mesh_data_wire_size bytes). */
void mesh_data_encode(const mesh_data *md, uint8_t *buf);
/* Reads a wire form, checking it whole (counts against size, indices,
 * flags, texture sizes); name is for messages. Errors are GLINT_ERR_INPUT
 * or GLINT_ERR_NOMEM. */
glint_rc mesh_data_decode(const uint8_t *buf, size_t size, const char *name, mesh_data *out,
                          glint_error *err);

#endif
