/* heap: the programs' use of the C library's heap (glibc malloc). A
 * process's blocks are mapped by the kernel one 4 KiB page at a time, on
 * first touch; on a virtual machine that traps each such touch this costs
 * about 10-15 us a page (bench/README.md, "What limits the rows that
 * miss"), which made the page faults of loading a scene of 11,000 objects
 * (some 3,000) cost more than half of its load. So, once, on the main
 * thread, before the first scene is loaded:
 *
 * - blocks up to 32 MiB come from the heap, and the main heap is trimmed
 *   only when more than HEAP_TRIM_FROM of it is free at its top: a block
 *   freed (a YAML tree, an image writer's buffers, a frame's film in a
 *   sequence) is reused on pages already mapped, where by default every
 *   block from 128 KiB up was a mapping of its own, fresh each time;
 * - every thread allocates from that one heap: by default each thread
 *   that allocates gets a heap of its own, on fresh pages (the PNG
 *   writer's second thread took some 550 page faults for a 1080p image
 *   there, about 5 ms of a 20 ms write);
 * - the library keeps a spare block six times the scene file's size, or
 *   the film's when -r gives it and it is bigger (glint_memory_spare),
 *   where the scene's parse tree is built and which the film takes after
 *   it, on the pages the load touched; and room in
 *   the main heap, six times the file's size, for the scene itself. Both,
 *   at most 256 MiB each, are mapped (in huge pages where the kernel
 *   offers them) on a thread of its own while the scene loads: the
 *   loader's blocks then land on mapped pages. Where the spare holds a
 *   tree (a scene file of some 700 KB or more, whose load takes long
 *   enough), the film's share of it beyond the tree's is mapped last, as
 *   far as the load leaves time (row 8 of bench/README.md: the film's
 *   clearing, on the render's threads, mapped 13 MiB of fresh pages);
 *   else it is left to that clearing;
 * - however small the scene file, or with none (the built-in scene), 32
 *   MiB of that room (less what lies before its first huge page, which
 *   a block kept untouched takes) is marked for huge pages, though only
 *   the file's share is mapped ahead: the rest
 *   is mapped 2 MiB at a time where it is first touched (the built-in
 *   scene at 1920x1080 on two threads took some 900 page faults, 160
 *   since).
 *
 * The process then keeps that memory until it ends. A process policy,
 * not the library's: it lives with the programs (glint, glint-mpi), and
 * an embedder keeps its own. */
#ifndef GLINT_CLI_HEAP_H
#define GLINT_CLI_HEAP_H

#include <stdbool.h>
#include <stddef.h>

/* Readies the heap for loading the scene at path (NULL: the built-in
 * scene; "-": standard input, whose size is not known), by a process that
 * may run `threads` threads (0: one a CPU; where that is one the room is
 * mapped before this returns, else by one more thread meanwhile), and then
 * rendering a film of film_bytes (0: not known yet; from -r), for which
 * the spare is made big enough. Call
 * once, from the main thread, before other threads start. Advice only:
 * nothing fails. */
void heap_ready(const char *path, int threads, size_t film_bytes);

/* Stops the mapping of the room heap_ready maps and waits for its thread
 * (within one huge page's mapping); pages it had not reached yet are
 * mapped when first touched. Call it once the scene is loaded, so that the
 * render's threads have the CPUs to themselves. From any thread, any
 * number of times: each returns once the mapping has stopped. */
void heap_settle(void);

/* Whether heap_ready does anything in this build: glibc's malloc, and no
 * AddressSanitizer (whose allocator replaces it). */
bool heap_policy_applies(void);

#endif
