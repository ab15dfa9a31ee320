/* cpus: what "one thread per core" means (the CPUs the process may run
 * on), and that the thread count a scene is loaded with bounds every
 * thread the load starts: texture decoding and the trees' builds. */
#define _GNU_SOURCE
#include <criterion/criterion.h>
#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "core/cpus.h"
#include "glint.h"
#include "tmpdir.h"

Test(cpus, one_per_core_follows_the_affinity_mask)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    cr_assert_eq(sched_getaffinity(0, sizeof set, &set), 0);
    int n = CPU_COUNT(&set);
    cr_expect_eq(cpus_available(), n);
    cr_expect_eq(glint_default_threads(), n < 1024 ? n : 1024);
    int first = 0;
    while (!CPU_ISSET(first, &set))
        first++;
    cpu_set_t one; /* this test's process alone is narrowed */
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    cr_assert_eq(sched_setaffinity(0, sizeof one, &one), 0);
    cr_expect_eq(cpus_available(), 1);
    cr_expect_eq(glint_default_threads(), 1);
    cr_expect_eq(cpus_threads(0, 16), 1);
    cr_expect_eq(cpus_threads(5, 16), 5);
    cr_expect_eq(cpus_threads(40, 16), 16);
}

/* A binary PLY grid of 2 * side * side triangles. */
static void write_grid(const char *path, int side)
{
    FILE *f = fopen(path, "wb");
    cr_assert_not_null(f);
    int nv = (side + 1) * (side + 1);
    fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
               "property float x\nproperty float y\nproperty float z\n"
               "element face %d\nproperty list uchar int vertex_indices\nend_header\n",
            nv, 2 * side * side);
    for (int j = 0; j <= side; j++)
        for (int i = 0; i <= side; i++) {
            float v[3] = {(float)i / (float)side, (float)j / (float)side,
                          0.1f * (float)((i * 7 + j * 3) % 5) / (float)side};
            fwrite(v, sizeof v, 1, f);
        }
    for (int j = 0; j < side; j++)
        for (int i = 0; i < side; i++) {
            int a = j * (side + 1) + i, b = a + 1, c = a + side + 1, d = c + 1;
            int tri[2][3] = {{a, b, d}, {a, d, c}};
            for (int t = 0; t < 2; t++) {
                unsigned char three = 3;
                fwrite(&three, 1, 1, f);
                fwrite(tri[t], sizeof tri[t], 1, f);
            }
        }
    cr_assert_eq(fclose(f), 0);
}

static atomic_int most;
static atomic_bool stop;

/* The process's threads now (field 20 of /proc/self/stat). With system
 * calls alone, no allocation: the load forks its mesh importer while this
 * runs, and a child forked while another thread holds AddressSanitizer's
 * allocator lock can wait on it for ever. */
static int threads_now(void)
{
    int fd = open("/proc/self/stat", O_RDONLY);
    if (fd < 0)
        return 0;
    char buf[1024];
    ssize_t n = read(fd, buf, sizeof buf - 1);
    close(fd);
    buf[n > 0 ? n : 0] = '\0';
    char *p = strrchr(buf, ')'); /* the command name may hold spaces */
    int field = 2, count = 0;
    for (; p && *p; p++)
        if (*p == ' ' && ++field == 20)
            count = atoi(p + 1);
    return count;
}

static void *watch(void *arg)
{
    (void)arg;
    while (!atomic_load(&stop)) {
        int n = threads_now();
        if (n > atomic_load(&most))
            atomic_store(&most, n);
    }
    return NULL;
}

/* The most threads seen at once while path loads with `threads`, beyond
 * those there before. */
static int extra_threads_loading(const char *path, int threads)
{
    atomic_store(&most, 0);
    atomic_store(&stop, false);
    pthread_t w;
    cr_assert_eq(pthread_create(&w, NULL, watch, NULL), 0);
    while (atomic_load(&most) == 0)
        sched_yield();
    int before = atomic_load(&most);
    glint_load_options o = {threads};
    glint_scene *s = NULL;
    glint_error err = {0};
    glint_rc rc = glint_scene_load_with(path, &o, &s, &err);
    atomic_store(&stop, true);
    pthread_join(w, NULL);
    cr_assert_eq(rc, GLINT_OK, "%s", err.msg);
    glint_scene_free(s);
    return atomic_load(&most) - before;
}

Test(cpus, a_load_runs_on_the_threads_it_is_given)
{
    tmpdir_make("cpus");
    char mesh[128], path[128];
    snprintf(mesh, sizeof mesh, "%s/grid.ply", dir);
    write_grid(mesh, 300); /* 180,000 triangles: the tree's top is built on threads */
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f);
    fprintf(f,
            "textures:\n"
            "  globe: {type: image, file: %s/scenes/textures/globe.png}\n"
            "  flag: {type: image, file: %s/scenes/textures/flag.png}\n"
            "materials:\n"
            "  a: {texture: globe}\n"
            "  b: {texture: flag}\n"
            "objects:\n"
            "  - {type: mesh, file: grid.ply, material: a}\n"
            "  - {type: sphere, center: [0, 0, -3], radius: 1, material: b}\n",
            GLINT_SOURCE_DIR, GLINT_SOURCE_DIR);
    cr_assert_eq(fclose(f), 0);
    int alone = extra_threads_loading(path, 1), two = extra_threads_loading(path, 2);
    tmpdir_remove();
    cr_expect_eq(alone, 0, "a load on one thread started %d more", alone);
    cr_expect_geq(two, 1, "a load on two threads started none"); /* the watch sees them */

    glint_load_options bad = {1025};
    glint_scene *s = NULL;
    glint_error err = {0};
    cr_expect_eq(glint_scene_builtin_with(&bad, &s, &err), GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, "glint_scene_builtin_with: threads must be 0 to 1024 (got 1025)");
    cr_expect_null(s);
    cr_assert_eq(glint_scene_new(&s, &err), GLINT_OK);
    cr_expect_eq(glint_scene_set_threads(s, -1, &err), GLINT_ERR_INPUT);
    cr_expect_eq(glint_scene_set_threads(s, 3, &err), GLINT_OK);
    glint_scene_free(s);
}

/* cpus_share: fn runs n times at once, once on the calling thread; each
 * waits until all n have started, which only threads running together can
 * do (n past the handles kept on the stack too). */
typedef struct share_count {
    atomic_int started, on_caller, gave_up;
    int n;
    pthread_t caller;
} share_count;

static void *share_fn(void *arg)
{
    share_count *c = arg;
    atomic_fetch_add(&c->started, 1);
    if (pthread_equal(pthread_self(), c->caller))
        atomic_fetch_add(&c->on_caller, 1);
    for (long spins = 0; atomic_load(&c->started) < c->n; spins++) {
        if (spins > 20000000L) { /* seconds: some never started */
            atomic_fetch_add(&c->gave_up, 1);
            break;
        }
        sched_yield();
    }
    return NULL;
}

Test(cpus, share_runs_the_work_on_that_many_threads_at_once)
{
    static const int ns[] = {1, 2, 5, 40};
    for (size_t i = 0; i < sizeof ns / sizeof *ns; i++) {
        share_count c = {.n = ns[i], .caller = pthread_self()};
        cpus_share(ns[i], share_fn, &c);
        cr_assert_eq(atomic_load(&c.started), ns[i]);
        cr_assert_eq(atomic_load(&c.on_caller), 1);
        cr_assert_eq(atomic_load(&c.gave_up), 0);
    }
    share_count c = {.n = 1, .caller = pthread_self()};
    cpus_share(0, share_fn, &c); /* fewer than one: once, here */
    cr_assert_eq(atomic_load(&c.started), 1);
}
