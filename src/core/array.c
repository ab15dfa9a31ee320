#include "array.h"

#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#define HUGE_PAGE ((size_t)2 << 20)

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
    if (n < HUGE_PAGE / 8 || n > SIZE_MAX - HUGE_PAGE)
        return calloc(1, n ? n : 1);
    /* Whole huge pages, aligned, so that none of it is left in 4 KiB
     * pages, mapped at once: a virtual machine may trap the first touch of
     * every 4 KiB page (about 10 us each on some: 70 ms for a 1080p film
     * touched by its render, 4 ms for a 1024x512 texture decoded). */
    size_t whole = (n + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
    void *p = aligned_alloc(HUGE_PAGE, whole);
    if (!p)
        return NULL;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, whole, MADV_HUGEPAGE); /* advice only: failure changes nothing */
#if defined(MADV_POPULATE_WRITE)
    madvise(p, whole, MADV_POPULATE_WRITE); /* likewise (Linux 5.14 on) */
#endif
#endif
    return memset(p, 0, n);
}
