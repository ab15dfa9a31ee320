/* spare: one block of mapped pages that the process keeps between two
 * big arrays that do not live at once, so that the second takes the
 * first's pages instead of fresh ones. A scene's parse tree (load/yaml_doc.c)
 * lives only while the scene loads, and the film made next is the
 * biggest block of a render: on a virtual machine whose host takes freed
 * memory back, the first touch of a fresh page waits for the host (1.5-2.4
 * ms a MiB measured here; bench/README.md, seventh round), and a 1080p
 * film is 25 MiB.
 *
 * There is a spare only once a program makes one (spare_make: the
 * programs' heap policy, cli/heap.h, sized from the scene file); without
 * one spare_take returns NULL and its callers allocate as they always did.
 * A block taken is the spare's pages, in whole huge pages aligned to one,
 * and is handed back with spare_give, after which it is the spare again.
 * There is one block at most, kept until the process ends. Thread-safe. */
#ifndef GLINT_CORE_SPARE_H
#define GLINT_CORE_SPARE_H

#include <stdbool.h>
#include <stddef.h>

/* Makes the spare: n bytes (rounded up to whole huge pages) mapped in
 * transparent huge pages where the kernel offers them, not yet touched
 * (the caller may map them ahead: spare_make returns the block; NULL when
 * it cannot be made or there is one already, kept or taken). The process
 * keeps it until it ends. */
void *spare_make(size_t n);

/* The spare, grown to at least n bytes (its pages kept, moved if need
 * be), now the caller's; *had (when not NULL) the bytes it held before
 * growing, which may hold anything: the rest are fresh, zero. NULL when
 * there is no spare or it cannot grow. */
void *spare_take(size_t n, size_t *had);

/* n zeroed bytes: from 1 MiB up the spare, cleared by up to `threads`
 * threads (as array_calloc_big_on clears), when there is one; else
 * array_calloc_big_on(n, threads). A spare never taken before is only
 * mapped, the kernel's zeros (spare_make's caller maps, never writes);
 * one taken before is cleared as far as it then held (spare_size), the
 * rest mapped. Free with spare_free. */
void *spare_calloc(size_t n, int threads);

/* Hands back a block spare_take gave: it becomes the spare again. False,
 * doing nothing, for any other pointer (NULL included). */
bool spare_give(void *p);

/* spare_give, or free() for a block that did not come from the spare. */
void spare_free(void *p);

/* The bytes a block from spare_take holds (0 for any other pointer). */
size_t spare_size(const void *p);

#endif
