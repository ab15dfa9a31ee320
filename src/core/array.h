/* array: growth for the flat arrays that scenes own (objects, materials,
 * textures...). Arrays are a pointer, a count and a capacity. */
#ifndef GLINT_CORE_ARRAY_H
#define GLINT_CORE_ARRAY_H

#include <stdbool.h>
#include <stddef.h>

/* The size from which array_realloc and array_calloc_big take whole 2 MiB
 * huge pages (so a block takes at most twice its bytes). */
#define ARRAY_HUGE_FROM ((size_t)1 << 20)

/* realloc for a block of which the first `old` bytes are in use (no more
 * than the block holds; 0 when items is NULL): from 1 MiB up the block is
 * copied into whole 2 MiB huge pages mapped at once (at most twice n)
 * rather than grown in place, keeping min(old, n) bytes. A virtual machine
 * may trap the first touch of every 4 KiB page (about 10 us each on some),
 * and growth left in such pages cost more than the copy (advised huge,
 * realloc's remapping split them, which cost more still). NULL when
 * memory runs out, the block untouched; the result is freed with free(). */
void *array_realloc(void *items, size_t old, size_t n);

/* Makes room for one more element of size elem in *items (count *n, capacity
 * *cap) and returns its index, or -1 when memory runs out (the array is left
 * unchanged). The new element is zeroed. */
int array_push(void **items, int *n, int *cap, size_t elem);

/* Grows *items (elements of size elem, capacity *cap, counted in size_t)
 * by doubling from 16 until it holds need; false when memory runs out or
 * the size would overflow (the array is left unchanged). */
bool array_grow(void **items, size_t *cap, size_t need, size_t elem);

/* The same, asked where the array usually has room: the test is inline. */
static inline bool array_reserve(void **items, size_t *cap, size_t need, size_t elem)
{
    return need <= *cap || array_grow(items, cap, need, elem);
}

/* n bytes for a large array written once in full (a BVH build's working
 * arrays), aligned to 64: from 2 MiB up in transparent huge pages where
 * the kernel offers them (madvise), so that touching it takes one page
 * fault per 2 MiB rather than per 4 KiB. NULL when memory runs out; free
 * with free(). */
void *array_alloc_big(size_t n);

/* n zeroed bytes for a large array that will be written in full (a film,
 * a decoded image): from 1 MiB up, whole 2 MiB pages, aligned (so at most
 * twice n), in transparent huge pages where the kernel offers them and
 * mapped before they are returned, so that writing them takes no page
 * fault per 4 KiB. NULL when memory runs out; free with free(). */
void *array_calloc_big(size_t n);

/* array_calloc_big with the pages of a block from 8 MiB up mapped and
 * cleared by up to `threads` threads at once (0: one per CPU, as
 * cpus_threads counts them), each taking the next huge page as it
 * finishes one: on a virtual machine whose host gives memory back,
 * mapping a 1080p film after another program ended took 40-55 ms on one
 * thread and 25-31 ms on two. */
void *array_calloc_big_on(size_t n, int threads);

/* Maps and clears the n bytes at p (a block of whole 2 MiB pages from
 * 2 MiB up, aligned to one) as array_calloc_big_on does: from 8 MiB up
 * by up to `threads` threads, a huge page at a time. */
void array_clear_on(void *p, size_t n, int threads);

/* array_clear_on for pages never written since they were mapped: the
 * kernel gives them zeroed, so they are mapped but not cleared again. */
void array_map_on(void *p, size_t n, int threads);

#endif
