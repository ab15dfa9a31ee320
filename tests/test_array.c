/* core/array: growth keeps what the array holds, and big zeroed blocks
 * (films, decoded images) are zero however the allocator last used their
 * memory, whether or not the kernel takes the huge-page advice. */
#include <criterion/criterion.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/array.h"

static bool all_zero(const unsigned char *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (p[i])
            return false;
    return true;
}

Test(array, calloc_big_is_zero_after_dirty_reuse)
{
    /* Freed dirty blocks of these sizes are what malloc hands out next
     * (after the first free of a mapped block, glibc serves blocks that big
     * from its heap), so a block that skipped the zeroing shows it. */
    const size_t sizes[] = {1, 4096, 100000, ((size_t)3 << 20) + 17, (size_t)25 << 20};
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        size_t n = sizes[k];
        for (int round = 0; round < 3; round++) {
            unsigned char *dirty = malloc(n);
            cr_assert_not_null(dirty);
            memset(dirty, 0xA5, n);
            free(dirty);
            unsigned char *p = array_calloc_big(n);
            cr_assert_not_null(p, "size %zu", n);
            cr_assert(all_zero(p, n), "a block of %zu bytes is not all zero", n);
            p[0] = 1, p[n - 1] = 2; /* writable from end to end */
            free(p);
        }
    }
}

Test(array, grow_to_millions_keeps_the_items)
{
    uint32_t *items = NULL;
    size_t cap = 0;
    const size_t n = (size_t)3 << 20; /* 12 MiB of items, grown by doubling */
    for (size_t i = 0; i < n; i++) {
        cr_assert(array_reserve((void **)&items, &cap, i + 1, sizeof *items));
        items[i] = (uint32_t)(i * 2654435761u);
    }
    cr_assert_geq(cap, n);
    for (size_t i = 0; i < n; i++)
        if (items[i] != (uint32_t)(i * 2654435761u))
            cr_assert_fail("item %zu changed in growth", i);
    free(items);
}

Test(array, realloc_keeps_the_bytes_in_use_across_huge_pages)
{
    /* small to small, small to huge (from 1 MiB), huge to bigger huge */
    const size_t sizes[] = {1000, 100000, (size_t)3 << 19, (size_t)5 << 20, (size_t)9 << 20};
    unsigned char *p = NULL;
    size_t used = 0;
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        unsigned char *q = array_realloc(p, used, sizes[k]);
        cr_assert_not_null(q, "size %zu", sizes[k]);
        for (size_t i = 0; i < used; i++)
            if (q[i] != (unsigned char)(i * 7 + 3))
                cr_assert_fail("byte %zu lost growing to %zu", i, sizes[k]);
        for (size_t i = used; i < sizes[k]; i++)
            q[i] = (unsigned char)(i * 7 + 3);
        p = q, used = sizes[k];
    }
    free(p);
}

Test(array, realloc_to_less_keeps_what_fits)
{
    size_t big = (size_t)5 << 20, less = (size_t)3 << 20;
    unsigned char *p = array_realloc(NULL, 0, big);
    cr_assert_not_null(p);
    for (size_t i = 0; i < big; i++)
        p[i] = (unsigned char)(i * 13 + 1);
    unsigned char *q = array_realloc(p, big, less); /* more in use than the new block holds */
    cr_assert_not_null(q);
    for (size_t i = 0; i < less; i++)
        if (q[i] != (unsigned char)(i * 13 + 1))
            cr_assert_fail("byte %zu lost shrinking", i);
    free(q);
}

Test(array, calloc_big_on_threads_is_zero_end_to_end)
{
    /* split among threads from 8 MiB up, whole huge pages each: sizes on
     * either side of the split, uneven shares, more threads than pages */
    const size_t sizes[] = {((size_t)8 << 20) - 1, (size_t)8 << 20, ((size_t)9 << 20) + 12345,
                            ((size_t)25 << 20) + 17};
    const int threads[] = {0, 1, 2, 3, 8};
#if defined(__GLIBC__)
    /* blocks this big from the heap, kept when freed, so that a freed one
     * comes back dirty (each would otherwise be a fresh mapping, zero
     * whatever we do) */
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++)
        for (size_t t = 0; t < sizeof threads / sizeof *threads; t++) {
            size_t n = sizes[k];
            /* the same block again, dirty: the allocator hands it back */
            unsigned char *dirty = array_calloc_big_on(n, threads[t]);
            cr_assert_not_null(dirty);
            memset(dirty, 0xA5, n);
            free(dirty);
            unsigned char *p = array_calloc_big_on(n, threads[t]);
            cr_assert_not_null(p, "size %zu, %d threads", n, threads[t]);
            cr_assert(all_zero(p, n), "%zu bytes on %d threads are not all zero", n,
                      threads[t]);
            p[0] = 1, p[n - 1] = 2;
            free(p);
        }
}
