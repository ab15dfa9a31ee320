/* Lights, shadows, absorption and fog (src/shade/light.h, src/shade/fog.h,
 * src/trace/lighting.h): the spot light's falloff at known angles, point
 * attenuation, the share of an area light a point sees past an edge (to
 * sampling accuracy), Beer-Lambert absorption through a slab of known
 * thickness along camera and shadow rays, fog transmittance at known
 * distances and heights, and area-light renders that are the same for 1, 2
 * and 3 threads. */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "load/load.h"
#include "scene/scene.h"
#include "shade/fog.h"
#include "shade/light.h"
#include "trace/lighting.h"
#include "film.h"
#include "near.h"

#define RAD(d) ((d) * M_PI / 180.0)

/* Direction at angle deg from the -y axis, towards +x. */
static vec3 off_axis(double deg) { return v3((float)sin(RAD(deg)), -(float)cos(RAD(deg)), 0.0f); }

Test(light, spot_intensity_at_known_angles)
{
    light l = light_spot(v3(0, 10, 0), v3(0, 0, 0), 20.0f, 30.0f, v3s(2.0f), v3(1, 0, 0));
    /* A point at distance 10 along each direction from the light. */
    double angles[] = {0, 10, 19.9, 20.1, 25, 29.9, 30.1, 45, 120};
    for (size_t i = 0; i < sizeof angles / sizeof *angles; i++) {
        double a = angles[i];
        vec3 p = v3_madd(v3(0, 10, 0), off_axis(a), 10.0f);
        light_ray r = light_sample(&l, p, 0, 0.5f, 0.5f);
        double expect;
        if (a <= 20)
            expect = 1;
        else if (a >= 30)
            expect = 0;
        else {
            double t = (cos(RAD(a)) - cos(RAD(30))) / (cos(RAD(20)) - cos(RAD(30)));
            expect = t * t * (3 - 2 * t);
        }
        ASSERT_NEAR(r.color.x, 2.0 * expect, 1e-4);
        ASSERT_NEAR(r.dist, 10.0, 1e-4);
        ASSERT_V3_NEAR(r.dir, -off_axis(a).x, -off_axis(a).y, 0, 1e-5);
    }
    /* Half way between the cosines the smooth step is exactly 1/2. */
    float mid = 0.5f * (float)(cos(RAD(20)) + cos(RAD(30)));
    ASSERT_NEAR(light_spot_factor(&l.spot, mid), 0.5, 1e-5);
    /* The falloff only decreases with the angle. */
    float prev = 1.0f;
    for (double a = 0; a <= 40; a += 0.25) {
        float f = light_spot_factor(&l.spot, (float)cos(RAD(a)));
        cr_expect_leq(f, prev + 1e-6f, "falloff rises at %g degrees", a);
        prev = f;
    }
}

Test(light, point_attenuation_values)
{
    vec3 p = v3(1, 2, 3);
    struct {
        vec3 att;
        float d, expect;
    } cases[] = {
        {{1, 0, 0}, 5, 1.0f},              /* the default: no fall-off */
        {{1, 0.5f, 0.25f}, 2, 1.0f / 3},   /* 1 + 1 + 1 */
        {{0, 0, 1}, 4, 1.0f / 16},         /* inverse square */
        {{0.5f, 0.25f, 0}, 6, 0.5f},       /* 0.5 + 1.5 */
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        light l = light_point(v3_add(p, v3(0, cases[i].d, 0)), v3(1, 2, 4), cases[i].att);
        light_ray r = light_sample(&l, p, 0, 0.5f, 0.5f);
        ASSERT_V3_NEAR(r.color, cases[i].expect, 2 * cases[i].expect, 4 * cases[i].expect, 1e-6);
        ASSERT_V3_NEAR(r.dir, 0, 1, 0, 1e-6);
        ASSERT_NEAR(r.dist, cases[i].d, 1e-5);
        ASSERT_NEAR(light_attenuation(cases[i].att, cases[i].d), cases[i].expect, 1e-6);
    }
    light sun = light_directional(v3(0, -2, 0), v3s(0.5f));
    light_ray r = light_sample(&sun, p, 0, 0.5f, 0.5f);
    ASSERT_V3_NEAR(r.dir, 0, 1, 0, 0);
    cr_expect(isinf(r.dist), "directional light is infinitely far");
    ASSERT_V3_NEAR(r.color, 0.5, 0.5, 0.5, 0);
}

Test(light, area_samples_cover_the_rectangle_in_strata)
{
    light l = light_area(v3(0, 10, 0), v3(4, 0, 0), v3(0, 0, 2), 4, v3s(1.6f), v3(1, 0, 0));
    cr_assert_eq(light_sample_count(&l), 16);
    for (int k = 0; k < 16; k++) {
        light_ray lo = light_sample(&l, v3s(0), k, 0.0f, 0.0f);
        light_ray hi = light_sample(&l, v3s(0), k, 0.999f, 0.999f);
        /* cell (k % 4, k / 4) of the 4 x 2 rectangle centred on (0, 10, 0) */
        ASSERT_NEAR(lo.pos.x, -2 + (k % 4), 1e-5);
        ASSERT_NEAR(lo.pos.z, -1 + 0.5 * (k / 4), 1e-5);
        ASSERT_NEAR(hi.pos.x, -2 + (k % 4) + 0.999, 1e-4);
        ASSERT_NEAR(lo.pos.y, 10, 0);
        ASSERT_NEAR(lo.color.x, 0.1, 1e-6); /* each sample carries 1/16 */
    }
}

/* A scene with an area light N x N of side 2 centred 10 above the origin
 * and an opaque half-plane at height 5 covering x < 0. */
static scene *edge_scene(int n)
{
    scene *s = scene_new();
    material m = material_default();
    scene_add_material(s, &m);
    shape q = shape_quad(v3(-100, 5, -100), v3(100, 0, 0), v3(0, 0, 200));
    scene_add_object(s, &q, 0, -1);
    light l = light_area(v3(0, 10, 0), v3(2, 0, 0), v3(0, 0, 2), n, v3s(1), v3(1, 0, 0));
    scene_add_light(s, &l);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

/* The diffuse light at p on a floor facing up, for one shading event. */
static float lit(trace_ctx *ctx, vec3 p)
{
    material m = material_default();
    m.ambient = 0.0f;
    shade_point sp = {p, v3(0, 1, 0), v3(0, 1, 0), v3(0, -1, 0), false, v3s(1), &m};
    return lighting_local(ctx, &sp).x;
}

Test(light, area_light_seen_half_past_an_edge)
{
    int n = 5;
    scene *s = edge_scene(n);
    scene *open = edge_scene(n);
    open->nobjects = 0; /* the same light with nothing in the way */
    glint_error err = {0};
    cr_assert_eq(scene_build(open, &err), GLINT_OK, "%s", err.msg);
    trace_ctx ctx = {.scene = s}, octx = {.scene = open};
    double sum = 0.0;
    int events = 400;
    for (int e = 0; e < events; e++) {
        trace_begin_sample(&ctx, (uint32_t)e, 7, 0);
        trace_begin_sample(&octx, (uint32_t)e, 7, 0);
        float f = lit(&ctx, v3(0, 0, 0)) / lit(&octx, v3(0, 0, 0));
        /* Two of five columns are hidden, two seen, and the middle one
         * straddles the edge: the share is 0.4 to 0.6 every time (up to
         * the slightly different angles of the samples). */
        cr_expect(f >= 0.39f && f <= 0.61f, "event %d sees %g", e, f);
        sum += f;
    }
    ASSERT_NEAR(sum / events, 0.5, 0.02);
    /* Far to either side the point sees all of it or none. */
    trace_begin_sample(&ctx, 1, 2, 3);
    trace_begin_sample(&octx, 1, 2, 3);
    ASSERT_NEAR(lit(&ctx, v3(3, 0, 0)) / lit(&octx, v3(3, 0, 0)), 1.0, 1e-6);
    ASSERT_NEAR(lit(&ctx, v3(-3, 0, 0)), 0.0, 0);
    cr_expect_eq(ctx.shadow_rays, (uint64_t)(events + 2) * 25, "one shadow ray per sample");
    scene_free(s);
    scene_free(open);
}

/* A slab x in [-1, 1] of clear glass (ior 1) absorbing (0.5, 0.25, 0)
 * per unit, seen through along x against a white background. */
static scene *slab_scene(void)
{
    scene *s = scene_new();
    material m = material_default();
    m.transmit = 1.0f;
    m.absorption = v3(0.5f, 0.25f, 0.0f);
    scene_add_material(s, &m);
    shape b = shape_box(v3(-1, -5, -5), v3(1, 5, 5));
    scene_add_object(s, &b, 0, -1);
    scene_set_background(s, v3s(1.0f));
    scene_set_camera(s, &(camera){.eye = v3(-10, 0, 0), .target = v3(0, 0, 0), .up = v3(0, 1, 0),
                             .hfov = 10.0f});
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    return s;
}

Test(light, absorption_through_a_slab_of_known_thickness)
{
    scene *s = slab_scene();
    glint_film f = test_render(s, 3, 3, 1, 1);
    const float *c = f.rgb + 4 * 3; /* the centre pixel, straight through 2 units */
    ASSERT_NEAR(c[0], exp(-1.0), 1e-4);
    ASSERT_NEAR(c[1], exp(-0.5), 1e-4);
    ASSERT_NEAR(c[2], 1.0, 1e-5);
    glint_film_free(&f);
    /* A shadow ray crossing the slab fades the same way. */
    trace_ctx ctx = {.scene = s};
    light_ray lr = {v3(1, 0, 0), INFINITY, v3s(0), v3s(1)};
    vec3 vis = lighting_shadow(&ctx, v3(-3, 0, 0), v3(1, 0, 0), &lr);
    ASSERT_V3_NEAR(vis, exp(-1.0), exp(-0.5), 1.0, 1e-4);
    scene_free(s);
}

Test(light, fog_transmittance_at_known_distances)
{
    vec3 o = v3(0, 0, 0), x = v3(1, 0, 0), up = v3(0, 1, 0);
    fog e = {FOG_EXPONENTIAL, v3(0.2f, 0.4f, 0.6f), 0.1f, 0, 0, 0};
    ASSERT_NEAR(fog_transmittance(&e, o, x, 10), exp(-1.0), 1e-6);
    ASSERT_NEAR(fog_transmittance(&e, o, x, 0), 1.0, 0);
    ASSERT_NEAR(fog_transmittance(&e, o, x, INFINITY), 0.0, 0);
    vec3 c = fog_apply(&e, o, x, INFINITY, v3(9, 9, 9));
    ASSERT_V3_NEAR(c, 0.2, 0.4, 0.6, 1e-7); /* the background fades to the fog */
    c = fog_apply(&e, o, x, 10, v3s(1));
    double t = exp(-1.0);
    ASSERT_V3_NEAR(c, t + 0.2 * (1 - t), t + 0.4 * (1 - t), t + 0.6 * (1 - t), 1e-6);

    fog lin = {FOG_LINEAR, v3s(1), 0, 2, 12, 0};
    ASSERT_NEAR(fog_transmittance(&lin, o, x, 1), 1.0, 0);
    ASSERT_NEAR(fog_transmittance(&lin, o, x, 7), 0.5, 1e-6);
    ASSERT_NEAR(fog_transmittance(&lin, o, x, 9.5f), 0.25, 1e-6);
    ASSERT_NEAR(fog_transmittance(&lin, o, x, 20), 0.0, 0);

    /* Height fall-off h: along the ground the fog is as dense as given;
     * straight up from y = 0 its distance is (1 - exp(-h t)) / h, and 1 / h
     * to infinity; from y = 2 everything is exp(-2 h) thinner. */
    fog g = {FOG_EXPONENTIAL, v3s(1), 0.1f, 0, 0, 0.5f};
    ASSERT_NEAR(fog_distance(&g, o, x, 10), 10.0, 1e-5);
    ASSERT_NEAR(fog_distance(&g, o, up, 4), (1 - exp(-2.0)) / 0.5, 1e-5);
    ASSERT_NEAR(fog_distance(&g, o, up, INFINITY), 2.0, 1e-6);
    ASSERT_NEAR(fog_transmittance(&g, o, up, INFINITY), exp(-0.2), 1e-6);
    ASSERT_NEAR(fog_distance(&g, v3(0, 2, 0), x, 10), 10 * exp(-1.0), 1e-5);
    cr_expect(isinf(fog_distance(&g, o, v3(0, -1, 0), INFINITY)), "down into the fog forever");
    ASSERT_NEAR(fog_transmittance(&g, o, v3(0, -1, 0), INFINITY), 0.0, 0);
}

Test(light, area_lights_render_the_same_for_1_2_and_3_threads)
{
    scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(scene_load_file(GLINT_SOURCE_DIR "/scenes/lights.yaml", &s, &err), GLINT_OK,
                 "%s", err.msg);
    glint_film ref = test_render(s, 48, 30, 4, 1);
    for (int threads = 2; threads <= 3; threads++) {
        glint_film f = test_render(s, 48, 30, 4, threads);
        cr_expect_eq(memcmp(ref.rgb, f.rgb, sizeof(float) * 48 * 30 * 3), 0, "%d threads",
                     threads);
        glint_film_free(&f);
    }
    /* and run to run */
    glint_film again = test_render(s, 48, 30, 4, 2);
    cr_expect_eq(memcmp(ref.rgb, again.rgb, sizeof(float) * 48 * 30 * 3), 0);
    glint_film_free(&again);
    glint_film_free(&ref);
    scene_free(s);
}

/* Secondary rays of a 3 x 3 render of s at one sample per pixel. */
static uint64_t secondary_rays(const scene *s)
{
    glint_settings st = scene_settings(s);
    st.width = st.height = 3;
    st.samples = 1;
    st.threads = 1;
    glint_film f = {0};
    glint_stats stats = {0};
    glint_error err = {0};
    cr_assert_eq(glint_render(s, &st, NULL, &f, &stats, &err), GLINT_OK, "%s", err.msg);
    glint_film_free(&f);
    return stats.secondary_rays;
}

Test(light, fresnel_off_and_emission)
{
    /* Straight through the slab of glass (ior 1.5): with Fresnel off and
     * reflect 0 nothing is reflected, so each pixel traces just the two
     * refracted rays and the background comes through whole; with it on,
     * each face also sends a reflected ray. Emission adds at each face. */
    scene *s = slab_scene();
    material *m = &s->materials[0];
    m->absorption = v3s(0.0f);
    m->ior = 1.5f;
    m->fresnel = false;
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    glint_film f = test_render(s, 3, 3, 1, 1);
    ASSERT_NEAR(f.rgb[4 * 3], 1.0, 1e-5);
    glint_film_free(&f);
    cr_expect_eq(secondary_rays(s), 9 * 2, "refracted rays only");
    m->fresnel = true;
    cr_expect_geq(secondary_rays(s), 9 * 4, "and reflected rays at the faces");
    m->fresnel = false;
    m->emission = v3(0.25f, 0, 0);
    f = test_render(s, 3, 3, 1, 1);
    ASSERT_NEAR(f.rgb[4 * 3], 1.5, 1e-5); /* 0.25 at the front + 0.25 at the back + 1 */
    ASSERT_NEAR(f.rgb[4 * 3 + 1], 1.0, 1e-5);
    glint_film_free(&f);
    scene_free(s);
}

/* The highlight's power: powf's to the bit for a shininess that is not a
 * whole number, and for whole ones (repeated squaring) within n + 1 ulps
 * of x^n relative to it, or below 2^-120 where x^n is; +0 where powf
 * gives +0. Every binade of (0, 1], mantissas from a fixed seed,
 * shininess from 0.5 to 10^4. */
Test(light, highlight_power_is_x_to_the_n)
{
    const float shininess[] = {0.5f,   1.0f,   2.0f,   5.0f,    10.0f,   40.0f,   50.0f,
                               100.0f, 151.0f, 152.0f, 153.0f,  1000.0f, 10000.0f, 2.5f,
                               37.25f, 80.0f,  200.0f, 255.0f,  65536.0f};
    uint32_t seed = 12345u;
    int zeros = 0, whole = 0;
    for (uint32_t exp = 1; exp <= 127; exp++)
        for (int k = 0; k < 64; k++) {
            seed = seed * 1664525u + 1013904223u;
            uint32_t bits = exp << 23 | (seed >> 9);
            float x;
            memcpy(&x, &bits, sizeof x);
            if (!(x > 0.0f && x <= 1.0f))
                continue;
            for (size_t i = 0; i < sizeof shininess / sizeof *shininess; i++) {
                float n = shininess[i], a = material_highlight(x, n), b = powf(x, n);
                double want = pow((double)x, (double)n);
                if (n != floorf(n)) {
                    cr_assert_eq(memcmp(&a, &b, sizeof a), 0, "%a^%g: %a, powf %a", (double)x,
                                 (double)n, (double)a, (double)b);
                } else if (want > 0x1p-120) {
                    cr_assert_leq(fabs(a - want), (n + 1.0) * 0x1p-23 * want, "%a^%g: %a, not %a",
                                  (double)x, (double)n, (double)a, want);
                    whole++;
                } else {
                    cr_assert_leq(a, 0x1p-119f, "%a^%g: %a", (double)x, (double)n, (double)a);
                }
                if (b == 0.0f)
                    cr_assert_eq(a, 0.0f, "%a^%g: %a where powf gives 0", (double)x, (double)n,
                                 (double)a);
                zeros += a == 0.0f;
            }
        }
    cr_assert_gt(whole, 5000, "only %d whole powers checked", whole);
    cr_assert_gt(zeros, 10000, "only %d results of 0", zeros);
}
