#include "array.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

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
