/* array: growth for the flat arrays that scenes own (objects, materials,
 * textures...). Arrays are a pointer, a count and a capacity. */
#ifndef GLINT_CORE_ARRAY_H
#define GLINT_CORE_ARRAY_H

#include <stddef.h>

/* Makes room for one more element of size elem in *items (count *n, capacity
 * *cap) and returns its index, or -1 when memory runs out (the array is left
 * unchanged). The new element is zeroed. */
int array_push(void **items, int *n, int *cap, size_t elem);

/* n bytes for a large array written once in full (a BVH build's working
 * arrays), aligned to 64: from 2 MiB up in transparent huge pages where
 * the kernel offers them (madvise), so that touching it takes one page
 * fault per 2 MiB rather than per 4 KiB. NULL when memory runs out; free
 * with free(). */
void *array_alloc_big(size_t n);

#endif
