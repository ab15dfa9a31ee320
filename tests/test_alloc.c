/* Running out of memory: every allocation the library makes while loading
 * and building a scene, or writing a PNG on two threads, is made to fail
 * in turn, and each time the call must report GLINT_ERR_NOMEM (or
 * succeed, when the failed allocation was one it can do without), crash
 * nowhere and leak nothing; a failed write leaves no file.
 *
 * The test binary is linked with --wrap for malloc, calloc, realloc and
 * aligned_alloc (Makefile), so calls from the library's own objects come
 * here; allocations inside shared libraries (libyaml, assimp, the image
 * decoders) are not counted. Leaks are checked by LeakSanitizer in the
 * sanitizer build, once every allocation has failed. */
#include <criterion/criterion.h>
#include <dirent.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "glint.h"

#ifdef __SANITIZE_ADDRESS__
#include <sanitizer/lsan_interface.h>
#endif

void *__real_malloc(size_t n);
void *__real_calloc(size_t k, size_t n);
void *__real_realloc(void *p, size_t n);
void *__real_aligned_alloc(size_t a, size_t n);

/* Atomic: the PNG writer's threads allocate at the same time. Which of
 * their allocations is the k-th then varies from run to run; each must
 * still fail cleanly. */
static atomic_long calls; /* allocations counted since the last reset */
static long fail_at;      /* the call that fails (1-based); 0: none */

static bool fail_now(void) { return ++calls == fail_at; }

/* The largest block asked for so far, for tests that bound what a call
 * allocates (test_png_read.c sets it to 0 first). */
atomic_size_t alloc_largest;

static void note(size_t n)
{
    size_t was = atomic_load(&alloc_largest);
    while (n > was && !atomic_compare_exchange_weak(&alloc_largest, &was, n)) {
    }
}

void *__wrap_malloc(size_t n)
{
    note(n);
    return fail_now() ? NULL : __real_malloc(n);
}
void *__wrap_calloc(size_t k, size_t n)
{
    note(k && n > SIZE_MAX / k ? SIZE_MAX : k * n);
    return fail_now() ? NULL : __real_calloc(k, n);
}
void *__wrap_realloc(void *p, size_t n)
{
    note(n);
    return fail_now() ? NULL : __real_realloc(p, n);
}
void *__wrap_aligned_alloc(size_t a, size_t n)
{
    note(n);
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

/* The mesh is imported in this process (GLINT_MESH_TRUSTED), so that every
 * allocation of the import is counted here; in the usual child process a
 * failure there is the child's, reported as the importer running out of
 * memory (test_mesh_files.c). */
Test(alloc, meshes_and_both_hierarchies)
{
    setenv("GLINT_MESH_TRUSTED", "1", 1);
    fail_each_allocation(GLINT_SOURCE_DIR "/scenes/bunny.yaml");
}

/* A 1000x700 film as a PNG: 5 strips, compressed on two threads. */
static glint_rc write_png(const char *path, const float *rgb)
{
    glint_film film = {.width = 1000, .height = 700, .rgb = (float *)rgb};
    glint_write_options o = {.threads = 2};
    glint_error err;
    return glint_film_write(&film, path, &o, &err);
}

static int files_in(const char *folder)
{
    DIR *d = opendir(folder);
    cr_assert_not_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

Test(alloc, png_written_on_two_threads)
{
    char folder[] = "/tmp/glint-test-alloc-XXXXXX", path[64];
    cr_assert_not_null(mkdtemp(folder));
    snprintf(path, sizeof path, "%s/out.png", folder);
    size_t n = 1000 * 700 * 3;
    float *rgb = malloc(n * sizeof *rgb);
    cr_assert_not_null(rgb);
    for (size_t i = 0; i < n; i++)
        rgb[i] = (float)(i * 7919 % 1013) / 1013.0f;
    calls = 0;
    fail_at = 0;
    cr_assert_eq(write_png(path, rgb), GLINT_OK);
    long total = calls;
    cr_assert_gt(total, 10, "allocations are not counted (%ld)", total);
    int nomem = 0;
    for (long k = 1; k <= total; k++) {
        unlink(path);
        calls = 0;
        fail_at = k;
        glint_rc rc = write_png(path, rgb);
        fail_at = 0;
        cr_assert(rc == GLINT_OK || rc == GLINT_ERR_NOMEM, "allocation %ld of %ld failed: rc %d",
                  k, total, (int)rc);
        cr_assert_eq(files_in(folder), rc == GLINT_OK, "allocation %ld: %d files", k,
                     files_in(folder));
        nomem += rc == GLINT_ERR_NOMEM;
    }
    unlink(path);
    rmdir(folder);
    free(rgb);
#ifdef __SANITIZE_ADDRESS__
    cr_assert_eq(__lsan_do_recoverable_leak_check(), 0,
                 "a failed allocation leaked (LeakSanitizer's report above)");
#endif
    cr_assert_gt(nomem, total / 2, "only %d of %ld failures were reported", nomem, total);
}
