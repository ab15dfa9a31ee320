#include "array.h"

#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#define HUGE_PAGE ((size_t)2 << 20)

/* Asks for the pages of the block p of n bytes, one from malloc, to be
 * transparent huge pages where whole ones fit, when it spans any: a block
 * this big is a mapping of its own, and a virtual machine may trap the
 * first touch of every 4 KiB page (about 10 us each on some). Advice only:
 * failure changes nothing. */
static void advise_huge(void *p, size_t n)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const uintptr_t page = 4096;
    uintptr_t lo = (uintptr_t)p & ~(page - 1);
    uintptr_t hi = ((uintptr_t)p + n + page - 1) & ~(page - 1);
    if (p && n >= HUGE_PAGE)
        madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
#else
    (void)p, (void)n;
#endif
}

int array_push(void **items, int *n, int *cap, size_t elem)
{
    if (*n == *cap) {
        if (*cap > INT_MAX / 2)
            return -1;
        int ncap = *cap ? *cap * 2 : 8;
        void *p = realloc(*items, (size_t)ncap * elem);
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
    void *q = realloc(*items, ncap * elem);
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
    size_t whole = (n + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
    void *p = aligned_alloc(HUGE_PAGE, whole);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (p)
        madvise(p, whole, MADV_HUGEPAGE); /* advice only: failure changes nothing */
#endif
    return p;
}

void *array_calloc_big(size_t n)
{
    void *p = calloc(1, n ? n : 1);
    advise_huge(p, n);
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    /* and mapped at once (Linux 5.14 on; advice likewise) */
    if (p && n >= HUGE_PAGE) {
        uintptr_t lo = (uintptr_t)p & ~(uintptr_t)4095;
        madvise((void *)lo, (uintptr_t)p + n - lo, MADV_POPULATE_WRITE);
    }
#endif
    return p;
}
