/* Rendering with each sampler: the adaptive sampler spends samples only
 * where the image changes and becomes the full grid at threshold 0; alpha
 * is coverage; each sampler renders the same for any thread count. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "glint.h"
#include "load/load.h"

/* Left of x = 0 a flat white quad (ambient light only) on a black
 * background; a 64 x 64 image whose left half the quad fills, the edge
 * running down column 32. */
static const char halves[] =
    "image: {width: 64, height: 64, sampler: adaptive, threshold: 0.05, max_depth: 3}\n"
    "camera: {projection: orthographic, width: 64, eye: [0, 0, 10], look_at: [0, 0, 0]}\n"
    "ambient: 1\n"
    "objects:\n"
    "  - {type: quad, origin: [-40, -40, 0], edge_u: [40, 0, 0], edge_v: [0, 80, 0],\n"
    "     material: {color: 1, diffuse: 0}}\n";

static glint_scene *load(const char *text)
{
    glint_scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(scene_load_text(text, strlen(text), "scene.yaml", NULL, NULL, NULL, &s, &err),
                 GLINT_OK, "%s", err.msg);
    return s;
}

/* Average camera rays per pixel over the region. */
static double spp_of(const glint_scene *s, const glint_settings *st, glint_rect r)
{
    glint_film film = {0};
    glint_error err = {0};
    glint_stats stats;
    cr_assert_eq(glint_film_alloc(&film, st->width, st->height, &err), GLINT_OK);
    cr_assert_eq(glint_render_region(s, st, &r, NULL, &film, &stats, &err), GLINT_OK, "%s",
                 err.msg);
    glint_film_free(&film);
    return (double)stats.primary_rays / (double)((r.x1 - r.x0) * (r.y1 - r.y0));
}

Test(sampling, adaptive_splits_only_where_the_image_changes)
{
    glint_scene *s = load(halves);
    glint_settings st;
    glint_scene_settings(s, &st, NULL);
    double flat_in = spp_of(s, &st, (glint_rect){0, 0, 16, 64});
    double flat_out = spp_of(s, &st, (glint_rect){48, 0, 64, 64});
    double edge = spp_of(s, &st, (glint_rect){31, 0, 33, 64});
    /* a flat pixel: its centre and one corner (the others are its
     * neighbours'), and the corners along tile borders traced twice */
    cr_expect(flat_in >= 1.0 && flat_in <= 2.2, "flat quad: %g samples per pixel", flat_in);
    cr_expect(flat_out >= 1.0 && flat_out <= 2.2, "background: %g samples per pixel", flat_out);
    /* the pixels beside the edge split to the finest cells along it */
    cr_expect(edge > 8.0, "the edge: only %g samples per pixel", edge);
    /* the edge pixel's value is its coverage, to 1/16 (8 x 8 cells) */
    glint_film film = {0};
    glint_error err = {0};
    cr_assert_eq(glint_render(s, &st, NULL, &film, NULL, &err), GLINT_OK);
    for (int y = 0; y < 64; y++) {
        cr_expect_eq(film.rgb[(y * 64 + 20) * 3], 1.0f, "inside");
        cr_expect_eq(film.rgb[(y * 64 + 40) * 3], 0.0f, "outside");
    }
    glint_film_free(&film);
    glint_scene_free(s);
}

/* A chequer texture: inside a square the pixels are flat, along its edges
 * (half-way through pixels) they split. */
Test(sampling, adaptive_splits_along_texture_edges)
{
    static const char text[] =
        "image: {width: 64, height: 64, sampler: adaptive, threshold: 0.05, max_depth: 3}\n"
        "camera: {projection: orthographic, width: 64, eye: [0, 0, 10], look_at: [0, 0, 0]}\n"
        "ambient: 1\n"
        "objects:\n"
        "  - {type: quad, origin: [-40.5, -40.5, 0], edge_u: [80, 0, 0], edge_v: [0, 80, 0],\n"
        "     material: {diffuse: 0, texture: {type: checker, scale: 5}}}\n";
    glint_scene *s = load(text);
    glint_settings st;
    glint_scene_settings(s, &st, NULL);
    /* squares 16 pixels wide, edges at x and y = 7.5, 23.5, 39.5, 55.5 */
    double inside = spp_of(s, &st, (glint_rect){9, 9, 23, 23});
    double edge = spp_of(s, &st, (glint_rect){23, 9, 24, 23});
    /* no pixel splits: each of the four 7 x 7 tile pieces traces its 8 x 8
     * pixel corners and 49 centres */
    cr_expect(fabs(inside - 4.0 * (64 + 49) / 196.0) < 1e-9,
              "inside a square: %g samples per pixel", inside);
    cr_expect(edge > 8.0, "along a square's edge: only %g samples per pixel", edge);
    glint_scene_free(s);
}

/* At threshold 0 every cell splits down to max_depth: the pixel is the
 * 2^depth x 2^depth grid's, to float rounding (the means are taken in
 * another order). */
Test(sampling, adaptive_at_threshold_0_is_the_full_grid)
{
    glint_scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(glint_scene_builtin(&s, &err), GLINT_OK);
    glint_settings grid;
    glint_scene_settings(s, &grid, NULL);
    grid.width = grid.height = 48;
    grid.samples = 16;
    glint_settings ad = grid;
    ad.sampler = GLINT_SAMPLER_ADAPTIVE;
    ad.threshold = 0.0;
    ad.adaptive_depth = 2;
    glint_film a = {0}, b = {0};
    glint_stats sa, sb;
    cr_assert_eq(glint_render(s, &grid, NULL, &a, &sb, &err), GLINT_OK);
    cr_assert_eq(glint_render(s, &ad, NULL, &b, &sa, &err), GLINT_OK);
    float worst = 0.0f;
    for (size_t i = 0; i < 48 * 48 * 3; i++)
        worst = fmaxf(worst, fabsf(a.rgb[i] - b.rgb[i]));
    cr_expect(worst < 1e-5f, "adaptive at threshold 0 differs from the 4 x 4 grid by %g",
              (double)worst);
    cr_expect_gt(sa.primary_rays, sb.primary_rays, "the lattice's corners come on top");
    glint_film_free(&a);
    glint_film_free(&b);
    glint_scene_free(s);
}

/* Alpha: 1 where camera rays hit, 0 where they see the background, the
 * share hit on an edge; the RGB is unchanged by asking for it. */
Test(sampling, alpha_is_coverage)
{
    glint_scene *s = load(halves);
    glint_settings st;
    glint_scene_settings(s, &st, NULL);
    st.sampler = GLINT_SAMPLER_GRID;
    st.samples = 16;
    /* move the edge to a quarter of a pixel: x = 0.25 in world units */
    glint_camera cam;
    glint_scene_camera(s, &cam, NULL);
    cam.eye[0] = cam.look_at[0] = 31.75;
    glint_error err = {0};
    cr_assert_eq(glint_scene_set_camera(s, &cam, &err), GLINT_OK, "%s", err.msg);
    glint_film plain = {0}, film = {0};
    cr_assert_eq(glint_render(s, &st, NULL, &plain, NULL, &err), GLINT_OK);
    cr_expect_null(plain.alpha, "no alpha unless asked");
    st.alpha = 1;
    cr_assert_eq(glint_render(s, &st, NULL, &film, NULL, &err), GLINT_OK);
    cr_assert_not_null(film.alpha);
    cr_expect_eq(memcmp(film.rgb, plain.rgb, sizeof(float) * 64 * 64 * 3), 0);
    /* the quad ends at world x 0, image x 32 - 31.75 = 0.25: pixel 0 is a
     * quarter covered (one column of four samples), pixel 1 not at all */
    for (int y = 0; y < 64; y += 9) {
        cr_expect_eq(film.alpha[y * 64 + 0], 0.25f, "row %d: edge %g", y,
                     (double)film.alpha[y * 64]);
        cr_expect_eq(film.alpha[y * 64 + 1], 0.0f, "row %d", y);
    }
    glint_film_free(&plain);
    glint_film_free(&film);
    glint_scene_free(s);
}

/* Every sampler, with lens and motion, is the same for 1 and 3 threads. */
Test(sampling, every_sampler_is_the_same_for_any_thread_count)
{
    static const char text[] =
        "animation: {frames: 2}\n"
        "image: {width: 40, height: 30, samples: 4}\n"
        "camera: {eye: {keys: [[0, [0, 1, 6]], [1, [1, 1, 6]]]}, look_at: [0, 0, 0],\n"
        "         aperture: 0.3, shutter: 1}\n"
        "lights: [{type: point, position: [3, 5, 4]}]\n"
        "objects:\n"
        "  - {type: plane, point: [0, -1, 0], normal: [0, 1, 0]}\n"
        "  - type: box\n"
        "    min: [-1, -1, -1]\n"
        "    max: [1, 1, 1]\n"
        "    transform: [{rotate_y: {keys: [[0, 0], [1, 90]]}}]\n";
    glint_scene *s = load(text);
    glint_error err = {0};
    cr_assert_eq(glint_scene_set_frame(s, 2, &err), GLINT_OK, "%s", err.msg);
    for (int k = 0; k < 3; k++) {
        glint_settings st;
        glint_scene_settings(s, &st, NULL);
        st.sampler = (glint_sampler)k;
        st.threads = 1;
        glint_film a = {0}, b = {0};
        cr_assert_eq(glint_render(s, &st, NULL, &a, NULL, &err), GLINT_OK);
        st.threads = 3;
        cr_assert_eq(glint_render(s, &st, NULL, &b, NULL, &err), GLINT_OK);
        cr_expect_eq(memcmp(a.rgb, b.rgb, sizeof(float) * 40 * 30 * 3), 0, "sampler %d", k);
        glint_film_free(&a);
        glint_film_free(&b);
    }
    glint_scene_free(s);
}
