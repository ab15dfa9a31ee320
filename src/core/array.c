#include "array.h"
#include "cpus.h"

#include <limits.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#define HUGE_PAGE ((size_t)2 << 20)

/* n bytes in whole 2 MiB pages, aligned, in transparent huge pages where
 * the kernel offers them, and with `map` mapped at once (advice only:
 * failure changes nothing); not zeroed. Rounding up wastes at most a huge
 * page, so the callers that map take it from ARRAY_HUGE_FROM up. */
static void *alloc_huge(size_t n, bool map)
{
    if (n > SIZE_MAX - HUGE_PAGE)
        return NULL;
    size_t whole = (n + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
    void *p = aligned_alloc(HUGE_PAGE, whole);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (p)
        madvise(p, whole, MADV_HUGEPAGE);
#if defined(MADV_POPULATE_WRITE)
    if (p && map)
        madvise(p, whole, MADV_POPULATE_WRITE); /* Linux 5.14 on */
#endif
#endif
    (void)map;
    return p;
}

void *array_realloc(void *items, size_t old, size_t n)
{
    if (n < ARRAY_HUGE_FROM)
        return realloc(items, n);
    void *q = alloc_huge(n, true);
    if (q && items && old)
        memcpy(q, items, old < n ? old : n);
    if (q)
        free(items);
    return q;
}

int array_push(void **items, int *n, int *cap, size_t elem)
{
    if (*n == *cap) {
        if (*cap > INT_MAX / 2)
            return -1;
        int ncap = *cap ? *cap * 2 : 8;
        void *p = array_realloc(*items, (size_t)*n * elem, (size_t)ncap * elem);
        if (!p)
            return -1;
        *items = p;
        *cap = ncap;
    }
    memset((char *)*items + (size_t)*n * elem, 0, elem);
    return (*n)++;
}

bool array_grow(void **items, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return true;
    size_t ncap = *cap ? *cap : 16;
    while (ncap < need) {
        if (ncap > SIZE_MAX / 2 / elem)
            return false;
        ncap *= 2;
    }
    void *q = array_realloc(*items, *cap * elem, ncap * elem);
    if (!q)
        return false;
    *items = q;
    *cap = ncap;
    return true;
}

void *array_alloc_big(size_t n)
{
    if (n < HUGE_PAGE || n > SIZE_MAX - HUGE_PAGE)
        return aligned_alloc(64, (n + 63) / 64 * 64);
    return alloc_huge(n, false);
}

/* A block being mapped and cleared a huge page at a time, by threads that
 * take the next page as they finish one: a thread the host serves slowly
 * (mapping a page took 0.7 ms on one thread and 1.8 on the other, on one
 * virtual machine) then maps fewer. */
typedef struct fill_job {
    char *p;
    size_t n, pages;
    atomic_size_t next;
    bool zero; /* clear each page once mapped (else it is fresh: the kernel's zeros) */
} fill_job;

static void *fill(void *arg)
{
    fill_job *f = arg;
    for (size_t i; (i = atomic_fetch_add(&f->next, 1)) < f->pages;) {
        char *page = f->p + i * HUGE_PAGE;
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
        madvise(page, HUGE_PAGE, MADV_POPULATE_WRITE); /* Linux 5.14 on */
#endif
        size_t end = (i + 1) * HUGE_PAGE < f->n ? (i + 1) * HUGE_PAGE : f->n;
        if (f->zero)
            memset(page, 0, end - i * HUGE_PAGE);
    }
    return NULL;
}

/* From this size a block may be mapped by more than one thread. */
#define FILL_SPLIT_FROM ((size_t)8 << 20)
#define FILL_MAX_THREADS 8

static void fill_on(void *p, size_t n, int threads, bool zero)
{
    fill_job f = {p, n, (n + HUGE_PAGE - 1) / HUGE_PAGE, 0, zero};
    int k = n >= FILL_SPLIT_FROM ? cpus_threads(threads, FILL_MAX_THREADS) : 1;
    k = (size_t)k > f.pages ? (int)f.pages : k;
    cpus_share(k, fill, &f);
}

void array_clear_on(void *p, size_t n, int threads) { fill_on(p, n, threads, true); }

void array_map_on(void *p, size_t n, int threads) { fill_on(p, n, threads, false); }

void *array_calloc_big_on(size_t n, int threads)
{
    if (n < ARRAY_HUGE_FROM)
        return calloc(1, n ? n : 1);
    /* mapped before it is written (a 1080p film touched by its render had
     * 70 ms of page faults, a 1024x512 texture decoded 4 ms); at most
     * twice the bytes asked for */
    char *p = alloc_huge(n, false);
    if (p)
        array_clear_on(p, n, threads);
    return p;
}

void *array_calloc_big(size_t n) { return array_calloc_big_on(n, 1); }
