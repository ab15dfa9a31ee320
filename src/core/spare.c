#define _GNU_SOURCE /* mremap */
#include "spare.h"

#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>

#include "array.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

#define HUGE_PAGE ((size_t)2 << 20)

typedef struct block {
    char *p;
    size_t n; /* whole huge pages */
} block;

/* The one block: kept (the spare) or taken. */
static struct {
    pthread_mutex_t lock;
    block b; /* p NULL: none */
    bool taken;
    size_t used; /* bytes from the block's start ever handed out (a whole block,
                    as spare_size reports it); past them, zeros */
} sp = {.lock = PTHREAD_MUTEX_INITIALIZER};

static size_t whole_pages(size_t n)
{
    return n > SIZE_MAX - HUGE_PAGE ? 0 : (n + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
}

#if defined(__linux__) && defined(MREMAP_MAYMOVE) && defined(MREMAP_FIXED)
/* n bytes (whole huge pages) of address space aligned to a huge page,
 * reserved (no access) when `reserve`, else mapped readable and writable
 * and marked for huge pages; NULL when there is none. */
static char *map_aligned(size_t n, bool reserve)
{
    size_t span = n + HUGE_PAGE;
    char *r = mmap(NULL, span, reserve ? PROT_NONE : PROT_READ | PROT_WRITE,
                   MAP_PRIVATE | MAP_ANONYMOUS | (reserve ? MAP_NORESERVE : 0), -1, 0);
    if (r == MAP_FAILED)
        return NULL;
    char *p = (char *)(((uintptr_t)r + HUGE_PAGE - 1) & ~(uintptr_t)(HUGE_PAGE - 1));
    if (p > r)
        munmap(r, (size_t)(p - r));
    if (r + span > p + n)
        munmap(p + n, (size_t)(r + span - (p + n)));
    if (!reserve)
        madvise(p, n, MADV_HUGEPAGE);
    return p;
}

/* b grown to n bytes (whole huge pages, more than b holds): moved to
 * an aligned place with its pages, where a move to any other place would
 * split its huge pages (clearing a 12 MiB block so split took 14 ms
 * against 0.3); false, b unchanged, when that fails. */
static bool grow(block *b, size_t n)
{
    char *to = map_aligned(n, true);
    if (!to)
        return false;
    char *q = mremap(b->p, b->n, n, MREMAP_MAYMOVE | MREMAP_FIXED, to);
    if (q == MAP_FAILED) /* the reservation is left: the kernel may have unmapped it already,
                            and another thread mapped something there since */
        return false;
    madvise(q, n, MADV_HUGEPAGE);
    *b = (block){q, n};
    return true;
}

#else
static char *map_aligned(size_t n, bool reserve)
{
    (void)n, (void)reserve;
    return NULL;
}
static bool grow(block *b, size_t n)
{
    (void)b, (void)n;
    return false;
}
#endif

void *spare_make(size_t n)
{
    n = whole_pages(n);
    pthread_mutex_lock(&sp.lock);
    char *p = !sp.b.p && n ? map_aligned(n, false) : NULL;
    if (p)
        sp.b = (block){p, n};
    pthread_mutex_unlock(&sp.lock);
    return p;
}

/* spare_take, with *used (when taken) the bytes from the start that may
 * hold anything: the rest are fresh, zero. */
static void *take(size_t n, size_t *had, size_t *used)
{
    n = whole_pages(n ? n : 1);
    pthread_mutex_lock(&sp.lock);
    char *p = NULL;
    size_t before = sp.b.n;
    if (sp.b.p && !sp.taken && n && (n <= sp.b.n || grow(&sp.b, n))) {
        p = sp.b.p;
        sp.taken = true;
        if (had)
            *had = before;
        *used = sp.used;
        sp.used = sp.b.n; /* all of it, which spare_size reports, may now be written */
    }
    pthread_mutex_unlock(&sp.lock);
    return p;
}

void *spare_take(size_t n, size_t *had)
{
    size_t used;
    return take(n, had, &used);
}

bool spare_give(void *p)
{
    pthread_mutex_lock(&sp.lock);
    bool ours = p && sp.taken && p == sp.b.p;
    if (ours)
        sp.taken = false;
    pthread_mutex_unlock(&sp.lock);
    return ours;
}

void spare_free(void *p)
{
    if (!spare_give(p))
        free(p);
}

size_t spare_size(const void *p)
{
    pthread_mutex_lock(&sp.lock);
    size_t n = p && sp.taken && p == sp.b.p ? sp.b.n : 0;
    pthread_mutex_unlock(&sp.lock);
    return n;
}

void *spare_calloc(size_t n, int threads)
{
    size_t used = 0;
    char *p = n >= ARRAY_HUGE_FROM ? take(n, NULL, &used) : NULL; /* not for a small block */
    if (!p)
        return array_calloc_big_on(n, threads);
    /* what was handed out before is cleared, the rest only mapped: a
     * 1080p film in a spare never taken before (no parse tree in it) is
     * 25 MB the kernel has already zeroed */
    size_t dirty = used < n ? used : whole_pages(n);
    if (dirty)
        array_clear_on(p, dirty, threads);
    if (whole_pages(n) > dirty)
        array_map_on(p + dirty, whole_pages(n) - dirty, threads);
    return p;
}
