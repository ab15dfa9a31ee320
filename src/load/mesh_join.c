#include "mesh_join.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <time.h>

#define EMPTY UINT32_MAX

/* The table's hash: SipHash-1-3 (Aumasson and Bernstein) under a key drawn
 * for each call, so that a file cannot be made to send every vertex to one
 * slot (with a fixed, invertible mix a crafted 9.6 MB PLY took 33 s). The
 * result does not depend on the key: vertices are numbered in the order
 * they come, whatever slot they land in. */
typedef struct sip {
    uint64_t v0, v1, v2, v3;
} sip;

static uint64_t rotl(uint64_t x, int b) { return (x << b) | (x >> (64 - b)); }

static void round1(sip *s)
{
    s->v0 += s->v1, s->v1 = rotl(s->v1, 13), s->v1 ^= s->v0, s->v0 = rotl(s->v0, 32);
    s->v2 += s->v3, s->v3 = rotl(s->v3, 16), s->v3 ^= s->v2;
    s->v0 += s->v3, s->v3 = rotl(s->v3, 21), s->v3 ^= s->v0;
    s->v2 += s->v1, s->v1 = rotl(s->v1, 17), s->v1 ^= s->v2, s->v2 = rotl(s->v2, 32);
}

static void absorb(sip *s, uint64_t m)
{
    s->v3 ^= m;
    round1(s);
    s->v0 ^= m;
}

/* The vertex's attributes as 32-bit words, two to a message; n words. */
static int vertex_words(const mesh_data *md, uint32_t v, uint32_t w[11])
{
    int n = 0;
    memcpy(w, md->pos[v], sizeof md->pos[v]), n += 3;
    if (md->nrm)
        memcpy(w + n, md->nrm[v], sizeof md->nrm[v]), n += 3;
    if (md->uv)
        memcpy(w + n, md->uv[v], sizeof md->uv[v]), n += 2;
    if (md->col)
        memcpy(w + n, md->col[v], sizeof md->col[v]), n += 3;
    return n;
}

static uint64_t hash_vertex(const mesh_data *md, uint32_t v, const uint64_t key[2])
{
    uint32_t w[12] = {0};
    int n = vertex_words(md, v, w);
    sip s = {key[0] ^ 0x736f6d6570736575ull, key[1] ^ 0x646f72616e646f6dull,
             key[0] ^ 0x6c7967656e657261ull, key[1] ^ 0x7465646279746573ull};
    for (int i = 0; i + 1 < n; i += 2)
        absorb(&s, (uint64_t)w[i] | (uint64_t)w[i + 1] << 32);
    absorb(&s, (uint64_t)(4 * n) << 56 | (n % 2 ? w[n - 1] : 0));
    s.v2 ^= 0xff;
    for (int r = 0; r < 3; r++)
        round1(&s);
    return s.v0 ^ s.v1 ^ s.v2 ^ s.v3;
}

static void draw_key(uint64_t key[2])
{
    if (getrandom(key, 2 * sizeof *key, GRND_NONBLOCK) == (ssize_t)(2 * sizeof *key))
        return;
    struct timespec t; /* no entropy yet: the clock and an address will do */
    clock_gettime(CLOCK_MONOTONIC, &t);
    key[0] = (uint64_t)t.tv_nsec * 0x9e3779b97f4a7c15ull ^ (uint64_t)(uintptr_t)key;
    key[1] = (uint64_t)t.tv_sec * 0xc2b2ae3d27d4eb4full ^ rotl(key[0], 29);
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
#if SIZE_MAX / 4 < UINT32_MAX
    if (n > SIZE_MAX / 4) /* a table of twice n slots must be countable */
        return false;
#endif
    size_t slots = 16;
    while (slots < 2 * (size_t)n)
        slots *= 2;
    uint32_t *table = malloc(slots * sizeof *table), *to = malloc((n ? n : 1) * sizeof *to);
    if (!table || !to) {
        free(table), free(to);
        return false;
    }
    memset(table, 0xff, slots * sizeof *table);
    memset(to, 0xff, n * sizeof *to); /* EMPTY: no triangle uses the vertex */
    for (uint32_t t = t0; t < t1; t++)
        for (int k = 0; k < 3; k++)
            to[md->tri[t][k] - v0] = 0;
    uint64_t key[2];
    draw_key(key);
    /* in place: vertex v's new number is at most v, and every vertex below
     * v has been read before its slot is written */
    uint32_t kept = 0;
    for (uint32_t v = 0; v < n; v++) {
        if (to[v] == EMPTY)
            continue;
        size_t s = (size_t)hash_vertex(md, v0 + v, key) & (slots - 1);
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
