/* The camera's projections and thin lens (scene/camera.h), and where the
 * sampler puts a pixel's samples (render/sampler.h). */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "near.h"
#include "render/sampler.h"
#include "scene/camera.h"

static camera cam_of(camera_projection p, float fov)
{
    return (camera){.eye = v3(1, 2, 3), .target = v3(1, 2, -7), .up = v3(0, 1, 0),
                    .hfov = fov, .width = 8.0f, .projection = p};
}

/* The point a ray passes at distance along its unit direction that is
 * nearest to p: how far p is from the ray. */
static float miss_distance(const ray *r, vec3 p)
{
    vec3 d = v3_norm(r->d), op = v3_sub(p, r->o);
    return v3_len(v3_sub(op, v3_scale(d, v3_dot(op, d))));
}

/* A point projects through the pixel centre it should, for each projection:
 * the pinhole ray through that position passes the point. */
Test(camera, known_points_project_where_they_should)
{
    /* the camera looks down -z from (1, 2, 3); right is +x, up +y */
    struct {
        camera_projection p;
        float fov, x, y; /* image position in a 200 x 100 image */
        vec3 point;
    } cases[] = {
        {CAMERA_PERSPECTIVE, 90, 100, 50, {1, 2, -20}},        /* straight ahead */
        {CAMERA_PERSPECTIVE, 90, 150, 50, {6, 2, -7}},         /* tan 45 / 2 to the right */
        {CAMERA_PERSPECTIVE, 90, 100, 25, {1, 4.5f, -7}},      /* square pixels: 1/4 up */
        {CAMERA_ORTHOGRAPHIC, 0, 150, 50, {3, 2, -50}},        /* width 8: 2 units right */
        {CAMERA_ORTHOGRAPHIC, 0, 100, 0, {1, 4, -1}},          /* 4 units up at the top edge */
        {CAMERA_EQUIRECTANGULAR, 0, 100, 50, {1, 2, -10}},     /* ahead at the centre */
        {CAMERA_EQUIRECTANGULAR, 0, 150, 50, {9, 2, 3}},       /* right: 90 degrees east */
        {CAMERA_EQUIRECTANGULAR, 0, 0, 50, {1, 2, 13}},        /* behind, at the left edge */
        {CAMERA_EQUIRECTANGULAR, 0, 100, 0, {1, 12, 3}},       /* straight up: top row */
        {CAMERA_EQUIRECTANGULAR, 0, 125, 25, {1 + 5, 2 + 7.0710678f, 3 - 5}}, /* 45 E, 45 N */
        {CAMERA_FISHEYE, 180, 100, 50, {1, 2, -4}},            /* ahead */
        {CAMERA_FISHEYE, 180, 200, 50, {5, 2, 3}},             /* 90 degrees right: the rim */
        {CAMERA_FISHEYE, 360, 150, 50, {5, 2, 3}},             /* 360: 90 degrees halfway out */
        {CAMERA_FISHEYE, 360, 0, 50, {1, 2, 9}},               /* behind: the rim */
        {CAMERA_FISHEYE, 360, 100, 0, {1, 9, 3}},              /* straight up */
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        camera c = cam_of(cases[i].p, cases[i].fov);
        camera_frame f = camera_frame_make(&c, 200, 100);
        ray r;
        cr_assert(camera_ray(&f, cases[i].x, cases[i].y, 0.5f, 0.5f, &r), "case %zu: no ray", i);
        float miss = miss_distance(&r, cases[i].point);
        cr_expect(miss < 1e-3f * (1.0f + v3_len(v3_sub(cases[i].point, c.eye))),
                  "case %zu (projection %d, at %g, %g): the ray misses the point by %g", i,
                  (int)cases[i].p, (double)cases[i].x, (double)cases[i].y, (double)miss);
        cr_expect(v3_dot(r.d, v3_sub(cases[i].point, r.o)) > 0.0f,
                  "case %zu: the point is behind the ray", i);
    }
}

Test(camera, fisheye_is_black_outside_its_circle)
{
    camera c = cam_of(CAMERA_FISHEYE, 180);
    camera_frame f = camera_frame_make(&c, 100, 100);
    ray r;
    cr_expect(!camera_ray(&f, 2, 2, 0.5f, 0.5f, &r), "a corner is outside the image circle");
    cr_expect(camera_ray(&f, 50, 2, 0.5f, 0.5f, &r), "the top middle is inside");
}

/* Thin lens: every ray through a pixel, from anywhere on the lens, passes
 * through the one point the pinhole ray meets at the focus distance; a
 * point off that distance is spread over many. */
Test(camera, thin_lens_focuses_one_point_for_any_lens_sample)
{
    camera_projection ps[] = {CAMERA_PERSPECTIVE, CAMERA_ORTHOGRAPHIC, CAMERA_EQUIRECTANGULAR,
                              CAMERA_FISHEYE};
    for (size_t k = 0; k < 4; k++) {
        camera c = cam_of(ps[k], 70);
        c.aperture = 1.5f;
        c.focus_distance = 6.0f;
        camera_frame pin = camera_frame_make(&(camera){.eye = c.eye, .target = c.target,
                                                       .up = c.up, .hfov = c.hfov,
                                                       .width = c.width, .projection = c.projection},
                                             64, 48);
        camera_frame lens = camera_frame_make(&c, 64, 48);
        float x = 41.3f, y = 17.6f;
        ray p;
        cr_assert(camera_ray(&pin, x, y, 0.5f, 0.5f, &p));
        /* the pinhole ray's point at the focus distance: along the axis
         * (perspective, orthographic) or along the ray (panoramas) */
        float t = k < 2 ? 6.0f / v3_dot(p.d, pin.w) : 6.0f / v3_len(p.d);
        vec3 focal = ray_at(&p, t);
        float spread = 0.0f;
        for (int i = 0; i < 64; i++) {
            float lu = (float)(i % 8) / 8 + 0.03f, lv = (float)(i / 8) / 8 + 0.05f;
            ray r;
            cr_assert(camera_ray(&lens, x, y, lu, lv, &r));
            cr_expect(miss_distance(&r, focal) < 1e-4f * 16,
                      "projection %zu, lens (%g, %g): misses the focal point by %g", k,
                      (double)lu, (double)lv, (double)miss_distance(&r, focal));
            cr_expect(v3_len(v3_sub(r.o, c.eye)) <= 0.75f + 1e-4f + (k == 1 ? 8.0f : 0.0f),
                      "the ray starts on the lens");
            spread = fmaxf(spread, miss_distance(&r, ray_at(&p, 2.0f * t)));
        }
        cr_expect(spread > 0.2f, "projection %zu: a point twice as far is not blurred (%g)", k,
                  (double)spread);
    }
}

/* ---- the sampler ---------------------------------------------------------- */

static sampler make(glint_sampler kind, int samples)
{
    glint_settings st = {16, 16, samples, 5, 1, GLINT_TRANSFER_NONE, 1.0 / 255,
                         kind, 0.05, 3, 0};
    return sampler_make(&st, true, true);
}

/* A row of up to eight camera rays (camera_row8, and camera_row8_on for
 * each SIMD path the CPU has) is camera_ray's rays to the bit, pixel by
 * pixel, idle lanes repeating the first; for a pinhole too, whose rows the
 * eight-wide paths make in registers. */
Test(camera, rows_of_eight_are_camera_rays_on_every_path)
{
    camera tilted = cam_of(CAMERA_PERSPECTIVE, 37.3f); /* every component of dx and dy */
    tilted.target = v3(4.1f, -1.3f, -7.0f);
    tilted.up = v3(0.2f, 1.0f, 0.1f);
    const camera cams[] = {tilted, cam_of(CAMERA_ORTHOGRAPHIC, 0), cam_of(CAMERA_FISHEYE, 190),
                           cam_of(CAMERA_EQUIRECTANGULAR, 0)};
    int checked = 0;
    for (int c = 0; c < 4; c++)
        for (int isa = ACCEL_SCALAR; isa <= ACCEL_AVX512; isa++) {
            if (isa > (int)accel_isa_best())
                continue;
            camera_frame f = camera_frame_make(&cams[c], 1283, 719);
            for (int i = 0; i < 400; i++) {
                int x0 = (i * 37) % 1280, n = 1 + i % 8;
                float fx = (float)(i % 13) / 13.0f, y = (float)(i * 7 % 719) + 0.37f;
                ray8 p;
                int active = camera_row8_on((accel_isa)isa, &f, x0, n, fx, y, 0.5f, 0.5f, 0.25f, &p);
                for (int k = 0; k < 8; k++) {
                    ray want;
                    bool has = camera_ray(&f, (float)(x0 + (k < n ? k : 0)) + fx, y, 0.5f, 0.5f,
                                          &want);
                    cr_assert_eq((active >> k & 1) != 0, has && k < n, "camera %d lane %d", c, k);
                    if (!has || k >= n)
                        continue;
                    ray got = ray8_get(&p, k);
                    cr_assert(memcmp(&got.o, &want.o, sizeof want.o) == 0 &&
                                  memcmp(&got.d, &want.d, sizeof want.d) == 0 &&
                                  got.tmin == want.tmin && got.tmax == want.tmax &&
                                  got.time == 0.25f,
                              "camera %d on %s, row %d lane %d: (%.9g %.9g %.9g) against "
                              "(%.9g %.9g %.9g)",
                              c, accel_isa_name((accel_isa)isa), i, k, got.d.x, got.d.y, got.d.z,
                              want.d.x, want.d.y, want.d.z);
                    checked++;
                }
            }
        }
    cr_assert_gt(checked, 4000);
}

Test(sampler, grid_is_the_regular_grid)
{
    sampler s = make(GLINT_SAMPLER_GRID, 4);
    float want[4][2] = {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.25f, 0.75f}, {0.75f, 0.75f}};
    for (int k = 0; k < 4; k++) {
        pixel_sample p = sampler_get(&s, 3, 9, k);
        cr_expect(p.fx == want[k][0] && p.fy == want[k][1], "sample %d at (%g, %g)", k,
                  (double)p.fx, (double)p.fy);
    }
}

/* Each sample of a pixel in its own cell, on the lens and in time too; the
 * same numbers on every call (no state); pixels differ from each other. */
Test(sampler, jitter_is_stratified_and_deterministic)
{
    for (int n = 1; n <= 7; n++) {
        sampler s = make(GLINT_SAMPLER_JITTER, n * n);
        int count = n * n;
        for (int px = 0; px < 20; px++) {
            int x = px * 37 % 1000, y = px * 101 % 777;
            unsigned char cell[64] = {0}, lens[64] = {0}, slot[64] = {0};
            for (int k = 0; k < count; k++) {
                pixel_sample p = sampler_get(&s, x, y, k), q = sampler_get(&s, x, y, k);
                cr_assert_eq(memcmp(&p, &q, sizeof p), 0, "not deterministic");
                cr_assert(p.fx >= 0 && p.fx < 1 && p.fy >= 0 && p.fy < 1 && p.lu >= 0 &&
                          p.lu < 1 && p.lv >= 0 && p.lv < 1 && p.time >= 0 && p.time < 1);
                cr_expect_eq((int)(p.fx * n), k % n, "n %d sample %d x outside its cell", n, k);
                cr_expect_eq((int)(p.fy * n), k / n, "n %d sample %d y outside its cell", n, k);
                cell[(int)(p.fy * n) * n + (int)(p.fx * n)]++;
                lens[(int)(p.lv * n) * n + (int)(p.lu * n)]++;
                slot[(int)(p.time * count)]++;
            }
            for (int c = 0; c < count; c++) {
                cr_expect_eq(cell[c], 1, "n %d: image cell %d used %d times", n, c, cell[c]);
                cr_expect_eq(lens[c], 1, "n %d: lens cell %d used %d times", n, c, lens[c]);
                cr_expect_eq(slot[c], 1, "n %d: time slot %d used %d times", n, c, slot[c]);
            }
        }
    }
    /* neighbours get different patterns */
    sampler s = make(GLINT_SAMPLER_JITTER, 16);
    pixel_sample a = sampler_get(&s, 10, 10, 5), b = sampler_get(&s, 11, 10, 5);
    cr_expect(a.fx != b.fx || a.fy != b.fy, "two pixels share a jitter");
}
