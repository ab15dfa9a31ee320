/* cli/heap: after heap_ready, blocks up to 32 MiB come from the heap
 * rather than from mappings of their own, and the heap holds room in
 * proportion to the scene file's size (up to its cap), kept after it is
 * freed and already mapped: carving it into small blocks takes almost no
 * page faults; at least 32 MiB of it, marked for huge pages, whatever the
 * file; blocks that other threads take come from that heap too;
 * the library's spare block (glint_memory_spare) is made and mapped
 * beside the room.
 * Where the policy does not apply (AddressSanitizer's
 * allocator, another C library) there is nothing to check. */
#include <criterion/criterion.h>
#include <malloc.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include "cli/heap.h"
#include "glint.h"
#include "tmpdir.h"

#define SKIP_UNLESS_APPLIES()                                                                   \
    do {                                                                                        \
        if (!heap_policy_applies())                                                             \
            cr_skip_test("the heap policy does not apply to this build");                      \
    } while (0)

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
    SKIP_UNLESS_APPLIES();
    if (!mapped_alone((size_t)1 << 20)) /* GLIBC_TUNABLES may have changed the default */
        cr_skip_test("this process's malloc already serves 1 MiB from its heap");
    heap_ready(NULL, 0, 0);
    cr_assert_not(mapped_alone((size_t)1 << 20));
    cr_assert_not(mapped_alone((size_t)31 << 20));
    cr_assert(mapped_alone((size_t)64 << 20), "blocks past 32 MiB keep their own mapping");
}

/* A scene file of `bytes` bytes, sparse (its size is all that counts). */
static void scene_file(const char *path, off_t bytes)
{
    FILE *f = fopen(path, "wb");
    cr_assert_not_null(f);
    cr_assert_eq(fclose(f), 0);
    cr_assert_eq(truncate(path, bytes), 0);
}

/* This process's resident bytes (/proc/self/statm). */
static size_t resident(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    cr_assert_not_null(f);
    unsigned long size = 0, pages = 0;
    cr_assert_eq(fscanf(f, "%lu %lu", &size, &pages), 2);
    fclose(f);
    return (size_t)pages * (size_t)sysconf(_SC_PAGESIZE);
}

/* Waits, for up to a minute, until the process holds `grown` bytes more
 * than `before` (a mapper thread at work): a load that takes longer than
 * the mapping. */
static void wait_resident(size_t before, size_t grown)
{
    for (int i = 0; i < 6000 && resident() < before + grown; i++)
        usleep(10000);
    cr_assert_geq(resident(), before + grown, "the room was not mapped within a minute");
}

/* The spare heap_ready makes for a scene file of `bytes`: six times its
 * size (cli/heap.c), mapped before the room. */
static size_t spare_for(off_t bytes) { return 6 * (size_t)bytes; }

/* How much heap_ready for a scene file of `bytes`, by a process of
 * `threads` threads, grows the heap by; with `mapped`, once the mapping
 * of the spare and the room had had time to finish before heap_settle
 * stopped it. */
static size_t room_for_mapped(off_t bytes, int threads, bool mapped)
{
    tmpdir_make("heap");
    char path[256];
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    scene_file(path, bytes);
    size_t before = mallinfo2().arena, held = resident();
    heap_ready(path, threads, 0);
    size_t room = mallinfo2().arena - before;
    if (mapped)
        wait_resident(held, spare_for(bytes) + room - room / 16);
    heap_settle();
    tmpdir_remove();
    return room;
}

static size_t room_for(off_t bytes, int threads)
{
    return room_for_mapped(bytes, threads, false);
}

static long minor_faults(void)
{
    struct rusage u;
    cr_assert_eq(getrusage(RUSAGE_SELF, &u), 0);
    return u.ru_minflt;
}

/* That heap_ready for a scene file of `bytes` grows the heap by at least
 * `mib` MiB and by less than `below` MiB. */
static void expect_room(off_t bytes, size_t mib, size_t below)
{
    size_t room = room_for(bytes, 0);
    cr_assert(room >= mib << 20, "the heap grew by %zu bytes", room);
    cr_assert(room < below << 20, "the heap grew by %zu bytes", room);
}

Test(heap, room_in_proportion_to_the_scene_file)
{
    SKIP_UNLESS_APPLIES();
    expect_room((off_t)8 << 20, 48, 52); /* 48 MiB taken and given back: the heap keeps it */
}

/* However small the scene file, or with none, the heap holds 32 MiB for
 * huge pages (cli/heap.c, HEAP_HUGE_LEAST), starting on one, left to be
 * mapped when first touched: heap_ready maps none of it ahead. */
static void expect_huge_floor(const char *path)
{
    size_t before = mallinfo2().arena, held = resident();
    heap_ready(path, 0, 0);
    heap_settle();
    size_t grown = mallinfo2().arena - before, mapped = resident() - held;
    /* less what was free at the heap's top already, and up to a huge
     * page before it, kept to bring the room to one */
    cr_assert(grown >= (size_t)28 << 20 && grown < (size_t)35 << 20, "the heap grew by %zu bytes",
              grown);
    cr_assert_lt(mapped, (size_t)8 << 20, "%zu bytes mapped ahead", mapped);
}

Test(heap, a_floor_of_huge_page_room_for_the_built_in_scene)
{
    SKIP_UNLESS_APPLIES();
    expect_huge_floor(NULL);
}

Test(heap, a_floor_of_huge_page_room_for_a_small_scene_file)
{
    SKIP_UNLESS_APPLIES();
    tmpdir_make("heap");
    char path[256];
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    scene_file(path, (off_t)100 << 10); /* 600 KiB of room: below the floor */
    expect_huge_floor(path);
    tmpdir_remove();
}

/* Blocks carved from the heap as a loader takes them: 48 bytes each (64
 * with malloc's header), each touched, up to 32 MiB of them. */
enum { CARVE_MAX = (32 << 20) / 64 };
static char *carved[CARVE_MAX];

/* Carves count blocks into carved[]; the page faults that took. */
static long carve(int count)
{
    memset(carved, 0, sizeof carved); /* the array's own pages touched first */
    long before = minor_faults();
    for (int i = 0; i < count; i++) {
        carved[i] = malloc(48);
        cr_assert_not_null(carved[i]);
        carved[i][0] = 1;
    }
    return minor_faults() - before;
}

static void free_carved(int count)
{
    for (int i = 0; i < count; i++)
        free(carved[i]);
}

/* The mapping that holds p, from /proc/self/smaps: whether it is marked
 * for huge pages (VmFlags "hg", madvise MADV_HUGEPAGE) and how many kB
 * of it are in huge pages now. */
static void mapping_of(const void *p, bool *marked, long *huge_kb)
{
    FILE *f = fopen("/proc/self/smaps", "r");
    cr_assert_not_null(f);
    char line[512];
    bool in = false;
    *marked = false;
    *huge_kb = 0;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        long kb;
        if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2)
            in = (uintptr_t)p >= lo && (uintptr_t)p < hi;
        else if (in && sscanf(line, "AnonHugePages: %ld kB", &kb) == 1)
            *huge_kb = kb;
        else if (in && strncmp(line, "VmFlags:", 8) == 0)
            *marked = strstr(line, " hg") != NULL;
    }
    fclose(f);
}

/* The floor's room is marked for huge pages; and where the kernel gave
 * it some, blocks carved from it took a page fault per 2 MiB, not per 4
 * KiB: 8 MiB of small blocks, 2,048 pages of 4 KiB. (Where it gave none,
 * short of huge pages or set never to, only the mark is checked.) */
Test(heap, the_floor_is_mapped_in_huge_pages)
{
    SKIP_UNLESS_APPLIES();
    heap_ready(NULL, 0, 0);
    enum { COUNT = (8 << 20) / 64 };
    long faults = carve(COUNT);
    bool marked;
    long huge_kb;
    mapping_of(carved[COUNT / 2], &marked, &huge_kb);
    free_carved(COUNT);
    cr_assert(marked, "the room's blocks lie in a mapping not marked for huge pages");
    if (huge_kb > 0)
        cr_assert_lt(faults, 200, "%ld page faults carving the room (%ld kB in huge pages)",
                     faults, huge_kb);
}

/* That the room for a scene file of 8 MiB, readied by a process of
 * `threads` threads, is mapped once heap_settle returns after a load that
 * took longer than the mapping. */
static void expect_room_mapped(int threads)
{
    void *probe = mmap(NULL, 4096, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    cr_assert_neq(probe, MAP_FAILED);
    bool can_map = madvise(probe, 4096, MADV_POPULATE_WRITE) == 0;
    munmap(probe, 4096);
    if (!can_map)
        cr_skip_test("the kernel cannot map memory ahead (Linux 5.14 on)");
    cr_assert_geq(room_for_mapped((off_t)8 << 20, threads, true), (size_t)48 << 20);
    /* 32 MiB of small blocks, as a loader takes them: 8,192 pages, but
     * already mapped, so only the odd fault of malloc's own */
    enum { COUNT = (32 << 20) / 64 };
    long faults = carve(COUNT);
    free_carved(COUNT);
    cr_assert_lt(faults, 200, "%ld page faults carving the room", faults);
}

Test(heap, room_is_mapped_on_a_thread_of_its_own)
{
    SKIP_UNLESS_APPLIES();
    expect_room_mapped(0);
}

Test(heap, room_is_mapped_in_place_on_one_thread)
{
    SKIP_UNLESS_APPLIES();
    expect_room_mapped(1);
}

/* count blocks of 48 bytes into blocks, block i written with i's low byte */
static void write_blocks(unsigned char **blocks, int count)
{
    for (int i = 0; i < count; i++) {
        blocks[i] = malloc(48);
        cr_assert_not_null(blocks[i]);
        memset(blocks[i], i & 0xff, 48);
    }
}

/* That every step-th block holds what write_blocks wrote; frees them all. */
static void check_blocks(unsigned char **blocks, int count, int step)
{
    for (int i = 0; i < count; i += step)
        for (int b = 0; b < 48; b++)
            cr_assert_eq(blocks[i][b], i & 0xff, "block %d byte %d", i, b);
    for (int i = 0; i < count; i++)
        free(blocks[i]);
}

/* Blocks taken and written while the room is being mapped on the mapper's
 * thread keep what was written in them. */
Test(heap, blocks_written_while_the_room_is_mapped_keep_their_bytes)
{
    SKIP_UNLESS_APPLIES();
    tmpdir_make("heap");
    char path[256];
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    scene_file(path, (off_t)16 << 20); /* 96 MiB of room, after the spare's 96 */
    enum { COUNT = 1 << 20 };
    static unsigned char *blocks[COUNT];
    memset(blocks, 0, sizeof blocks);
    heap_ready(path, 0, 0);
    write_blocks(blocks, COUNT);
    heap_settle();
    check_blocks(blocks, COUNT, 1);
    tmpdir_remove();
}

/* A load done before the mapper is: heap_settle stops it, and the rest
 * of the room is mapped as it is touched, with what is written kept. */
Test(heap, room_left_unmapped_when_the_load_is_done_first)
{
    SKIP_UNLESS_APPLIES();
    tmpdir_make("heap");
    char path[256];
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    scene_file(path, (off_t)20 << 20); /* 120 MiB of spare, then 120 of room */
    size_t held = resident();
    heap_ready(path, 0, 0);
    heap_settle();
    size_t after = resident();
    enum { COUNT = 1 << 22 }; /* 256 MiB of 48-byte blocks, past the room */
    static unsigned char *blocks[COUNT];
    write_blocks(blocks, COUNT);
    check_blocks(blocks, COUNT, 4099);
    tmpdir_remove();
    cr_assert_lt(after, held + ((size_t)240 << 20),
                 "all of the spare and the room were mapped before it stopped");
}

Test(heap, room_at_its_cap_is_kept)
{
    SKIP_UNLESS_APPLIES();
    expect_room((off_t)50 << 20, 256, 264); /* 50 MB would ask for 300 MiB: 256, all kept */
}

/* heap_ready makes the library's spare from a scene file's size (a
 * second glint_memory_spare then has none to make), and none for a file
 * of unknown size. */
Test(heap, the_spare_is_made_for_a_scene_file)
{
    SKIP_UNLESS_APPLIES();
    tmpdir_make("heap");
    char path[256];
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    scene_file(path, (off_t)1 << 20);
    heap_ready(path, 0, 0);
    heap_settle();
    cr_assert_null(glint_memory_spare((size_t)4 << 20), "heap_ready made no spare");
    tmpdir_remove();
}

/* Without a scene file (the built-in scene), a film's size from -r still
 * gets its spare, left for the film's clearing to map (on the render's
 * threads), and no more room in the heap than the floor. */
Test(heap, the_spare_is_made_for_a_known_film)
{
    SKIP_UNLESS_APPLIES();
    size_t before = mallinfo2().arena, held = resident();
    heap_ready(NULL, 0, (size_t)1920 * 1080 * 12);
    usleep(200000); /* time for a mapper, were there one, to map much of it */
    heap_settle();
    size_t mapped = resident() - held;
    cr_assert_null(glint_memory_spare((size_t)4 << 20), "heap_ready made no spare");
    cr_assert_lt(mallinfo2().arena - before, (size_t)35 << 20, "room for no scene file");
    cr_assert_lt(mapped, (size_t)8 << 20, "%zu bytes of the film's spare mapped ahead", mapped);
}

Test(heap, no_spare_without_a_file_of_known_size)
{
    SKIP_UNLESS_APPLIES();
    heap_ready("-", 0, 0);
    heap_settle();
    cr_assert_not_null(glint_memory_spare((size_t)4 << 20), "a spare for standard input");
}

Test(heap, no_room_without_a_file_of_known_size)
{
    SKIP_UNLESS_APPLIES();
    size_t before = mallinfo2().arena;
    heap_ready("-", 0, 0);
    heap_ready("/nonexistent/scene.yaml", 0, 0);
    heap_ready("/tmp", 0, 0); /* a folder */
    heap_ready(NULL, 0, 0);
    heap_settle();
    /* the floor, and up to a huge page kept before it (cli/heap.c) */
    cr_assert_lt(mallinfo2().arena - before, (size_t)35 << 20, "more than the floor");
}

static void *take_block(void *out)
{
    *(void **)out = malloc((size_t)64 << 10);
    return NULL;
}

/* Whether p lies in the main heap, the process's [heap] mapping (another
 * thread's heap would be a mapping of its own). */
static bool in_main_heap(const void *p)
{
    FILE *f = fopen("/proc/self/maps", "r");
    cr_assert_not_null(f);
    char line[512];
    bool in = false;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        if (strstr(line, "[heap]") && sscanf(line, "%lx-%lx", &lo, &hi) == 2)
            in = in || ((uintptr_t)p >= lo && (uintptr_t)p < hi);
    }
    fclose(f);
    return in;
}

Test(heap, other_threads_take_blocks_from_the_main_heap)
{
    SKIP_UNLESS_APPLIES();
    heap_ready(NULL, 0, 0);
    void *mine = malloc((size_t)64 << 10), *theirs = NULL;
    pthread_t t;
    cr_assert_eq(pthread_create(&t, NULL, take_block, &theirs), 0);
    cr_assert_eq(pthread_join(t, NULL), 0);
    cr_assert_not_null(mine);
    cr_assert_not_null(theirs);
    cr_assert(in_main_heap(mine));
    cr_assert(in_main_heap(theirs), "the thread's block %p is outside the main heap", theirs);
    free(mine);
    free(theirs);
}
