#include "mesh_join.h"

#include <stdlib.h>
#include <string.h>

#define EMPTY UINT32_MAX

static uint32_t mix(uint32_t h, const void *p, size_t bytes)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < bytes; i += 4) {
        uint32_t w;
        memcpy(&w, b + i, 4);
        h = (h ^ w) * 0x9e3779b1u;
        h ^= h >> 15;
    }
    return h;
}

static uint32_t hash_vertex(const mesh_data *md, uint32_t v)
{
    uint32_t h = mix(0x811c9dc5u, md->pos[v], sizeof md->pos[v]);
    if (md->nrm)
        h = mix(h, md->nrm[v], sizeof md->nrm[v]);
    if (md->uv)
        h = mix(h, md->uv[v], sizeof md->uv[v]);
    if (md->col)
        h = mix(h, md->col[v], sizeof md->col[v]);
    return h ^ (h >> 16);
}

static bool same_vertex(const mesh_data *md, uint32_t a, uint32_t b)
{
    return memcmp(md->pos[a], md->pos[b], sizeof md->pos[a]) == 0 &&
           (!md->nrm || memcmp(md->nrm[a], md->nrm[b], sizeof md->nrm[a]) == 0) &&
           (!md->uv || memcmp(md->uv[a], md->uv[b], sizeof md->uv[a]) == 0) &&
           (!md->col || memcmp(md->col[a], md->col[b], sizeof md->col[a]) == 0);
}

static void move_vertex(mesh_data *md, uint32_t to, uint32_t from)
{
    memcpy(md->pos[to], md->pos[from], sizeof md->pos[to]);
    if (md->nrm)
        memcpy(md->nrm[to], md->nrm[from], sizeof md->nrm[to]);
    if (md->uv)
        memcpy(md->uv[to], md->uv[from], sizeof md->uv[to]);
    if (md->col)
        memcpy(md->col[to], md->col[from], sizeof md->col[to]);
}

bool mesh_join_vertices(mesh_data *md, uint32_t v0, uint32_t *nv, uint32_t t0, uint32_t t1)
{
    uint32_t n = *nv;
    if (n < 2)
        return true;
    size_t slots = 16;
    while (slots < 2 * (size_t)n)
        slots *= 2;
    uint32_t *table = malloc(slots * sizeof *table), *to = malloc((size_t)n * sizeof *to);
    if (!table || !to) {
        free(table), free(to);
        return false;
    }
    memset(table, 0xff, slots * sizeof *table);
    /* in place: vertex v's new number is at most v, and every vertex below
     * v has been read before its slot is written */
    uint32_t kept = 0;
    for (uint32_t v = 0; v < n; v++) {
        size_t s = hash_vertex(md, v0 + v) & (slots - 1);
        while (table[s] != EMPTY && !same_vertex(md, v0 + table[s], v0 + v))
            s = (s + 1) & (slots - 1);
        if (table[s] == EMPTY) {
            if (kept != v)
                move_vertex(md, v0 + kept, v0 + v);
            table[s] = kept++;
        }
        to[v] = table[s];
    }
    for (uint32_t t = t0; t < t1; t++)
        for (int k = 0; k < 3; k++)
            md->tri[t][k] = v0 + to[md->tri[t][k] - v0];
    *nv = kept;
    free(table);
    free(to);
    return true;
}
