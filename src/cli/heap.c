#include "heap.h"

#include <pthread.h>
#include <stdatomic.h>
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

#include "glint.h"

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
 * loaded, 12 of it the parse tree, which now lies in the spare), at most
 * HEAP_ROOM_MAX. */
#define HEAP_ROOM_PER_BYTE 6
#define HEAP_ROOM_MAX ((size_t)256 << 20)
/* The library's spare block (glint_memory_spare), for the parse tree and
 * then the film: this many times the scene file's bytes, at most
 * HEAP_ROOM_MAX. */
#define HEAP_SPARE_PER_BYTE 6
/* However small the scene file (the built-in scene has none), this much
 * of the main heap is marked for huge pages, though only the room is
 * mapped ahead: the rest is mapped a huge page at a time where it is
 * first touched. The built-in scene at 1920x1080 takes some 12 MiB of
 * heap (its textures, the PNG writer's rows, compressors and streams),
 * which otherwise came in 4 KiB pages: some 650 page faults, 230 of them
 * on the second thread of a two-thread run. */
#define HEAP_HUGE_LEAST ((size_t)32 << 20)
/* The room is taken in pieces of this size (below HEAP_MMAP_FROM). */
#define HEAP_PIECE ((size_t)16 << 20)
/* The mapper maps this much at a time (a huge page), and stops between
 * two when the load is done (heap_settle). */
#define HEAP_STEP ((uintptr_t)2 << 20)
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
enum { ROOM_PIECES = (int)(HEAP_ROOM_MAX / HEAP_PIECE) + 3 };

/* The room's pages still to be mapped, piece by piece, and the thread
 * mapping them while the scene loads. */
static struct {
    char *at[ROOM_PIECES];
    size_t bytes[ROOM_PIECES];
    int n;
    pthread_t mapper;
    bool mapping; /* the mapper runs and nobody has joined it yet */
    atomic_bool stop; /* the load is done: map no more */
    pthread_mutex_t lock; /* over mapper and mapping */
} room = {.lock = PTHREAD_MUTEX_INITIALIZER};

/* The block before the first room's first huge page, kept (map_room;
 * made once a process). */
static void *first_gap;

static void *map_pieces(void *unused)
{
    (void)unused;
    for (int k = 0; k < room.n; k++) {
        char *at = room.at[k], *end = at + room.bytes[k];
        while (at < end && !atomic_load_explicit(&room.stop, memory_order_relaxed)) {
            char *next = (char *)(((uintptr_t)at + HEAP_STEP) & ~(HEAP_STEP - 1));
            next = next < end ? next : end;
            madvise(at, (size_t)(next - at), MADV_POPULATE_WRITE); /* Linux 5.14 on */
            at = next;
        }
    }
    return NULL;
}

/* Takes n bytes, and at least `huge`, from the heap in pieces and gives
 * them back: the heap keeps them. Taken in pieces below HEAP_MMAP_FROM,
 * which would otherwise each be a mapping of their own and gone again when
 * freed; side by side at the top of the heap, they join again into one free
 * block. Each piece is marked for huge pages from its first whole 4 KiB
 * page to its last (the kernel puts whole huge pages where they fit, small
 * ones at the ends; the first piece from its first huge page), and the
 * first n bytes' pages are then mapped, after the spare's spare_bytes and
 * before film_bytes at film (the film's share of the spare beyond the
 * tree's): on a thread of their own beside the load (one thread more than
 * -t asks for, for that long) unless the process may use only one CPU (-t
 * 1, or one in its affinity mask), so that the loader, which carves the
 * room from its low end up, meanwhile parses (the mapper, also working
 * upwards, keeps ahead of it: a page the loader reaches first it maps
 * itself, once). The mapper stops once the load is done (heap_settle):
 * where mapping runs slower than the load (on a virtual machine whose host
 * has taken its memory back, 1-2 ms a MiB), the rest of the room is left to
 * be mapped if and when it is touched, instead of the render waiting for
 * all of it. */
static void map_room(size_t n, size_t huge, char *spare, size_t spare_bytes, char *film,
                     size_t film_bytes, int threads)
{
    const uintptr_t page = 4096;
    char *piece[ROOM_PIECES];
    int k = 0;
    room.n = 0;
    if (spare) { /* first: the parse tree there is written from the load's start */
        room.at[room.n] = spare;
        room.bytes[room.n++] = spare_bytes;
    }
    size_t whole = huge > n ? huge : n, map = n; /* marked; of it, mapped ahead */
    size_t gap = 0; /* from the room's start to its first huge page */
    uintptr_t start = 0; /* the room's first block, before it is freed */
    for (size_t left = whole; left > 0 && k < ROOM_PIECES - 1; k++) {
        size_t take = left < HEAP_PIECE ? left : HEAP_PIECE;
        if (!(piece[k] = malloc(take)))
            break;
        left -= take;
        if (k == 0) {
            start = (uintptr_t)piece[0];
            gap = ((start + HEAP_STEP - 1) & ~(HEAP_STEP - 1)) - start;
        }
        uintptr_t a = ((uintptr_t)piece[k] + (k ? page - 1 : gap)) & ~(page - 1);
        uintptr_t e = ((uintptr_t)piece[k] + take) & ~(page - 1);
        if (e > a) {
            madvise((void *)a, e - a, MADV_HUGEPAGE);
            size_t ahead = map < e - a ? map : e - a;
            map -= ahead;
            if (ahead) {
                room.at[room.n] = (char *)a;
                room.bytes[room.n++] = ahead;
            }
        }
    }
    if (film && film_bytes) { /* last: what the load leaves the film's clearing */
        room.at[room.n] = film;
        room.bytes[room.n++] = film_bytes;
    }
    while (k-- > 0)
        free(piece[k]);
    /* The room's first bytes, up to its first huge page's boundary, would
     * come in 4 KiB pages, and they are the first that blocks are carved
     * from. A block over them is taken and kept, never written past its
     * header (a chunk of malloc(gap - 16) is gap bytes), so that the
     * blocks that follow start on a huge page. */
    if (!first_gap && gap >= page && (uintptr_t)(first_gap = malloc(gap - 16)) != start)
        free(first_gap), first_gap = NULL; /* served from elsewhere: no use */
    if (room.n == 0)
        return;
    int cpus = threads > 0 ? threads : glint_default_threads();
    pthread_mutex_lock(&room.lock);
    atomic_store_explicit(&room.stop, false, memory_order_relaxed);
    bool started = cpus > 1 && pthread_create(&room.mapper, NULL, map_pieces, NULL) == 0;
    room.mapping = started;
    pthread_mutex_unlock(&room.lock);
    if (!started)
        map_pieces(NULL);
}
#endif

void heap_settle(void)
{
#if defined(HEAP_POLICY)
    pthread_mutex_lock(&room.lock); /* a second caller waits for the first's join */
    atomic_store_explicit(&room.stop, true, memory_order_relaxed);
    if (room.mapping)
        pthread_join(room.mapper, NULL);
    room.mapping = false;
    pthread_mutex_unlock(&room.lock);
#endif
}

#if defined(HEAP_POLICY)
/* per times n, at most HEAP_ROOM_MAX */
static size_t capped(size_t n, size_t per)
{
    return n > HEAP_ROOM_MAX / per ? HEAP_ROOM_MAX : n * per;
}
#endif

void heap_ready(const char *path, int threads, size_t film_bytes)
{
#if defined(HEAP_POLICY)
    heap_settle(); /* a room still being mapped stays as it is */
    mallopt(M_MMAP_THRESHOLD, (int)HEAP_MMAP_FROM);
    mallopt(M_TRIM_THRESHOLD, (int)HEAP_TRIM_FROM);
    mallopt(M_ARENA_MAX, 1);
    struct stat st;
    size_t bytes = 0; /* the scene file's, where it has a size */
    if (path && strcmp(path, "-") != 0 && stat(path, &st) == 0 && S_ISREG(st.st_mode))
        bytes = (size_t)st.st_size;
    const size_t least = (size_t)4 << 20;
    size_t room_bytes = capped(bytes, HEAP_ROOM_PER_BYTE);
    room_bytes = room_bytes < least ? 0 : room_bytes;
    /* the spare holds the parse tree, then the film: whichever is bigger.
     * The tree's share is mapped while the scene loads, then the room, then
     * the film's share beyond the tree's, as far as the load leaves time.
     * Without a tree (a small file, or the built-in scene) the film's share
     * is mapped by the film's clearing, on the render's threads (mapped
     * here, beside a load of a few ms, it held the kernel's lock on the
     * process's mappings for 0.1-4 ms a huge page while the loader's
     * threads started and its blocks were marked: on two threads the
     * built-in scene's load took 5.4 ms against 3.6 on one). The spare
     * stays where it is during the load (the tree is sized from the same
     * file's length; should the file have grown since, a spare moved to
     * grow has its old range mapped for nothing: mapping ahead never
     * writes) */
    size_t tree_bytes = capped(bytes, HEAP_SPARE_PER_BYTE);
    size_t spare_bytes = tree_bytes > film_bytes ? tree_bytes : capped(film_bytes, 1);
    char *spare = spare_bytes >= least ? glint_memory_spare(spare_bytes) : NULL;
    bool tree = spare && tree_bytes >= least;
    map_room(room_bytes, HEAP_HUGE_LEAST, tree ? spare : NULL, tree_bytes,
             tree && spare_bytes > tree_bytes ? spare + tree_bytes : NULL, spare_bytes - tree_bytes,
             threads);
#else
    (void)path, (void)threads, (void)film_bytes;
#endif
}
