#include "heap.h"

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#endif

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HEAP_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define HEAP_SANITIZED 1
#endif
#if defined(__GLIBC__) && defined(__linux__) && defined(MADV_POPULATE_WRITE) &&                 \
    !defined(HEAP_SANITIZED) && SIZE_MAX > 0xffffffffu
#define HEAP_POLICY 1
#endif

/* Blocks up to this size come from the heap. */
#define HEAP_MMAP_FROM ((size_t)32 << 20)
/* The room mapped at once: this many times the scene file's bytes (a
 * scene of 11,000 objects in 2 MB of YAML had 20 MiB of heap when
 * loaded), at most HEAP_ROOM_MAX. */
#define HEAP_ROOM_PER_BYTE 12
#define HEAP_ROOM_MAX ((size_t)256 << 20)
/* The room is taken in pieces of this size (below HEAP_MMAP_FROM). */
#define HEAP_PIECE ((size_t)16 << 20)
/* The main heap gives memory back only past this much free at its top:
 * twice the most room, which with glibc's slack is never trimmed away
 * as soon as it is freed. */
#define HEAP_TRIM_FROM (2 * HEAP_ROOM_MAX)

bool heap_policy_applies(void)
{
#if defined(HEAP_POLICY)
    return true;
#else
    return false;
#endif
}

#if defined(HEAP_POLICY)
/* Maps the pages of n bytes taken from the heap and gives them back: the
 * heap keeps them. Taken in pieces below HEAP_MMAP_FROM, which would
 * otherwise each be a mapping of their own and gone again when freed;
 * side by side at the top of the heap, they join again into one free
 * block. Each piece is mapped from its first whole 4 KiB page to its
 * last: the kernel puts whole huge pages where they fit, and small ones
 * at the ends. */
static void map_room(size_t n)
{
    enum { PIECES = (int)(HEAP_ROOM_MAX / HEAP_PIECE) + 1 };
    const uintptr_t page = 4096;
    char *piece[PIECES];
    int k = 0;
    for (size_t left = n; left > 0 && k < PIECES; k++) {
        size_t take = left < HEAP_PIECE ? left : HEAP_PIECE;
        if (!(piece[k] = malloc(take)))
            break;
        left -= take;
        uintptr_t a = ((uintptr_t)piece[k] + page - 1) & ~(page - 1);
        uintptr_t e = ((uintptr_t)piece[k] + take) & ~(page - 1);
        if (e > a) {
            madvise((void *)a, e - a, MADV_HUGEPAGE);
            madvise((void *)a, e - a, MADV_POPULATE_WRITE); /* Linux 5.14 on */
        }
    }
    while (k-- > 0)
        free(piece[k]);
}
#endif

void heap_ready(const char *path)
{
#if defined(HEAP_POLICY)
    mallopt(M_MMAP_THRESHOLD, (int)HEAP_MMAP_FROM);
    mallopt(M_TRIM_THRESHOLD, (int)HEAP_TRIM_FROM);
    struct stat st;
    if (!path || strcmp(path, "-") == 0 || stat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return;
    size_t bytes = (size_t)st.st_size;
    size_t room = bytes > HEAP_ROOM_MAX / HEAP_ROOM_PER_BYTE ? HEAP_ROOM_MAX
                                                             : bytes * HEAP_ROOM_PER_BYTE;
    if (room >= ((size_t)4 << 20))
        map_room(room);
#else
    (void)path;
#endif
}
