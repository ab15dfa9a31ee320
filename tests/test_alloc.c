/* Running out of memory: every allocation the library makes while loading
 * and building a scene is made to fail in turn, and each time the load
 * must report GLINT_ERR_NOMEM (or succeed, when the failed allocation was
 * one it can do without), crash nowhere and leak nothing.
 *
 * The test binary is linked with --wrap for malloc, calloc, realloc and
 * aligned_alloc (Makefile), so calls from the library's own objects come
 * here; allocations inside shared libraries (libyaml, assimp, the image
 * decoders) are not counted. Leaks are checked by LeakSanitizer in the
 * sanitizer build, once every allocation has failed. */
#include <criterion/criterion.h>
#include <stddef.h>
#include <stdlib.h>

#include "glint.h"

#ifdef __SANITIZE_ADDRESS__
#include <sanitizer/lsan_interface.h>
#endif

void *__real_malloc(size_t n);
void *__real_calloc(size_t k, size_t n);
void *__real_realloc(void *p, size_t n);
void *__real_aligned_alloc(size_t a, size_t n);

static long calls;   /* allocations counted since the last reset */
static long fail_at; /* the call that fails (1-based); 0: none */

static bool fail_now(void) { return ++calls == fail_at; }

void *__wrap_malloc(size_t n) { return fail_now() ? NULL : __real_malloc(n); }
void *__wrap_calloc(size_t k, size_t n) { return fail_now() ? NULL : __real_calloc(k, n); }
void *__wrap_realloc(void *p, size_t n) { return fail_now() ? NULL : __real_realloc(p, n); }
void *__wrap_aligned_alloc(size_t a, size_t n)
{
    return fail_now() ? NULL : __real_aligned_alloc(a, n);
}

static glint_rc load(const char *path)
{
    glint_scene *sc = NULL;
    glint_error err;
    glint_rc rc = glint_scene_load(path, &sc, &err);
    glint_scene_free(sc);
    return rc;
}

static void fail_each_allocation(const char *path)
{
    calls = 0;
    fail_at = 0;
    cr_assert_eq(load(path), GLINT_OK, "%s does not load", path);
    long total = calls;
    cr_assert_gt(total, 10, "allocations are not counted (%ld)", total);
    int nomem = 0;
    for (long k = 1; k <= total; k++) {
        calls = 0;
        fail_at = k;
        glint_rc rc = load(path);
        fail_at = 0;
        cr_assert(rc == GLINT_OK || rc == GLINT_ERR_NOMEM,
                  "%s: allocation %ld of %ld failed: rc %d, not 'out of memory'", path, k,
                  total, (int)rc);
        nomem += rc == GLINT_ERR_NOMEM;
    }
#ifdef __SANITIZE_ADDRESS__
    cr_assert_eq(__lsan_do_recoverable_leak_check(), 0,
                 "%s: a failed allocation leaked (LeakSanitizer's report above)", path);
#endif
    cr_assert_gt(nomem, total / 2, "only %d of %ld failures were reported", nomem, total);
}

Test(alloc, scene_of_shapes_and_textures)
{
    fail_each_allocation(GLINT_SOURCE_DIR "/scenes/shapes.yaml");
}

Test(alloc, csg_trees_and_polyhedra)
{
    fail_each_allocation(GLINT_SOURCE_DIR "/scenes/csg.yaml");
}

Test(alloc, meshes_and_both_hierarchies)
{
    fail_each_allocation(GLINT_SOURCE_DIR "/scenes/bunny.yaml");
}
