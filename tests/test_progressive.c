/* Progressive rendering (include/glint.h, src/render/progressive.h): passes
 * of 1, then more, then all samples per pixel, even with passes cancelled
 * part way, resolve to the byte-identical film glint_render makes. */
#include <criterion/criterion.h>
#include <stdatomic.h>
#include <string.h>

#include "film.h"
#include "glint.h"

static glint_error err;
#define OK(call) cr_assert_eq((call), GLINT_OK, "%s: %s", #call, err.msg)

typedef struct stopper {
    atomic_int left;
    atomic_int tiles;
} stopper;

static void count_tile(void *u, const glint_film *f, int x0, int y0, int x1, int y1)
{
    (void)f, (void)x0, (void)y0, (void)x1, (void)y1;
    stopper *sp = u;
    atomic_fetch_sub(&sp->left, 1);
    atomic_fetch_add(&sp->tiles, 1);
}

static int stop_now(void *u) { return atomic_load(&((stopper *)u)->left) <= 0; }

/* Renders in passes up to each of `passes`, cancelling the pass numbered
 * `cut` after a few tiles and running it again; compares with the batch. */
static void passes_match_batch(int samples, const int *passes, int npasses, int cut, int threads)
{
    glint_scene *s;
    OK(glint_scene_builtin(&s, &err));
    glint_settings st;
    OK(glint_scene_settings(s, &st, &err));
    st.width = 72;
    st.height = 50;
    st.samples = samples;
    st.threads = threads;
    glint_film batch = test_render(s, st.width, st.height, samples, 1);
    glint_accum a;
    OK(glint_accum_alloc(&a, st.width, st.height, &err));
    glint_film film;
    OK(glint_film_alloc(&film, st.width, st.height, &err));
    int tiles;
    OK(glint_tile_count(&st, &tiles, &err));
    for (int i = 0; i < npasses; i++) {
        if (i == cut) {
            stopper sp = {5, 0};
            glint_callbacks cb = {&sp, count_tile, NULL, stop_now};
            cr_assert_eq(glint_render_pass(s, &st, passes[i], &cb, &a, NULL, &err),
                         GLINT_ERR_CANCELLED);
            int done = 0;
            for (int t = 0; t < tiles; t++)
                done += a.tile_samples[t] == passes[i];
            cr_expect_eq(done, atomic_load(&sp.tiles), "tiles brought up = tiles reported");
        }
        glint_stats stats;
        OK(glint_render_pass(s, &st, passes[i], NULL, &a, &stats, &err));
        int least;
        OK(glint_accum_resolve(&a, NULL, &film, &least, &err));
        cr_expect_eq(least, passes[i]);
    }
    size_t n = (size_t)st.width * (size_t)st.height * 3 * sizeof(float);
    cr_expect_eq(memcmp(film.rgb, batch.rgb, n), 0, "%d samples in %d passes differ from batch",
                 samples, npasses);
    glint_film_free(&film);
    glint_film_free(&batch);
    glint_accum_free(&a);
    glint_scene_free(s);
}

Test(progressive, passes_converge_to_the_batch_image)
{
    passes_match_batch(4, (int[]){1, 4}, 2, -1, 2);
    passes_match_batch(9, (int[]){1, 2, 5, 9}, 4, 2, 1);
    passes_match_batch(16, (int[]){1, 16}, 2, 0, 2);
    passes_match_batch(1, (int[]){1}, 1, 0, 1);
}

/* The adaptive sampler's passes: each pixel's centre first, then the whole
 * adaptive tile; a pass cancelled part way and run again changes nothing.
 * The resolved film is the batch film to the bit, and the first pass is
 * not (it is one sample a pixel where the batch image refines edges). */
Test(progressive, adaptive_passes_end_at_the_batch_image)
{
    glint_scene *s;
    OK(glint_scene_builtin(&s, &err));
    glint_settings st;
    OK(glint_scene_settings(s, &st, &err));
    st.width = 64;
    st.height = 48;
    st.samples = 4;
    st.threads = 2;
    st.sampler = GLINT_SAMPLER_ADAPTIVE;
    st.threshold = 0.05;
    st.adaptive_depth = 2;
    glint_film batch = {0};
    OK(glint_render(s, &st, NULL, &batch, NULL, &err));
    glint_accum a;
    OK(glint_accum_alloc(&a, st.width, st.height, &err));
    glint_film film;
    OK(glint_film_alloc(&film, st.width, st.height, &err));
    size_t n = (size_t)st.width * (size_t)st.height * 3 * sizeof(float);
    int least;
    OK(glint_render_pass(s, &st, 1, NULL, &a, NULL, &err));
    OK(glint_accum_resolve(&a, NULL, &film, &least, &err));
    cr_expect_eq(least, 1);
    cr_expect_neq(memcmp(film.rgb, batch.rgb, n), 0, "the centres alone are the batch image");
    stopper sp = {3, 0};
    glint_callbacks cb = {&sp, count_tile, NULL, stop_now};
    cr_assert_eq(glint_render_pass(s, &st, st.samples, &cb, &a, NULL, &err), GLINT_ERR_CANCELLED);
    OK(glint_render_pass(s, &st, st.samples, NULL, &a, NULL, &err));
    OK(glint_accum_resolve(&a, NULL, &film, &least, &err));
    cr_expect_eq(least, st.samples);
    cr_expect_eq(memcmp(film.rgb, batch.rgb, n), 0, "adaptive passes differ from the batch image");
    glint_film_free(&film);
    glint_film_free(&batch);
    glint_accum_free(&a);
    glint_scene_free(s);
}

Test(progressive, first_pass_is_one_sample_and_refusals)
{
    glint_scene *s;
    OK(glint_scene_builtin(&s, &err));
    glint_settings st;
    OK(glint_scene_settings(s, &st, &err));
    st.width = 40;
    st.height = 30;
    st.samples = 4;
    glint_accum a;
    OK(glint_accum_alloc(&a, 40, 30, &err));
    glint_stats stats;
    OK(glint_render_pass(s, &st, 1, NULL, &a, &stats, &err));
    cr_expect_eq(stats.primary_rays, 40 * 30, "one sample per pixel");
    OK(glint_render_pass(s, &st, 1, NULL, &a, &stats, &err));
    cr_expect_eq(stats.primary_rays, 0, "nothing left to trace");
    OK(glint_render_pass(s, &st, 4, NULL, &a, &stats, &err));
    cr_expect_eq(stats.primary_rays, 40 * 30 * 3, "the three samples each pixel lacked");
    cr_expect_eq(glint_render_pass(s, &st, 5, NULL, &a, NULL, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, "upto must be 1 to 4"), "%s", err.msg);
    st.width = 41;
    cr_expect_eq(glint_render_pass(s, &st, 1, NULL, &a, NULL, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, "40x30"), "%s", err.msg);
    glint_accum_clear(&a);
    cr_expect_eq(a.tile_samples[0], 0);
    glint_accum_free(&a);
    cr_expect_eq(glint_render_pass(s, NULL, 1, NULL, &a, NULL, &err), GLINT_ERR_INPUT);
    glint_scene_free(s);
}
