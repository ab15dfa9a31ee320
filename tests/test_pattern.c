/* Procedural patterns, colour maps and image mappings
 * (src/shade/pattern.h, src/shade/texture.h): pattern values at known
 * points, Perlin noise in [-1, 1] and deterministic, the (u, v) of each
 * mapping at known points, a spherical map on a sphere agreeing with the
 * sphere's own (u, v), bump gradients, and the scene format's rules for
 * lights, textures, materials and fog. */
#include <criterion/criterion.h>
#include <dlfcn.h>
#include <math.h>
#include <string.h>

#include "core/hash.h"
#include "geom/shape.h"
#include "load/load.h"
#include "scene/scene.h"
#include "shade/pattern.h"
#include "shade/texture.h"
#include "near.h"

#define TOL 1e-6

/* The parity of floor(x) + floor(y) + floor(z) is fmod(|s|, 2) < 0.5's,
 * far out too: large odd and even cells, past 2^24 (where a float is a
 * whole even number), infinities and NaN. */
Test(pattern, checker_parity_far_out)
{
    const float at[] = {0.5f,        -0.5f,     3.0f,       -3.0f,    8388607.5f, -8388607.5f,
                        16777215.0f, 16777216.0f, 1e20f,    -1e20f,   3.4e38f,    -3.4e38f,
                        INFINITY,    -INFINITY,  NAN,       1e-45f,   -1e-45f,    2.5e9f};
    int n = (int)(sizeof at / sizeof *at);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            vec3 q = v3(at[i], at[j], at[(i + j) % n]);
            double s = floor((double)q.x) + floor((double)q.y) + floor((double)q.z);
            float want = fmod(fabs(s), 2.0) < 0.5 ? 0.0f : 1.0f;
            cr_assert_eq(pattern_checker(q, false), want, "(%g, %g, %g)", (double)q.x,
                         (double)q.y, (double)q.z);
        }
}

Test(pattern, values_at_known_points)
{
    cr_expect_eq(pattern_checker(v3(0.5f, 0.5f, 0.5f), true), 0.0f);
    cr_expect_eq(pattern_checker(v3(1.5f, 0.5f, 0.5f), true), 1.0f);
    cr_expect_eq(pattern_checker(v3(1.5f, 1.5f, 0.5f), true), 0.0f);
    cr_expect_eq(pattern_checker(v3(-0.5f, 0.5f, 0.5f), true), 1.0f);
    /* A floor at y = 0 lands in one layer whatever the rounding of y. */
    for (int i = 0; i < 100; i++) {
        float x = 0.1f + 0.37f * (float)i;
        cr_expect_eq(pattern_checker(v3(x, 1e-6f, 0.3f), true),
                     pattern_checker(v3(x, -1e-6f, 0.3f), true), "at x = %g", x);
    }
    cr_expect_eq(pattern_checker(v3(0.5f, 1.5f, 0), false), 1.0f); /* on (u, v) */

    cr_expect_eq(pattern_stripes(v3(0.5f, 7, 7), true), 0.0f);
    cr_expect_eq(pattern_stripes(v3(1.5f, -3, 2), true), 1.0f);
    cr_expect_eq(pattern_stripes(v3(-0.5f, 0, 0), true), 1.0f);
    cr_expect_eq(pattern_rings(v3(0.3f, 0.4f, 9), true), 0.0f);  /* r = 0.5 */
    cr_expect_eq(pattern_rings(v3(0.9f, 1.2f, -9), true), 1.0f); /* r = 1.5 */
    cr_expect_eq(pattern_rings(v3(1.5f, 2.0f, 0), true), 0.0f);  /* r = 2.5 */
    ASSERT_NEAR(pattern_gradient(v3(0.25f, 5, 5)), 0.25, TOL);
    ASSERT_NEAR(pattern_gradient(v3(1.75f, 0, 0)), 0.75, TOL);
    ASSERT_NEAR(pattern_gradient(v3(-0.25f, 0, 0)), 0.75, TOL);

    pattern_noise flat = {6, 2.0f, 0.5f, 0.0f};
    ASSERT_NEAR(pattern_marble(v3(0, 3, 4), &flat), 0.5, TOL);
    ASSERT_NEAR(pattern_marble(v3(0.5f, 3, 4), &flat), 1.0, TOL);
    ASSERT_NEAR(pattern_marble(v3(1.5f, 3, 4), &flat), 0.0, TOL);
    ASSERT_NEAR(pattern_wood(v3(0, 0, 5), &flat), 0.0, TOL);
    ASSERT_NEAR(pattern_wood(v3(0.3f, 0.4f, 5), &flat), 1.0, 1e-5); /* r = 0.5 */
    ASSERT_NEAR(pattern_wood(v3(0, 1.25f, 0), &flat), 0.5, 1e-5);   /* r = 1.25 */
}

Test(pattern, perlin_noise_is_bounded_smooth_and_deterministic)
{
    float lo = 1.0f, hi = -1.0f;
    pattern_noise pn = {6, 2.0f, 0.5f, 1.0f};
    for (uint32_t i = 0; i < 20000; i++) {
        uint32_t h = hash_u32(i);
        vec3 q = v3(100.0f * hash_unit(h) - 50.0f, 100.0f * hash_unit(hash_u32(h)) - 50.0f,
                    100.0f * hash_unit(hash_u32(h + 1)) - 50.0f);
        float n = pattern_perlin(q);
        cr_assert(n >= -1.0f && n <= 1.0f, "noise %g at (%g, %g, %g)", n, q.x, q.y, q.z);
        cr_assert_eq(n, pattern_perlin(q), "the same point gives the same value");
        lo = fminf(lo, n);
        hi = fmaxf(hi, n);
        float t = pattern_turbulence(q, &pn);
        cr_assert(t >= 0.0f && t <= 1.0f, "turbulence %g", t);
        /* continuous: a step of 1e-3 changes it by little */
        cr_assert_leq(fabsf(pattern_perlin(v3_add(q, v3s(1e-3f))) - n), 0.01f);
    }
    cr_expect_lt(lo, -0.5f, "noise reaches well below 0 (min %g)", lo);
    cr_expect_gt(hi, 0.5f, "and well above (max %g)", hi);
    ASSERT_NEAR(pattern_perlin(v3(3, -7, 12)), 0.0, TOL); /* lattice points are 0 */
    ASSERT_NEAR(pattern_noise_value(v3(3, -7, 12)), 0.5, TOL);
    /* Far away it keeps its period of 256 rather than failing. */
    ASSERT_NEAR(pattern_perlin(v3(1e9f, 2.5f, 0.5f)), pattern_perlin(v3(0, 2.5f, 0.5f)), 1e-4);
}

/* glint compiles stb_perlin in (src/shade/pattern.c) instead of linking
 * Debian's libstb, built from the same header: the noise is the same to
 * the bit as the library's, on lattice points, near them and anywhere in
 * the period. */
Test(pattern, perlin_noise_is_libstb_s_to_the_bit)
{
    void *lib = dlopen(GLINT_SONAME_STB, RTLD_NOW | RTLD_LOCAL);
    cr_assert_not_null(lib, "%s", dlerror());
    float (*noise)(float, float, float, int, int, int);
    *(void **)&noise = dlsym(lib, "stb_perlin_noise3");
    cr_assert_not_null(noise);
    for (uint32_t i = 0; i < 200000; i++) {
        uint32_t h = hash_u32(i);
        float s = i % 4 == 0 ? 1.0f / 4096 : 256.0f; /* near a lattice point or anywhere */
        vec3 q = v3(s * hash_unit(h), s * hash_unit(hash_u32(h)), s * hash_unit(hash_u32(h + 1)));
        if (i % 4 == 0)
            q = v3_add(q, v3((float)(h % 256), (float)(h / 256 % 256), (float)(h / 65536 % 256)));
        if (!(q.x < 256.0f && q.y < 256.0f && q.z < 256.0f))
            continue;
        float want = noise(q.x, q.y, q.z, 0, 0, 0);
        want = want < -1.0f ? -1.0f : want > 1.0f ? 1.0f : want;
        float got = pattern_perlin(q);
        cr_assert(memcmp(&got, &want, sizeof got) == 0, "%a against libstb's %a at (%a, %a, %a)",
                  (double)got, (double)want, (double)q.x, (double)q.y, (double)q.z);
    }
    dlclose(lib);
}

Test(pattern, color_map_interpolates_between_stops)
{
    color_map m = {3, {0.0f, 0.5f, 1.0f}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    ASSERT_V3_NEAR(color_map_eval(&m, -1), 1, 0, 0, 0);
    ASSERT_V3_NEAR(color_map_eval(&m, 0.25f), 0.5, 0.5, 0, TOL);
    ASSERT_V3_NEAR(color_map_eval(&m, 0.5f), 0, 1, 0, TOL);
    ASSERT_V3_NEAR(color_map_eval(&m, 0.875f), 0, 0.25, 0.75, TOL);
    ASSERT_V3_NEAR(color_map_eval(&m, 2), 0, 0, 1, 0);
    color_map one = {1, {0.3f}, {{0.2f, 0.4f, 0.6f}}};
    ASSERT_V3_NEAR(color_map_eval(&one, 0.9f), 0.2, 0.4, 0.6, 1e-7);
}

Test(pattern, mapping_uv_at_known_points)
{
    float u, v;
    vec3 n = v3(0, 0, 1);
    texture_map(MAPPING_PLANAR, 2, v3(0, 0, 0), n, &u, &v);
    cr_expect(u == 0.5f && v == 0.5f, "planar z centre: %g %g", u, v);
    texture_map(MAPPING_PLANAR, 2, v3(0.25f, -0.5f, 3), n, &u, &v);
    cr_expect(u == 0.75f && v == 0.0f, "planar z: %g %g", u, v);
    texture_map(MAPPING_PLANAR, 1, v3(0.5f, 7, -0.5f), n, &u, &v);
    cr_expect(u == 1.0f && v == 1.0f, "planar y (far side up): %g %g", u, v);
    texture_map(MAPPING_PLANAR, 0, v3(3, 0.2f, 0.5f), n, &u, &v);
    cr_expect(u == 0.0f && fabsf(v - 0.7f) < 1e-6f, "planar x: %g %g", u, v);

    texture_map(MAPPING_SPHERICAL, 0, v3(0, 0, 2), n, &u, &v);
    cr_expect(u == 0.5f && v == 0.5f, "spherical +z: %g %g", u, v);
    texture_map(MAPPING_SPHERICAL, 0, v3(2, 0, 0), n, &u, &v);
    ASSERT_NEAR(u, 0.75, TOL);
    texture_map(MAPPING_SPHERICAL, 0, v3(0, 3, 0), n, &u, &v);
    ASSERT_NEAR(v, 1.0, TOL);
    texture_map(MAPPING_SPHERICAL, 0, v3(0, 1, 1), n, &u, &v);
    ASSERT_NEAR(v, 0.75, TOL);

    texture_map(MAPPING_CYLINDRICAL, 0, v3(-1, 0.3f, 0), n, &u, &v);
    ASSERT_NEAR(u, 0.25, TOL);
    ASSERT_NEAR(v, 0.8, TOL);

    /* Box: each face from outside. */
    texture_map(MAPPING_BOX, 0, v3(0.5f, 0.2f, -0.3f), v3(1, 0.1f, 0), &u, &v);
    ASSERT_NEAR(u, 0.8, TOL);
    ASSERT_NEAR(v, 0.7, TOL);
    texture_map(MAPPING_BOX, 0, v3(-0.5f, 0.2f, -0.3f), v3(-1, 0, 0), &u, &v);
    ASSERT_NEAR(u, 0.2, TOL);
    texture_map(MAPPING_BOX, 0, v3(0.2f, 0.5f, 0.4f), v3(0, 1, 0), &u, &v);
    ASSERT_NEAR(u, 0.7, TOL);
    ASSERT_NEAR(v, 0.1, TOL);
    texture_map(MAPPING_BOX, 0, v3(0.2f, -0.5f, 0.4f), v3(0, -1, 0), &u, &v);
    ASSERT_NEAR(v, 0.9, TOL);
    texture_map(MAPPING_BOX, 0, v3(0.3f, 0.1f, 0.5f), v3(0, 0, 1), &u, &v);
    ASSERT_NEAR(u, 0.8, TOL);
    texture_map(MAPPING_BOX, 0, v3(0.3f, 0.1f, -0.5f), v3(0, 0, -1), &u, &v);
    ASSERT_NEAR(u, 0.2, TOL);
    ASSERT_NEAR(v, 0.6, TOL);
}

Test(pattern, spherical_mapping_on_a_sphere_is_its_uv)
{
    /* On a sphere away from the origin, object space starts at its centre,
     * so the spherical map gives the sphere's own (u, v) everywhere. */
    scene *s = scene_new();
    material m = material_default();
    scene_add_material(s, &m);
    shape sp = shape_sphere(v3(4, -2, 7), 1.5f);
    scene_add_object(s, &sp, 0, -1);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
    for (uint32_t i = 0; i < 200; i++) {
        vec3 d = v3(hash_unit(hash_u32(3 * i)) - 0.5f, hash_unit(hash_u32(3 * i + 1)) - 0.5f,
                    hash_unit(hash_u32(3 * i + 2)) - 0.5f);
        d = v3_norm(d);
        surface sf;
        sphere_surface(&sp.sphere, v3_madd(sp.sphere.center, d, 1.5f), &sf);
        vec3 po, no;
        scene_object_point(s, 0, sf.p, sf.n, &po, &no);
        float u, v;
        texture_map(MAPPING_SPHERICAL, 0, po, no, &u, &v);
        if (fabsf(sf.u - u) > 0.5f) /* the seam: 0 and 1 are the same longitude */
            u += sf.u > u ? 1.0f : -1.0f;
        ASSERT_NEAR(u, sf.u, 1e-4);
        ASSERT_NEAR(v, sf.v, 1e-4);
    }
    scene_free(s);
}

Test(pattern, texture_space_transform_and_scale)
{
    texture t = texture_pattern(TEXTURE_GRADIENT);
    texture_point tp = {v3(0.1f, 0, 0), v3(0, 1, 0), 0, 0};
    ASSERT_NEAR(texture_value(&t, NULL, NULL, &tp), 0.1, TOL);
    t.scale = v3s(2.0f); /* twice as fine */
    ASSERT_NEAR(texture_value(&t, NULL, NULL, &tp), 0.2, TOL);
    t.has_xform = true; /* the pattern moved by +0.05 along x */
    t.xf = xform_translate(v3(0.05f, 0, 0));
    ASSERT_NEAR(texture_value(&t, NULL, NULL, &tp), 0.1, 1e-5);
    /* The gradient of the ramp is scale along x. */
    t.has_xform = false;
    vec3 g = texture_gradient(&t, NULL, NULL, &tp);
    ASSERT_V3_NEAR(g, 2.0, 0.0, 0.0, 1e-2);
    /* A checker's colours come from its map. */
    texture c = texture_checker(v3(1, 0, 0), v3(0, 0, 1), 2, 2);
    texture_point at = {v3s(0), v3s(0), 0.75f, 0.25f};
    ASSERT_V3_NEAR(texture_eval(&c, NULL, NULL, &at), 0, 0, 1, 0);
}

/* ---- the scene format --------------------------------------------------- */

static scene *load_ok(const char *text)
{
    scene *s = NULL;
    glint_error err = {0};
    glint_rc rc = scene_load_text(text, strlen(text), "scene.yaml", GLINT_SOURCE_DIR "/scenes",
                                  NULL, NULL, &s, &err);
    cr_assert_eq(rc, GLINT_OK, "%s", err.msg);
    return s;
}

static void expect_error(const char *text, const char *message)
{
    scene *s = NULL;
    glint_error err = {0};
    glint_rc rc = scene_load_text(text, strlen(text), "scene.yaml", GLINT_SOURCE_DIR "/scenes",
                                  NULL, NULL, &s, &err);
    cr_expect_eq(rc, GLINT_ERR_INPUT, "rc %d for:\n%s", rc, text);
    cr_expect_str_eq(err.msg, message, "\n got: %s\nwant: %s", err.msg, message);
    if (rc == GLINT_OK)
        scene_free(s);
}

Test(format, lights_materials_textures_and_fog_load)
{
    scene *s = load_ok(
        "fog: {type: linear, color: [0.5, 0.6, 0.7], start: 2, end: 30, height_falloff: 0.1}\n"
        "lights:\n"
        "  - {type: point, position: [0, 5, 0], attenuation: [1, 0.1, 0.01]}\n"
        "  - {type: directional, direction: [0, -2, 0], color: 0.5}\n"
        "  - {type: spot, position: [0, 5, 0], look_at: [0, 0, 0], outer_angle: 40}\n"
        "  - {type: area, position: [0, 5, 0], edge_u: [1, 0, 0], edge_v: [0, 0, 1]}\n"
        "textures:\n"
        "  w: {type: wood, scale: [1, 2, 3], transform: [rotate_y: 90], octaves: 3}\n"
        "  g: {type: image, file: textures/globe.png, mapping: planar, axis: y, space: world}\n"
        "materials:\n"
        "  m: {texture: w, absorption: [0.1, 0.2, 0.3], emission: 0.5, fresnel: false,\n"
        "      bump: {pattern: w, strength: -0.5}}\n"
        "objects: [{type: sphere, center: [0, 0, 0], radius: 1, material: m}]\n");
    cr_assert_eq(s->nlights, 4);
    cr_expect_eq(s->lights[0].kind, LIGHT_POINT);
    ASSERT_V3_NEAR(s->lights[0].point.attenuation, 1, 0.1, 0.01, 1e-7);
    ASSERT_V3_NEAR(s->lights[1].directional.direction, 0, -1, 0, 0);
    ASSERT_NEAR(s->lights[2].spot.cos_inner, cos(20 * M_PI / 180), 1e-6);
    ASSERT_NEAR(s->lights[2].spot.cos_outer, cos(40 * M_PI / 180), 1e-6);
    cr_expect_eq(light_sample_count(&s->lights[3]), 16, "area samples default to 4 x 4");
    cr_expect_eq(s->fog.kind, FOG_LINEAR);
    ASSERT_NEAR(s->fog.end, 30, 0);
    const material *m = &s->materials[0];
    cr_expect_eq(m->fresnel, false);
    ASSERT_NEAR(m->bump_strength, -0.5, 0);
    cr_expect_eq(m->bump, m->texture);
    const texture *w = &s->textures[m->texture];
    cr_expect_eq(w->kind, TEXTURE_WOOD);
    cr_expect_eq(w->space, SPACE_OBJECT);
    ASSERT_V3_NEAR(w->scale, 1, 2, 3, 0);
    cr_expect(w->has_xform);
    cr_expect_eq(w->pattern.noise.octaves, 3);
    const texture *g = &s->textures[1];
    cr_expect_eq(g->image.mapping, MAPPING_PLANAR);
    cr_expect_eq(g->image.axis, 1);
    cr_expect_eq(g->space, SPACE_WORLD);
    scene_free(s);
}

Test(format, bad_lights_textures_materials_and_fog)
{
    expect_error("lights: [{type: spot, position: [0, 0, 0], look_at: [0, -1, 0], "
                 "inner_angle: 30, outer_angle: 25}]\n",
                 "scene.yaml:1:95: outer_angle (25) must be greater than inner_angle (30)");
    expect_error("lights: [{type: spot, position: [0, 0, 0], look_at: [0, 0, 0]}]\n",
                 "scene.yaml:1:53: look_at must differ from position");
    expect_error("lights: [{type: area, position: [0, 0, 0], edge_u: [1, 0, 0], "
                 "edge_v: [2, 0, 0]}]\n",
                 "scene.yaml:1:71: edge_v must not be parallel to edge_u");
    expect_error("lights: [{type: area, position: [0, 0, 0], edge_u: [1, 0, 0], "
                 "edge_v: [0, 1, 0], samples: 0}]\n",
                 "scene.yaml:1:91: samples must be 1 to 64 (got 0)");
    expect_error("lights: [{type: point, position: [0, 0, 0], attenuation: [0, 0, 0]}]\n",
                 "scene.yaml:1:58: attenuation must not be [0, 0, 0] (use [1, 0, 0] for none)");
    expect_error("lights: [{type: directional, position: [0, 0, 0]}]\n",
                 "scene.yaml:1:30: unknown key 'position' in directional light (valid: type, "
                 "direction, color)");
    expect_error("fog: {type: exponential, color: 1}\n",
                 "scene.yaml:1:6: exponential fog needs 'density'");
    expect_error("fog: {type: linear, start: 5, end: 5}\n",
                 "scene.yaml:1:36: end (5) must be greater than start (5)");
    expect_error("fog: {type: linear, end: 5, density: 1}\n",
                 "scene.yaml:1:29: unknown key 'density' in linear fog (valid: type, color, "
                 "start, end, height_falloff)");
    expect_error("textures: {t: {type: noise, colors: [[0.5, 1], [0.2, 0]]}}\n",
                 "scene.yaml:1:49: colors must be in ascending order of value (0.2 after 0.5)");
    expect_error("textures: {t: {type: checker, even: 1, colors: [[0, 1]]}}\n",
                 "scene.yaml:1:37: a checker takes even and odd or colors, not both");
    expect_error("textures: {t: {type: image, file: textures/globe.png, space: object}}\n",
                 "scene.yaml:1:62: an image with mapping uv is on (u, v); space object or "
                 "world needs mapping planar, spherical, cylindrical or box");
    expect_error("textures: {t: {type: image, file: textures/globe.png, mapping: box, "
                 "axis: x}}\n",
                 "scene.yaml:1:75: axis is for mapping planar only");
    expect_error("textures: {t: {type: marble, scale: [1, 2]}}\n",
                 "scene.yaml:1:37: expected 3 numbers for 'scale', got 2");
    expect_error("textures: {t: {type: checker}}\n"
                 "materials: {m: {bump: {pattern: t}}}\n",
                 "scene.yaml:2:33: a bump pattern must be in space object or world (its "
                 "gradient is taken in space), not on (u, v)");
    expect_error("materials: {m: {bump: {pattern: {type: stripes, space: uv}}}}\n",
                 "scene.yaml:1:33: a bump pattern must be in space object or world (its "
                 "gradient is taken in space), not on (u, v)");
    expect_error("materials: {m: {fresnel: 0}}\n",
                 "scene.yaml:1:26: expected true or false for 'fresnel', got a number");
}
