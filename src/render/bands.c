#include "bands.h"

#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>

/* A band's items not yet taken, [lo, hi), as lo | hi << 32, on a cache
 * line of its own: each thread changes its own band's at every item. */
typedef struct band {
    _Alignas(64) _Atomic uint64_t span;
} band;

struct bands {
    int n;
    band *band;
};

static uint64_t span_of(uint32_t lo, uint32_t hi) { return (uint64_t)hi << 32 | lo; }

bands *bands_new(int n, int nbands)
{
    bands *b = malloc(sizeof *b);
    if (!b)
        return NULL;
    b->n = nbands < 1 ? 1 : nbands;
    b->band = aligned_alloc(_Alignof(band), sizeof *b->band * (size_t)b->n);
    if (!b->band) {
        free(b);
        return NULL;
    }
    for (int i = 0; i < b->n; i++) {
        uint32_t lo = (uint32_t)((int64_t)n * i / b->n);
        uint32_t hi = (uint32_t)((int64_t)n * (i + 1) / b->n);
        atomic_init(&b->band[i].span, span_of(lo, hi));
    }
    return b;
}

void bands_free(bands *b)
{
    if (!b)
        return;
    free(b->band);
    free(b);
}

/* The front (or back) item of band d; -1 when it is empty. */
static int take_end(band *d, int back)
{
    uint64_t v = atomic_load(&d->span);
    for (;;) {
        uint32_t lo = (uint32_t)v, hi = (uint32_t)(v >> 32);
        if (lo >= hi)
            return -1;
        uint64_t next = back ? span_of(lo, hi - 1) : span_of(lo + 1, hi);
        if (atomic_compare_exchange_weak(&d->span, &v, next))
            return (int)(back ? hi - 1 : lo);
    }
}

int bands_take(bands *b, int own)
{
    if (own >= 0 && own < b->n) {
        int i = take_end(&b->band[own], 0);
        if (i >= 0)
            return i;
    }
    for (;;) {
        int fullest = -1;
        uint32_t most = 0;
        for (int k = 0; k < b->n; k++) {
            uint64_t v = atomic_load(&b->band[k].span);
            uint32_t lo = (uint32_t)v, hi = (uint32_t)(v >> 32);
            if (hi > lo && hi - lo > most) {
                most = hi - lo;
                fullest = k;
            }
        }
        if (fullest < 0)
            return -1;
        int i = take_end(&b->band[fullest], 1);
        if (i >= 0)
            return i;
    }
}
