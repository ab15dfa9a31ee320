/* Whole renders of the built-in scene: a golden image with a stated
 * tolerance, bit-identical output run to run and for any thread count, and
 * the settings checks. Set GLINT_UPDATE_GOLDEN=1 to rewrite the reference
 * (then look at it before committing). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "glint.h"
#include "io/image.h"
#include "film.h"

#define GOLDEN GLINT_SOURCE_DIR "/tests/golden/builtin-100.png"

/* Tolerance against the reference, in 8-bit levels: the mean absolute error
 * over all channels, and the largest single error. Differences come only
 * from compilers and optimisation levels rounding floats differently. */
#define GOLDEN_MEAN_TOLERANCE 0.5
#define GOLDEN_MAX_TOLERANCE 32

static glint_scene *builtin(void)
{
    glint_scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(glint_scene_builtin(&s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

Test(render, builtin_matches_golden_image)
{
    glint_scene *s = builtin();
    glint_film film = test_render(s, 100, 100, 4, 0);
    size_t n = 100 * 100 * 3;
    uint8_t *px = malloc(n);
    image_quantize(film.rgb, n, GLINT_TRANSFER_NONE, px);
    if (getenv("GLINT_UPDATE_GOLDEN")) {
        glint_error err = {0};
        cr_assert_eq(glint_film_write(&film, GOLDEN, NULL, &err), GLINT_OK, "%s", err.msg);
    }
    image ref;
    glint_error err = {0};
    cr_assert_eq(image_load(GOLDEN, &ref, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(ref.width, 100);
    cr_assert_eq(ref.height, 100);
    double sum = 0.0;
    int worst = 0;
    for (size_t i = 0; i < n; i++) {
        int d = abs((int)px[i] - (int)ref.rgb[i]);
        sum += d;
        if (d > worst)
            worst = d;
    }
    double mean = sum / (double)n;
    cr_expect_leq(mean, GOLDEN_MEAN_TOLERANCE, "mean error %.3f levels", mean);
    cr_expect_leq(worst, GOLDEN_MAX_TOLERANCE, "max error %d levels", worst);
    image_free(&ref);
    free(px);
    glint_film_free(&film);
    glint_scene_free(s);
}

Test(render, builtin_is_not_blank)
{
    /* Guards the golden test against a reference that is itself broken:
     * the scene has bright, dark and coloured areas. */
    glint_scene *s = builtin();
    glint_film film = test_render(s, 64, 64, 1, 0);
    float lo = INFINITY, hi = -INFINITY, chroma = 0.0f;
    for (int i = 0; i < 64 * 64; i++) {
        const float *p = film.rgb + i * 3;
        float mx = fmaxf(p[0], fmaxf(p[1], p[2])), mn = fminf(p[0], fminf(p[1], p[2]));
        lo = fminf(lo, mn);
        hi = fmaxf(hi, mx);
        chroma = fmaxf(chroma, mx - mn);
    }
    cr_expect_eq(lo, 0.0f, "the background is black");
    cr_expect_gt(hi, 0.9f);
    cr_expect_gt(chroma, 0.5f);
    glint_film_free(&film);
    glint_scene_free(s);
}

Test(render, same_render_is_bit_identical)
{
    glint_scene *s = builtin();
    glint_film a = test_render(s, 120, 80, 4, 0);
    glint_film b = test_render(s, 120, 80, 4, 0);
    cr_assert_eq(memcmp(a.rgb, b.rgb, sizeof(float) * 120 * 80 * 3), 0);
    glint_film_free(&a);
    glint_film_free(&b);
    glint_scene_free(s);
}

Test(render, thread_count_does_not_change_pixels)
{
    glint_scene *s = builtin();
    glint_film ref = test_render(s, 97, 61, 4, 1);
    int counts[] = {2, 3, 8};
    for (size_t i = 0; i < sizeof counts / sizeof *counts; i++) {
        glint_film f = test_render(s, 97, 61, 4, counts[i]);
        cr_expect_eq(memcmp(ref.rgb, f.rgb, sizeof(float) * 97 * 61 * 3), 0, "%d threads",
                     counts[i]);
        glint_film_free(&f);
    }
    glint_film_free(&ref);
    glint_scene_free(s);
}

Test(render, one_sample_grid_hits_pixel_centres_and_2x2_the_quarter_points)
{
    /* The 2x2 grid samples each pixel at its quarter points, which are the
     * centres of the pixels of an image twice the size: so a 2x2 render
     * equals a 1-sample render at double size, box-filtered. */
    glint_scene *s = builtin();
    glint_film big = test_render(s, 64, 64, 1, 0);
    glint_film aa = test_render(s, 32, 32, 4, 0);
    double sum_d = 0.0;
    int off = 0;
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++)
            for (int c = 0; c < 3; c++) {
                float sum = 0.0f;
                for (int dy = 0; dy < 2; dy++)
                    for (int dx = 0; dx < 2; dx++)
                        sum += big.rgb[((2 * y + dy) * 64 + 2 * x + dx) * 3 + c];
                double d = fabs(sum / 4.0 - aa.rgb[(y * 32 + x) * 3 + c]);
                sum_d += d;
                off += d > 1e-3;
            }
    /* The two grids meet the same points up to float rounding of the
     * camera's pixel steps, which can flip a ray that grazes an edge. */
    cr_expect_lt(sum_d / (32 * 32 * 3), 1e-3, "mean difference %g", sum_d / (32 * 32 * 3));
    cr_expect_lt(off, 32 * 32 * 3 / 100, "%d channels differ", off);
    glint_film_free(&big);
    glint_film_free(&aa);
    glint_scene_free(s);
}

static void expect_bad(glint_settings st, const char *needle)
{
    glint_error err = {0};
    cr_expect_eq(glint_settings_check(&st, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, needle) != NULL, "message '%s' lacks '%s'", err.msg, needle);
}

Test(render, settings_are_checked)
{
    glint_settings ok = {500, 500, 4, 5, 0, GLINT_TRANSFER_NONE, 1.0 / 255,
                         GLINT_SAMPLER_GRID, 0.05, 3, 0};
    glint_error err = {0};
    cr_expect_eq(glint_settings_check(&ok, &err), GLINT_OK);
    glint_settings s = ok;
    s.width = 0;
    expect_bad(s, "resolution 0x500 is out of range");
    s = ok;
    s.width = 20000;
    s.height = 20000;
    expect_bad(s, "pixel limit");
    s = ok;
    s.samples = 8;
    expect_bad(s, "perfect square");
    s = ok;
    s.samples = 0;
    expect_bad(s, "samples per pixel must be 1 to");
    s = ok;
    s.max_depth = -1;
    expect_bad(s, "recursion depth");
    s = ok;
    s.threads = -2;
    expect_bad(s, "threads");
    s = ok;
    s.adc_bailout = NAN;
    expect_bad(s, "adc_bailout must be 0 (never prune) to 1 (got nan)");
    s = ok;
    s.adc_bailout = 1.5;
    expect_bad(s, "adc_bailout must be 0 (never prune) to 1 (got 1.5)");
}

static void cancel_on_first_tile(void *user, const glint_film *f, int x0, int y0, int x1, int y1)
{
    (void)f, (void)x0, (void)y0, (void)x1, (void)y1;
    atomic_store((atomic_int *)user, 1);
}

static int cancel_flag(void *user) { return atomic_load((atomic_int *)user); }

Test(render, cancel_stops_the_render)
{
    glint_scene *s = builtin();
    glint_settings st;
    glint_scene_settings(s, &st, NULL);
    st.threads = 1;
    atomic_int flag = 0;
    glint_callbacks cb = {.user = &flag, .tile_done = cancel_on_first_tile, .cancelled = cancel_flag};
    glint_film film = {0};
    glint_error err = {0};
    cr_expect_eq(glint_render(s, &st, &cb, &film, NULL, &err), GLINT_ERR_CANCELLED);
    cr_expect_null(film.rgb, "a cancelled render leaves no film");
    glint_scene_free(s);
}

/* Eight nested spheres of one material around the origin, seen from +z,
 * lit by one light. */
static glint_scene *nested_spheres(glint_material m)
{
    glint_scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(glint_scene_new(&s, &err), GLINT_OK, "%s", err.msg);
    glint_camera cam = {{0, 0, 20}, {0, 0, 0}, {0, 1, 0}, 40, 0, 0, GLINT_PROJECTION_PERSPECTIVE,
                        0, 0};
    cr_assert_eq(glint_scene_set_camera(s, &cam, &err), GLINT_OK, "%s", err.msg);
    glint_light l = {.kind = GLINT_LIGHT_POINT, .position = {5, 10, 20}, .color = {1, 1, 1}};
    cr_assert_eq(glint_scene_add_light(s, &l, NULL, &err), GLINT_OK, "%s", err.msg);
    int mat;
    cr_assert_eq(glint_scene_add_material(s, &m, &mat, &err), GLINT_OK, "%s", err.msg);
    for (int i = 1; i <= 8; i++) {
        glint_object o = {{GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, i}}, mat, NULL, 0};
        cr_assert_eq(glint_scene_add_object(s, &o, NULL, &err), GLINT_OK, "%s", err.msg);
    }
    cr_assert_eq(glint_scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

static glint_stats render_stats(const glint_scene *s, int depth, double bailout, glint_film *film)
{
    glint_settings st;
    glint_scene_settings(s, &st, NULL);
    st.width = st.height = 8;
    st.samples = 1;
    st.threads = 1;
    st.max_depth = depth;
    st.adc_bailout = bailout;
    glint_stats stats = {0};
    glint_error err = {0};
    cr_assert_eq(glint_render(s, &st, NULL, film, &stats, &err), GLINT_OK, "%s", err.msg);
    return stats;
}

/* Glass made the tree of rays grow as 2^depth: eight nested glass spheres
 * needed 3.3 M rays for 64 pixels at depth 14 and never finished at depth
 * 30. Adaptive depth control prunes a branch whose share of the pixel falls
 * below adc_bailout, so each level of the tree holds at most 1 / bailout
 * rays: at the deepest limit the render finishes within 64 pixels x 64
 * levels x 255 secondary rays, even for a material that gains energy. The
 * timeout is the failure on the old code. */
Test(render, adaptive_depth_control_bounds_the_tree_of_rays, .timeout = 120)
{
    glint_material glass = glint_material_default();
    glass.transmit = 0.9;
    glass.ior = 1.5;
    glint_material gain = glass; /* reflects and transmits all, and more */
    gain.reflect = 1;
    gain.transmit = 1;
    gain.tint[0] = gain.tint[1] = gain.tint[2] = 2;
    const uint64_t bound = 64ull * 64 * 255;
    glint_material mats[] = {glass, gain};
    for (int k = 0; k < 2; k++) {
        glint_scene *s = nested_spheres(mats[k]);
        glint_settings st;
        glint_scene_settings(s, &st, NULL);
        cr_expect_float_eq(st.adc_bailout, 1.0 / 255, 1e-12, "the default is POV-Ray's");
        glint_film film = {0};
        glint_stats deep = render_stats(s, 64, 1.0 / 255, &film);
        cr_expect_leq(deep.secondary_rays, bound, "%llu secondary rays",
                      (unsigned long long)deep.secondary_rays);
        cr_expect_gt(deep.secondary_rays, 64u, "glass is traced through");
        glint_film_free(&film);
        glint_scene_free(s);
    }

    /* What pruning leaves out is below a level of an 8-bit pixel or
     * close to it: the image at depth 9 without pruning (2^9 paths per
     * pixel) against the pruned one. */
    glint_scene *s = nested_spheres(glass);
    glint_film full = {0}, pruned = {0};
    glint_stats a = render_stats(s, 9, 0.0, &full);
    glint_stats b = render_stats(s, 9, 1.0 / 255, &pruned);
    cr_expect_lt(b.secondary_rays * 4, a.secondary_rays, "%llu of %llu",
                 (unsigned long long)b.secondary_rays, (unsigned long long)a.secondary_rays);
    double worst = 0;
    for (int i = 0; i < 8 * 8 * 3; i++)
        worst = fmax(worst, fabs(full.rgb[i] - pruned.rgb[i]));
    cr_expect_lt(worst, 4.0 / 255, "largest difference %g", worst);
    glint_film_free(&full);
    glint_film_free(&pruned);
    glint_scene_free(s);
}
