/* cli/heap: after heap_ready, blocks up to 32 MiB come from the heap
 * rather than from mappings of their own, and the heap holds room in
 * proportion to the scene file's size, kept after it is freed. Under
 * AddressSanitizer the heap is the sanitizer's and heap_ready leaves it
 * alone: these tests then have nothing to check. */
#include <criterion/criterion.h>
#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli/heap.h"
#include "tmpdir.h"

#if defined(__SANITIZE_ADDRESS__)
#define SKIP_SANITIZED() cr_skip_test("the heap is AddressSanitizer's")
#else
#define SKIP_SANITIZED() (void)0
#endif

/* Whether a block of n bytes is a mapping of its own. */
static bool mapped_alone(size_t n)
{
    size_t before = mallinfo2().hblks;
    void *p = malloc(n);
    cr_assert_not_null(p);
    bool alone = mallinfo2().hblks > before;
    free(p);
    return alone;
}

Test(heap, big_blocks_come_from_the_heap)
{
    SKIP_SANITIZED();
    /* glibc's default maps a block of 1 MiB on its own */
    cr_assert(mapped_alone((size_t)1 << 20), "the default changed: nothing left to check");
    heap_ready(NULL);
    cr_assert_not(mapped_alone((size_t)1 << 20));
    cr_assert_not(mapped_alone((size_t)31 << 20));
    cr_assert(mapped_alone((size_t)64 << 20), "blocks past 32 MiB keep their own mapping");
}

/* A scene file of `mib` MiB in the test's folder. */
static void scene_file(const char *path, int mib)
{
    FILE *f = fopen(path, "wb");
    cr_assert_not_null(f);
    for (int i = 0; i < mib * (1 << 20) / 16; i++) /* comment lines of 16 bytes */
        fputs("# 0123456789abc\n", f);
    cr_assert_eq(fclose(f), 0);
}

/* How much heap_ready(path) grows the heap by. */
static size_t room_for(const char *path)
{
    size_t before = mallinfo2().arena;
    heap_ready(path);
    return mallinfo2().arena - before;
}

Test(heap, room_in_proportion_to_the_scene_file)
{
    SKIP_SANITIZED();
    tmpdir_make("heap");
    char path[256];
    snprintf(path, sizeof path, "%s/big.yaml", dir);
    scene_file(path, 1);
    size_t room = room_for(path);
    /* 12 MiB taken and given back: the heap keeps it */
    cr_assert(room >= (size_t)12 << 20, "the heap grew by %zu bytes", room);
    cr_assert(room < (size_t)16 << 20, "the heap grew by %zu bytes", room);
    tmpdir_remove();
}

Test(heap, room_past_the_size_of_a_mapped_block)
{
    SKIP_SANITIZED();
    tmpdir_make("heap");
    char path[256];
    snprintf(path, sizeof path, "%s/bigger.yaml", dir);
    scene_file(path, 4);
    /* 48 MiB, more than one block may take from the heap: kept all the same */
    size_t room = room_for(path);
    cr_assert(room >= (size_t)48 << 20, "the heap grew by %zu bytes", room);
    cr_assert(room < (size_t)56 << 20, "the heap grew by %zu bytes", room);
    tmpdir_remove();
}

Test(heap, no_room_without_a_file_of_known_size)
{
    SKIP_SANITIZED();
    size_t before = mallinfo2().arena;
    heap_ready("-");
    heap_ready("/nonexistent/scene.yaml");
    heap_ready(NULL);
    cr_assert_lt(mallinfo2().arena - before, (size_t)1 << 20);
}
