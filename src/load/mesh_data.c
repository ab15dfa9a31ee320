#include "mesh_data.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "io/image.h"

static const char wire_magic[8] = "glintM1";

typedef struct wire_head {
    char magic[8];
    uint32_t nverts, ntris, nmats, ntexs, flags, dropped, skinned, reserved;
} wire_head;

typedef struct wire_tex {
    uint32_t kind, width, height, size;
} wire_tex;

/* Longest texture path kept from a model file. */
#define MESH_TEX_PATH_MAX 4096u

/* Bytes of the per-vertex and per-triangle arrays. */
static uint64_t array_bytes(uint32_t nverts, uint32_t ntris, uint32_t flags)
{
    uint64_t per_vertex = 12 + (flags & MESH_HAS_NORMALS ? 12 : 0) + (flags & MESH_HAS_UV ? 8 : 0) +
                          (flags & MESH_HAS_COLORS ? 12 : 0);
    return per_vertex * nverts + 16ull * ntris;
}

glint_rc mesh_data_alloc(mesh_data *md, glint_error *err)
{
    size_t nv = md->nverts ? md->nverts : 1, nt = md->ntris ? md->ntris : 1;
    md->pos = calloc(nv, sizeof *md->pos);
    md->nrm = md->flags & MESH_HAS_NORMALS ? calloc(nv, sizeof *md->nrm) : NULL;
    md->uv = md->flags & MESH_HAS_UV ? calloc(nv, sizeof *md->uv) : NULL;
    md->col = md->flags & MESH_HAS_COLORS ? calloc(nv, sizeof *md->col) : NULL;
    md->tri = calloc(nt, sizeof *md->tri);
    md->tri_mat = calloc(nt, sizeof *md->tri_mat);
    if (!md->mats)
        md->mats = calloc(md->nmats ? md->nmats : 1, sizeof *md->mats);
    if (!md->texs)
        md->texs = calloc(md->ntexs ? md->ntexs : 1, sizeof *md->texs);
    if (!md->pos || (md->flags & MESH_HAS_NORMALS && !md->nrm) ||
        (md->flags & MESH_HAS_UV && !md->uv) || (md->flags & MESH_HAS_COLORS && !md->col) ||
        !md->tri || !md->tri_mat || !md->mats || !md->texs) {
        mesh_data_free(md);
        return err_nomem(err);
    }
    return GLINT_OK;
}

void mesh_data_free(mesh_data *md)
{
    free(md->pos);
    free(md->nrm);
    free(md->uv);
    free(md->col);
    free(md->tri);
    free(md->tri_mat);
    free(md->mats);
    if (md->texs)
        for (uint32_t i = 0; i < md->ntexs; i++)
            free(md->texs[i].bytes);
    free(md->texs);
    memset(md, 0, sizeof *md);
}

size_t mesh_data_wire_size(const mesh_data *md, size_t max_bytes)
{
    uint64_t n = sizeof(wire_head) + array_bytes(md->nverts, md->ntris, md->flags) +
                 (uint64_t)md->nmats * sizeof(mesh_mat);
    for (uint32_t i = 0; i < md->ntexs; i++)
        n += sizeof(wire_tex) + md->texs[i].size;
    return n > max_bytes || n > SIZE_MAX ? 0 : (size_t)n;
}

static uint8_t *put(uint8_t *at, const void *src, size_t n)
{
    if (n)
        memcpy(at, src, n);
    return at + n;
}

void mesh_data_encode(const mesh_data *md, uint8_t *buf)
{
    wire_head h = {{0}, md->nverts, md->ntris, md->nmats, md->ntexs, md->flags, md->dropped,
                   md->skinned, 0};
    memcpy(h.magic, wire_magic, sizeof h.magic);
    size_t nv = md->nverts, nt = md->ntris;
    buf = put(buf, &h, sizeof h);
    buf = put(buf, md->pos, nv * sizeof *md->pos);
    if (md->flags & MESH_HAS_NORMALS)
        buf = put(buf, md->nrm, nv * sizeof *md->nrm);
    if (md->flags & MESH_HAS_UV)
        buf = put(buf, md->uv, nv * sizeof *md->uv);
    if (md->flags & MESH_HAS_COLORS)
        buf = put(buf, md->col, nv * sizeof *md->col);
    buf = put(buf, md->tri, nt * sizeof *md->tri);
    buf = put(buf, md->tri_mat, nt * sizeof *md->tri_mat);
    buf = put(buf, md->mats, md->nmats * sizeof *md->mats);
    for (uint32_t i = 0; i < md->ntexs; i++) {
        const mesh_tex *t = &md->texs[i];
        wire_tex w = {t->kind, t->width, t->height, t->size};
        buf = put(buf, &w, sizeof w);
        buf = put(buf, t->bytes, t->size);
    }
}

/* ---- decoding: nothing in the buffer is trusted ---------------------------- */

typedef struct reader {
    const uint8_t *p;
    size_t left;
} reader;

static bool take(reader *r, void *dst, size_t n)
{
    if (n > r->left)
        return false;
    if (n)
        memcpy(dst, r->p, n);
    r->p += n;
    r->left -= n;
    return true;
}

static bool tex_ok(const wire_tex *w)
{
    switch (w->kind) {
    case MESH_TEX_FILE:
        return w->size > 0 && w->size <= MESH_TEX_PATH_MAX && !w->width && !w->height;
    case MESH_TEX_ENCODED:
        return w->size > 0 && !w->width && !w->height;
    case MESH_TEX_TEXELS:
        return w->width > 0 && w->height > 0 &&
               (uint64_t)w->width * w->height <= IMAGE_MAX_PIXELS &&
               w->size == (uint64_t)w->width * w->height * 4;
    default:
        return false;
    }
}

static glint_rc read_textures(reader *r, mesh_data *md, glint_error *err)
{
    for (uint32_t i = 0; i < md->ntexs; i++) {
        wire_tex w;
        if (!take(r, &w, sizeof w) || !tex_ok(&w) || w.size > r->left)
            return GLINT_ERR_INPUT;
        mesh_tex *t = &md->texs[i];
        t->bytes = malloc(w.size + 1); /* room for a path's terminating zero */
        if (!t->bytes)
            return err_nomem(err);
        *t = (mesh_tex){w.kind, w.width, w.height, w.size, t->bytes};
        take(r, t->bytes, w.size);
        t->bytes[w.size] = 0;
        if (w.kind == MESH_TEX_FILE && memchr(t->bytes, 0, w.size))
            return GLINT_ERR_INPUT;
    }
    return GLINT_OK;
}

static bool indices_ok(const mesh_data *md)
{
    for (uint32_t t = 0; t < md->ntris; t++) {
        if (md->tri_mat[t] >= md->nmats)
            return false;
        for (int k = 0; k < 3; k++)
            if (md->tri[t][k] >= md->nverts)
                return false;
    }
    for (uint32_t i = 0; i < md->nmats; i++)
        if (md->mats[i].texture < -1 || md->mats[i].texture >= (int64_t)md->ntexs)
            return false;
    return true;
}

static glint_rc read_body(reader *r, mesh_data *md, glint_error *err)
{
    glint_rc rc = mesh_data_alloc(md, err);
    if (rc != GLINT_OK)
        return rc;
    size_t nv = md->nverts, nt = md->ntris;
    take(r, md->pos, nv * sizeof *md->pos);
    if (md->nrm)
        take(r, md->nrm, nv * sizeof *md->nrm);
    if (md->uv)
        take(r, md->uv, nv * sizeof *md->uv);
    if (md->col)
        take(r, md->col, nv * sizeof *md->col);
    take(r, md->tri, nt * sizeof *md->tri);
    take(r, md->tri_mat, nt * sizeof *md->tri_mat);
    take(r, md->mats, md->nmats * sizeof *md->mats);
    rc = read_textures(r, md, err);
    if (rc == GLINT_OK && (r->left != 0 || !indices_ok(md)))
        rc = GLINT_ERR_INPUT;
    return rc;
}

glint_rc mesh_data_decode(const uint8_t *buf, size_t size, const char *name, mesh_data *out,
                          glint_error *err)
{
    memset(out, 0, sizeof *out);
    reader r = {buf, size};
    wire_head h;
    glint_rc rc = GLINT_ERR_INPUT;
    if (take(&r, &h, sizeof h) && memcmp(h.magic, wire_magic, sizeof h.magic) == 0 &&
        !(h.flags & ~(uint32_t)(MESH_HAS_NORMALS | MESH_HAS_UV | MESH_HAS_COLORS)) &&
        h.nmats > 0 &&
        array_bytes(h.nverts, h.ntris, h.flags) + (uint64_t)h.nmats * sizeof(mesh_mat) +
                (uint64_t)h.ntexs * sizeof(wire_tex) <=
            r.left) {
        *out = (mesh_data){.nverts = h.nverts, .ntris = h.ntris, .nmats = h.nmats,
                           .ntexs = h.ntexs, .flags = h.flags, .dropped = h.dropped,
                           .skinned = h.skinned};
        rc = read_body(&r, out, err);
    }
    if (rc == GLINT_OK)
        return rc;
    mesh_data_free(out);
    if (rc == GLINT_ERR_INPUT)
        return err_set(err, rc, "%s: the importer handed back a malformed mesh", name);
    return rc;
}
