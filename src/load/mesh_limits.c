#include "mesh_limits.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/error.h"

static uint64_t env_number(const char *key, uint64_t fallback)
{
    const char *v = getenv(key);
    if (!v || !*v)
        return fallback;
    char *end;
    unsigned long long n = strtoull(v, &end, 10);
    return *end == 0 && n > 0 && v[0] != '-' ? (uint64_t)n : fallback;
}

void mesh_limits_get(mesh_limits *out)
{
    out->memory_mib = env_number("GLINT_MESH_MEMORY", MESH_DEFAULT_MEMORY_MIB);
    uint64_t s = env_number("GLINT_MESH_SECONDS", MESH_DEFAULT_SECONDS);
    out->seconds = s > 86400 * 365 ? 86400 * 365 : (unsigned)s;
    out->triangles = env_number("GLINT_MESH_TRIANGLES", MESH_DEFAULT_TRIANGLES);
    if (out->triangles > (1u << 30))
        out->triangles = 1u << 30; /* the mesh's own index limits */
    const char *t = getenv("GLINT_MESH_TRUSTED");
    out->trusted = t && strcmp(t, "1") == 0;
}

/* a * b + c, saturating */
static uint64_t mad_sat(uint64_t a, uint64_t b, uint64_t c)
{
    if (b && a > (UINT64_MAX - c) / b)
        return UINT64_MAX;
    return a * b + c;
}

static glint_rc too_short(const char *name, const char *fmt, uint64_t count, const char *what,
                          uint64_t body, glint_error *err)
{
    return err_set(err, GLINT_ERR_INPUT,
                   "%s: the %s header declares %llu %s, more than the file's %llu bytes can hold "
                   "(truncated or corrupt file?)",
                   name, fmt, (unsigned long long)count, what, (unsigned long long)body);
}

static glint_rc too_many(const char *name, uint64_t count, const char *what, uint64_t limit,
                         glint_error *err)
{
    return err_set(err, GLINT_ERR_INPUT,
                   "%s: mesh is too large (%llu %s, limit %llu; GLINT_MESH_TRIANGLES raises it)",
                   name, (unsigned long long)count, what, (unsigned long long)limit);
}

/* ---- PLY ------------------------------------------------------------------- */

typedef struct ply_elem {
    char name[32];
    uint64_t count, bytes; /* bytes: the least one element takes */
} ply_elem;

static unsigned ply_type_size(const char *t)
{
    static const char *const one[] = {"char", "uchar", "int8", "uint8", NULL};
    static const char *const two[] = {"short", "ushort", "int16", "uint16", NULL};
    static const char *const four[] = {"int", "uint", "float", "int32", "uint32", "float32", NULL};
    for (int i = 0; one[i]; i++)
        if (strcmp(t, one[i]) == 0)
            return 1;
    for (int i = 0; two[i]; i++)
        if (strcmp(t, two[i]) == 0)
            return 2;
    for (int i = 0; four[i]; i++)
        if (strcmp(t, four[i]) == 0)
            return 4;
    return strcmp(t, "double") == 0 || strcmp(t, "float64") == 0 ? 8 : 1;
}

/* One header line; returns false at end_header. */
static bool ply_line(const char *line, bool *ascii, ply_elem *e, uint64_t *need,
                     uint64_t *verts, uint64_t *faces, uint64_t *elements)
{
    char a[32] = "", b[32] = "", c[32] = "";
    unsigned long long n = 0;
    if (sscanf(line, "format %31s", a) == 1) {
        *ascii = strcmp(a, "ascii") == 0;
    } else if (sscanf(line, "element %31s %llu", e->name, &n) == 2) {
        e->count = n;
        e->bytes = 0;
        *elements = mad_sat(1, n, *elements);
        if (strcmp(e->name, "vertex") == 0)
            *verts += n;
        if (strcmp(e->name, "face") == 0)
            *faces += n;
    } else if (sscanf(line, "property list %31s %31s %31s", a, b, c) == 3) {
        *need = mad_sat(e->count, *ascii ? 2 : ply_type_size(a), *need);
    } else if (sscanf(line, "property %31s %31s", a, b) == 2) {
        *need = mad_sat(e->count, *ascii ? 2 : ply_type_size(a), *need);
    } else if (strncmp(line, "end_header", 10) == 0 &&
               (line[10] == 0 || isspace((unsigned char)line[10]))) {
        return false;
    }
    return true;
}

static glint_rc ply_check(const char *name, const char *head, size_t n, uint64_t size,
                          const mesh_limits *lim, mesh_header *hdr, glint_error *err)
{
    bool ascii = true;
    ply_elem e = {"", 0, 0};
    uint64_t need = 0, verts = 0, faces = 0, elements = 0;
    size_t at = 0;
    for (;;) {
        const char *nl = memchr(head + at, '\n', n - at);
        if (!nl) {
            if (size <= n)
                return err_set(err, GLINT_ERR_INPUT,
                               "%s: the PLY header never ends (truncated file?)", name);
            return err_set(err, GLINT_ERR_INPUT, "%s: the PLY header is longer than %u bytes",
                           name, MESH_HEAD_BYTES);
        }
        char line[256];
        size_t len = (size_t)(nl - (head + at));
        memcpy(line, head + at, len < sizeof line - 1 ? len : sizeof line - 1);
        line[len < sizeof line - 1 ? len : sizeof line - 1] = 0;
        at += len + 1;
        if (!ply_line(line, &ascii, &e, &need, &verts, &faces, &elements))
            break;
    }
    uint64_t body = size - at;
    *hdr = (mesh_header){faces, ascii ? elements : 0, at};
    if (verts > 3 * lim->triangles)
        return too_many(name, verts, "vertices", 3 * lim->triangles, err);
    if (faces > lim->triangles)
        return too_many(name, faces, "faces", lim->triangles, err);
    if (need > body)
        return too_short(name, "PLY", verts ? verts : faces, verts ? "vertices" : "faces", body,
                         err);
    return GLINT_OK;
}

/* ---- OFF --------------------------------------------------------------------- */

/* Skips white space and # comments. */
static size_t off_skip(const char *h, size_t n, size_t at)
{
    while (at < n) {
        if (h[at] == '#') {
            while (at < n && h[at] != '\n')
                at++;
        } else if (isspace((unsigned char)h[at])) {
            at++;
        } else {
            break;
        }
    }
    return at;
}

static bool off_number(const char *h, size_t n, size_t *at, uint64_t *out)
{
    *at = off_skip(h, n, *at);
    if (*at >= n || !isdigit((unsigned char)h[*at]))
        return false;
    uint64_t v = 0;
    while (*at < n && isdigit((unsigned char)h[*at])) {
        v = v > UINT64_MAX / 16 ? UINT64_MAX / 16 : v * 10 + (uint64_t)(h[*at] - '0');
        (*at)++;
    }
    *out = v;
    return true;
}

static glint_rc off_check(const char *name, const char *head, size_t n, size_t at, uint64_t size,
                          const mesh_limits *lim, mesh_header *hdr, glint_error *err)
{
    uint64_t nv, nf;
    if (!off_number(head, n, &at, &nv) || !off_number(head, n, &at, &nf))
        return GLINT_OK;
    hdr->faces = nf;
    if (nv > 3 * lim->triangles)
        return too_many(name, nv, "vertices", 3 * lim->triangles, err);
    if (nf > lim->triangles)
        return too_many(name, nf, "faces", lim->triangles, err);
    /* a vertex is at least "0 0 0\n", a face at least "0\n" */
    uint64_t body = size - at;
    if (mad_sat(nv, 6, mad_sat(nf, 2, 0)) > body)
        return too_short(name, "OFF", nv, "vertices", body, err);
    return GLINT_OK;
}

glint_rc mesh_precheck(const char *name, const char *head, size_t n, uint64_t size,
                       const mesh_limits *lim, mesh_header *hdr, glint_error *err)
{
    *hdr = (mesh_header){0, 0, 0};
    if (n > size)
        n = (size_t)size;
    if (n >= 3 && strncasecmp(head, "ply", 3) == 0) /* what assimp's PLY reader looks for */
        return ply_check(name, head, n, size, lim, hdr, err);
    size_t at = off_skip(head, n, 0), start = at;
    while (at < n && isalnum((unsigned char)head[at]) && at - start < 8)
        at++;
    if (at - start >= 3 && at - start <= 6 && memcmp(head + at - 3, "OFF", 3) == 0 &&
        (at == n || isspace((unsigned char)head[at])))
        return off_check(name, head, n, at, size, lim, hdr, err);
    const char *dot = strrchr(name, '.');
    if (dot && strcasecmp(dot, ".stl") == 0 && n >= 84 && strncmp(head, "solid", 5) != 0) {
        uint32_t facets;
        memcpy(&facets, head + 80, 4);
        hdr->faces = facets;
        if (facets > lim->triangles)
            return too_many(name, facets, "triangles", lim->triangles, err);
        if (84 + 50ull * facets > size)
            return too_short(name, "STL", facets, "triangles", size - 84, err);
    }
    return GLINT_OK;
}

uint64_t mesh_count_lines(const char *p, size_t n, bool *open)
{
    uint64_t lines = 0;
    for (size_t i = 0; i < n; i++) {
        if (p[i] == '\n') {
            *open = false;
        } else if (!*open && !isspace((unsigned char)p[i])) {
            *open = true;
            lines++;
        }
    }
    return lines;
}
