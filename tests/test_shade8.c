/* The packet shading's eight-lane kernels (trace/prepare8.h: prepare;
 * trace/bounce8.h: split, mix, bounce; trace/light8.h: point, start, add,
 * end) against the one-ray code they stand for (trace/whitted.c,
 * trace/lighting.c, trace/shading.h), through whole renders: random
 * scenes whose packets
 * mix objects and materials, with every kind of edge the kernels choose
 * between (a whole shininess raised by squaring, a fractional one left to
 * powf, none; total internal reflection, Fresnel on and off, an ior below
 * one; energy-gaining reflection and tints; absorption, emission, fog; a
 * camera inside glass; a bailout met exactly), render the same bytes on
 * every path this CPU has as on the scalar one, which traces one ray at a
 * time, with as many secondary and shadow rays. A failure names the seed,
 * the path and the first pixel that differs, and describes the scene on
 * stderr. GLINT_SHADE8_SEEDS=n runs scenes 1 to n instead of 1 to 24. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "accel/isa.h"
#include "core/rng.h"
#include "geom/csg.h"
#include "glint.h"
#include "scene/camera.h"
#include "scene/scene.h"

static float uniform(rng *g, float lo, float hi) { return lo + (hi - lo) * rng_float(g); }

/* 0 to n - 1. */
static int pick(rng *g, int n) { return (int)(rng_float(g) * (float)n) % n; }

static bool chance(rng *g, float p) { return rng_float(g) < p; }

static vec3 random_color(rng *g, float lo, float hi)
{
    return v3(uniform(g, lo, hi), uniform(g, lo, hi), uniform(g, lo, hi));
}

/* A shininess: a whole one (1 to 300, raised by squaring eight lanes at
 * once), one that is not (powf, lane by lane), 0 (powf too), or a large
 * whole one (many squarings, most highlights under 2^-152). */
static float random_shininess(rng *g)
{
    static const float odd[] = {37.5f, 0.5f, 2.25f, 150.7f, 1.5f};
    switch (pick(g, 8)) {
    case 0:
        return 0.0f;
    case 1:
    case 2:
        return odd[pick(g, 5)];
    case 3:
        return pick(g, 2) ? 1.0f : 10000.0f;
    default:
        return (float)(1 + pick(g, 300));
    }
}

/* A tint: white, a colour with components above 1, or with a 0. */
static vec3 random_tint(rng *g)
{
    switch (pick(g, 4)) {
    case 0:
        return v3s(1.0f);
    case 1:
        return v3(uniform(g, 0.8f, 1.6f), uniform(g, 0.3f, 1.3f), uniform(g, 0.5f, 1.4f));
    case 2:
        return v3(uniform(g, 0.2f, 1.0f), 0.0f, uniform(g, 0.4f, 1.2f));
    default:
        return random_color(g, 0.3f, 1.0f);
    }
}

static float random_ior(rng *g)
{
    static const float iors[] = {1.0f, 1.5f, 0.7f, 2.4f};
    return iors[pick(g, 4)];
}

/* A material drawn at random. reflect reaches 1.25 and tints exceed 1,
 * beyond what scene files allow, as the internal API does not refuse
 * them (adc_keep's shares are scaled for such materials). tex, when >=
 * 0, is the first of five textures that a few take (random_scene): two
 * chequers on (u, v), which the kernels look up on quads, one of them so
 * fine that its squares' numbers pass 2^53; stripes in object space,
 * which they leave to the lane-by-lane path, as they leave every
 * textured sphere, box and cylinder; and two images (add_images), which
 * they look up on quads too. */
static material random_material(rng *g, int tex)
{
    material m = material_default();
    m.color = chance(g, 0.15f) ? v3(uniform(g, 0, 1), 0.0f, uniform(g, 0, 1))
                               : random_color(g, 0.05f, 1.0f);
    static const float ambients[] = {0.0f, 0.1f, 0.3f, 1.0f};
    m.ambient = chance(g, 0.5f) ? ambients[pick(g, 4)] : uniform(g, 0.0f, 1.0f);
    static const float diffuses[] = {0.0f, 0.5f, 1.0f, 1.3f};
    m.diffuse = chance(g, 0.5f) ? diffuses[pick(g, 4)] : uniform(g, 0.0f, 1.0f);
    m.specular = chance(g, 0.4f) ? 0.0f : uniform(g, 0.1f, 1.5f);
    m.shininess = random_shininess(g);
    static const float reflects[] = {0.0f, 0.0f, 0.3f, 1.0f, 1.25f};
    m.reflect = chance(g, 0.8f) ? reflects[pick(g, 5)] : uniform(g, 0.0f, 1.0f);
    static const float transmits[] = {0.3f, 0.7f, 1.0f};
    m.transmit = chance(g, 0.5f) ? 0.0f : chance(g, 0.7f) ? transmits[pick(g, 3)]
                                                           : uniform(g, 0.05f, 1.0f);
    m.ior = random_ior(g);
    m.fresnel = chance(g, 0.6f);
    m.tint = random_tint(g);
    if (chance(g, 0.3f))
        m.absorption = v3(uniform(g, 0.0f, 0.4f), uniform(g, 0.0f, 0.2f),
                          chance(g, 0.5f) ? 0.0f : 0.3f);
    if (chance(g, 0.2f))
        m.emission = random_color(g, 0.0f, 0.4f);
    if (tex >= 0 && chance(g, 0.1f))
        m.texture = tex + pick(g, 5);
    return m;
}

/* A sphere with the camera inside it, of glass: hits from behind, total
 * internal reflection where ior < 1 from outside (or > 1 from inside). */
static material inside_glass(rng *g)
{
    material m = random_material(g, -1);
    m.transmit = chance(g, 0.5f) ? 1.0f : uniform(g, 0.3f, 0.95f);
    m.texture = -1;
    return m;
}

/* The material of an object: one of the scene's few shared ones, or one
 * of its own. */
static int object_material(scene *s, rng *g, const int shared[3], int tex)
{
    if (chance(g, 0.55f))
        return shared[pick(g, 3)];
    material m = random_material(g, tex);
    int i = scene_add_material(s, &m);
    cr_assert_geq(i, 0);
    return i;
}

/* A quad's material: object_material's, or in scenes with textures
 * (tex >= 0) often one of its own that takes one of them. */
static int quad_material(scene *s, rng *g, const int shared[3], int tex)
{
    if (tex < 0 || chance(g, 0.5f))
        return object_material(s, g, shared, tex);
    material m = random_material(g, -1);
    m.texture = tex + pick(g, 5);
    int i = scene_add_material(s, &m);
    cr_assert_geq(i, 0);
    return i;
}

/* A turn, stretch and move: a turned object's transform. */
static int random_xform(scene *s, rng *g, vec3 at, bool stretch)
{
    xform r = xform_rotate(v3(uniform(g, -1, 1), uniform(g, 0.2f, 1), uniform(g, -1, 1)),
                           uniform(g, 0, 180));
    xform t = xform_translate(at);
    xform x = xform_then(&r, &t);
    if (stretch) {
        xform sc = xform_scale(v3(uniform(g, 0.6f, 1.4f), uniform(g, 0.6f, 1.4f),
                                  uniform(g, 0.6f, 1.4f)));
        xform y = xform_then(&sc, &x);
        x = y;
    }
    int i = scene_add_xform(s, &x);
    cr_assert_geq(i, 0);
    return i;
}

static vec3 random_place(rng *g)
{
    return v3(uniform(g, -6.5f, 6.5f), uniform(g, -4.0f, 4.5f), uniform(g, -7.0f, 3.0f));
}

/* The scene's three shared materials into shared; returns a bailout
 * that the shares of its rays reach exactly, or -1. In three scenes of
 * ten the first is a mirror, perhaps clear glass too (ior 1: no
 * Fresnel), that may gain energy: a camera ray reflected off it has share
 * w1, and one reflected off it again w2, the bailout then, which
 * adc_keep keeps (it drops shares below the bailout, not at it). */
static float shared_materials(scene *s, rng *g, int shared[3])
{
    float boundary = -1.0f;
    for (int i = 0; i < 3; i++) {
        material m = random_material(g, -1);
        if (i == 0 && chance(g, 0.3f)) {
            m.reflect = uniform(g, 0.6f, 1.25f);
            if (chance(g, 0.5f))
                m.transmit = 0.0f;
            else
                m.transmit = uniform(g, 0.3f, 1.0f), m.ior = 1.0f;
            float gt = m.transmit * v3_max_comp(m.tint), total = fmaxf(m.reflect + gt, 1.0f);
            float w1 = 1.0f * m.reflect / total;
            boundary = w1 * m.reflect / total;
        }
        shared[i] = scene_add_material(s, &m);
        cr_assert_geq(shared[i], 0);
    }
    return boundary;
}

/* A few csg objects: (box & sphere) - a hole (a cylinder, a sphere or a
 * torus), or their union, unturned, moved, or turned and stretched; some
 * leaves turned in the csg's space, and some of their own materials (the
 * kernels prepare the hits on unturned spheres, boxes and cylinders, and
 * leave the others, and textured ones, to the lane-by-lane path). */
static void add_csgs(scene *s, rng *g, const int shared[3], int tex)
{
    for (int i = 0, n = 2 + pick(g, 3); i < n; i++) {
        csg *c = calloc(1, sizeof *c);
        cr_assert_not_null(c);
        float e = uniform(g, 0.4f, 0.9f);
        shape box = shape_box(v3s(-e), v3s(e)), ball = shape_sphere(v3s(0.0f), e * 1.35f);
        int kind = pick(g, 3);
        shape hole = kind == 0   ? shape_cylinder(v3(0, -2, 0), e * 0.5f, 4.0f, chance(g, 0.7f))
                     : kind == 1 ? shape_sphere(v3(0, e, 0), e * 0.6f)
                                 : shape_torus(v3(0, e * 0.8f, 0), e * 0.7f, e * 0.25f);
        xform tilt = xform_rotate(v3(1, 0, 0), uniform(g, 10, 80));
        int mat = object_material(s, g, shared, tex);
        int ball_mat = chance(g, 0.5f) ? mat : object_material(s, g, shared, tex);
        int32_t both[2] = {csg_add_leaf(c, &box, NULL, mat),
                           csg_add_leaf(c, &ball, chance(g, 0.3f) ? &tilt : NULL, ball_mat)};
        int32_t ops[2] = {csg_add_node(c, CSG_INTERSECTION, both, 2),
                          csg_add_leaf(c, &hole, chance(g, 0.3f) ? &tilt : NULL,
                                       object_material(s, g, shared, tex))};
        csg_add_node(c, chance(g, 0.75f) ? CSG_DIFFERENCE : CSG_UNION, ops, 2);
        csg_finish(c);
        cr_assert_geq(scene_add_csg(s, c), 0);
        int x = -1;
        if (chance(g, 0.4f)) {
            xform t = xform_translate(random_place(g));
            x = scene_add_xform(s, &t);
            cr_assert_geq(x, 0);
        } else if (chance(g, 0.6f)) {
            x = random_xform(s, g, random_place(g), chance(g, 0.5f));
        }
        shape sh = shape_csg(c);
        cr_assert_geq(scene_add_object(s, &sh, -1, x), 0);
    }
}

/* Many unturned spheres, so that packets mix objects and materials; a
 * few large ones, which packets meet whole; turned (and stretched)
 * spheres; quads, boxes and cylinders, some turned; turned tori;
 * sometimes a floor and a tilted wall (the surfaces that are plain,
 * shading.h, are prepared eight lanes at once: trace/prepare8.h). */
static void add_shapes(scene *s, rng *g, const int shared[3], int tex)
{
    for (int i = 0, n = 26 + pick(g, 14); i < n; i++) {
        shape b = shape_sphere(random_place(g), uniform(g, 0.35f, 1.7f));
        cr_assert_geq(scene_add_object(s, &b, object_material(s, g, shared, tex), -1), 0);
    }
    for (int i = 0, n = 1 + pick(g, 3); i < n; i++) {
        shape b = shape_sphere(random_place(g), uniform(g, 2.0f, 3.2f));
        cr_assert_geq(scene_add_object(s, &b, object_material(s, g, shared, tex), -1), 0);
    }
    for (int i = 0, n = 2 + pick(g, 4); i < n; i++) {
        shape b = shape_sphere(v3s(0.0f), uniform(g, 0.5f, 1.5f));
        int x = random_xform(s, g, random_place(g), chance(g, 0.6f));
        cr_assert_geq(scene_add_object(s, &b, object_material(s, g, shared, tex), x), 0);
    }
    for (int i = 0, n = 2 + pick(g, 3); i < n; i++) {
        shape q = shape_quad(random_place(g), v3(uniform(g, 1, 4), uniform(g, -1, 1), 0.5f),
                             v3(uniform(g, -0.5f, 0.5f), uniform(g, 1, 3), uniform(g, -1, 1)));
        int x = chance(g, 0.3f) ? random_xform(s, g, v3s(0.0f), false) : -1;
        cr_assert_geq(scene_add_object(s, &q, quad_material(s, g, shared, tex), x), 0);
    }
    for (int i = 0, n = 2 + pick(g, 3); i < n; i++) {
        vec3 lo = random_place(g);
        vec3 hi = v3_add(lo, v3(uniform(g, 0.5f, 2.5f), uniform(g, 0.5f, 2.5f),
                                uniform(g, 0.5f, 2.5f)));
        int x = -1;
        if (chance(g, 0.4f)) { /* about its centre */
            vec3 c = v3_scale(v3_add(lo, hi), 0.5f);
            lo = v3_sub(lo, c), hi = v3_sub(hi, c);
            x = random_xform(s, g, c, false);
        }
        shape b = shape_box(lo, hi);
        cr_assert_geq(scene_add_object(s, &b, object_material(s, g, shared, tex), x), 0);
    }
    for (int i = 0, n = 2 + pick(g, 3); i < n; i++) { /* cylinders, some turned or open */
        shape c = shape_cylinder(random_place(g), uniform(g, 0.3f, 1.2f), uniform(g, 0.5f, 3.0f),
                                 chance(g, 0.7f));
        int x = chance(g, 0.4f) ? random_xform(s, g, v3s(0.0f), chance(g, 0.5f)) : -1;
        cr_assert_geq(scene_add_object(s, &c, object_material(s, g, shared, tex), x), 0);
    }
    for (int i = 0, n = 2 + pick(g, 4); i < n; i++) { /* turned tori, some stretched */
        shape t = shape_torus(v3s(0.0f), uniform(g, 0.6f, 1.6f), uniform(g, 0.15f, 0.5f));
        int x = random_xform(s, g, random_place(g), chance(g, 0.4f));
        cr_assert_geq(scene_add_object(s, &t, object_material(s, g, shared, tex), x), 0);
    }
    if (chance(g, 0.5f)) { /* a plane, which every ray is tested against */
        shape floor = shape_plane(v3(0, -5.5f, 0), v3(0, 1, 0));
        cr_assert_geq(scene_add_object(s, &floor, object_material(s, g, shared, -1), -1), 0);
    }
    if (chance(g, 0.3f)) { /* a tilted one behind, seen from either side */
        shape wall = shape_plane(v3(0, 0, -9.0f), v3_norm(v3(uniform(g, -0.5f, 0.5f), 0.3f, 1.0f)));
        cr_assert_geq(scene_add_object(s, &wall, object_material(s, g, shared, -1), -1), 0);
    }
}

/* The camera, now and then a fisheye (whose packets have idle lanes
 * outside its circle) or orthographic one, inside a glass sphere in a
 * third of the scenes (every camera ray then hits it from behind), whose
 * material half of them share with spheres in view. */
static void add_camera(scene *s, rng *g)
{
    camera c = {.eye = v3(uniform(g, -3, 3), uniform(g, -1, 3), uniform(g, 11, 16)),
                .target = v3(uniform(g, -1, 1), uniform(g, -1, 1), -1.0f),
                .up = v3(0, 1, 0),
                .hfov = uniform(g, 45, 70),
                .projection = CAMERA_PERSPECTIVE};
    if (chance(g, 0.15f))
        c.projection = CAMERA_FISHEYE, c.hfov = uniform(g, 100, 200);
    else if (chance(g, 0.1f))
        c.projection = CAMERA_ORTHOGRAPHIC, c.width = uniform(g, 10, 18);
    if (chance(g, 0.35f)) {
        material glass = inside_glass(g);
        int mg = scene_add_material(s, &glass);
        vec3 off = v3(uniform(g, -0.6f, 0.6f), uniform(g, -0.6f, 0.6f), uniform(g, -0.6f, 0.6f));
        shape around = shape_sphere(v3_add(c.eye, off), uniform(g, 1.5f, 3.0f));
        cr_assert_geq(scene_add_object(s, &around, mg, -1), 0);
        if (chance(g, 0.5f))
            for (int i = 0; i < 3; i++) {
                shape b = shape_sphere(random_place(g), uniform(g, 0.8f, 1.8f));
                cr_assert_geq(scene_add_object(s, &b, mg, -1), 0);
            }
    }
    scene_set_camera(s, &c);
}

/* One or two point lights (light8_point), some among the objects, some
 * fading with distance; now and then a spot, a sun, an area light (lane
 * by lane), and a point light of no colour, which lights no lane. */
static void add_lights(scene *s, rng *g)
{
    for (int i = 0, n = 1 + pick(g, 2); i < n; i++) {
        vec3 at = chance(g, 0.25f) ? random_place(g)
                                   : v3(uniform(g, -12, 12), uniform(g, 6, 14),
                                        uniform(g, -4, 16));
        vec3 att = chance(g, 0.5f) ? v3(1, 0, 0) : v3(0.6f, 0.03f, 0.002f);
        light l = light_point(at, random_color(g, 0.3f, 1.4f), att);
        cr_assert_geq(scene_add_light(s, &l), 0);
    }
    if (chance(g, 0.3f)) {
        light l = light_spot(v3(uniform(g, -8, 8), 12, 10), v3(uniform(g, -2, 2), 0, -2),
                             uniform(g, 8, 15), uniform(g, 20, 35), random_color(g, 0.3f, 1.0f),
                             v3(1, 0, 0));
        cr_assert_geq(scene_add_light(s, &l), 0);
    }
    if (chance(g, 0.3f)) {
        light l = light_directional(v3(uniform(g, -0.5f, 0.5f), -1.0f, uniform(g, -0.6f, 0.2f)),
                                    random_color(g, 0.2f, 0.6f));
        cr_assert_geq(scene_add_light(s, &l), 0);
    }
    if (chance(g, 0.12f)) {
        light l = light_area(v3(uniform(g, -5, 5), 10, 6), v3(3, 0, 0), v3(0, 0, 3), 2,
                             random_color(g, 0.3f, 0.8f), v3(1, 0, 0));
        cr_assert_geq(scene_add_light(s, &l), 0);
    }
    if (chance(g, 0.1f)) {
        light l = light_point(v3(0, 9, 9), v3s(0.0f), v3(1, 0, 0));
        cr_assert_geq(scene_add_light(s, &l), 0);
    }
}

/* Ambient light, background, and fog in a third of the scenes:
 * exponential or linear, some thinning upwards. */
static void add_air(scene *s, rng *g)
{
    scene_set_ambient(s, random_color(g, 0.05f, 0.35f));
    scene_set_background(s, random_color(g, 0.0f, 0.4f));
    if (!chance(g, 0.35f))
        return;
    fog f = {.color = random_color(g, 0.3f, 0.8f)};
    if (chance(g, 0.5f)) {
        f.kind = FOG_EXPONENTIAL;
        f.density = uniform(g, 0.01f, 0.06f);
    } else {
        f.kind = FOG_LINEAR;
        f.start = uniform(g, 0, 8);
        f.end = f.start + uniform(g, 15, 40);
    }
    f.height_falloff = chance(g, 0.4f) ? uniform(g, 0.05f, 0.3f) : 0.0f;
    scene_set_fog(s, &f);
}

/* Textures first to first + 1: two small images, one of stored bytes
 * clamped and one of linear floats repeating, each scaled and moved so
 * that their texels' indices run past both edges (one far enough out,
 * past 1e9, that image_bilinear takes texel (0, 0)). */
static void add_images(scene *s, rng *g, int first)
{
    for (int i = 0; i < 2; i++) {
        image img = {5 + i * 2, 3 + i * 4, NULL, NULL};
        size_t n = (size_t)img.width * (size_t)img.height * 3;
        if (i == 0) {
            img.rgb = malloc(n);
            cr_assert_not_null(img.rgb);
            for (size_t k = 0; k < n; k++)
                img.rgb[k] = (uint8_t)(rng_float(g) * 255.0f);
        } else {
            img.linear = malloc(n * sizeof(float));
            cr_assert_not_null(img.linear);
            for (size_t k = 0; k < n; k++)
                img.linear[k] = uniform(g, 0.0f, 1.5f);
        }
        texture t = texture_image(scene_add_image(s, &img));
        t.image.wrap_u = i ? WRAP_REPEAT : WRAP_CLAMP;
        t.image.wrap_v = t.image.wrap_u;
        t.scale = i ? v3(2.5f, -1.5f, 1.0f) : v3(1.3f, 2e9f, 1.0f);
        t.offset = v3(-0.2f, 0.35f, 0.0f);
        cr_assert_eq(scene_add_texture(s, &t), first + i);
    }
}

/* Seeds from here on (few_glass_render_the_same_on_every_path) give
 * scenes whose only transmitting objects are a few unturned spheres. */
#define FEW_GLASS 1000

/* Every material made opaque but that of a glass sphere round the camera
 * (add_camera), then two to four glass spheres of their own, some
 * overlapping, some absorbing, some with tints that take a colour out:
 * at most eight transmitting spheres, whose shadow rays that cross one
 * of them only are filtered without their crossings listed
 * (trace/lighting.c), the others as scene_shadow finds them. */
static void few_glass(scene *s, rng *g)
{
    int keep = -1;
    for (int i = 0; i < s->nobjects; i++) {
        const object *o = &s->objects[i];
        if (o->shape.kind == SHAPE_SPHERE && o->xform < 0 &&
            v3_len(v3_sub(s->camera.eye, o->shape.sphere.center)) < o->shape.sphere.radius)
            keep = o->material;
    }
    for (int i = 0; i < s->nmaterials; i++)
        if (i != keep)
            s->materials[i].transmit = 0.0f;
    vec3 at = random_place(g);
    for (int i = 0, n = 2 + pick(g, 3); i < n; i++) {
        material m = random_material(g, -1);
        m.transmit = uniform(g, 0.3f, 1.0f);
        m.absorption = chance(g, 0.4f) ? v3(uniform(g, 0.0f, 0.5f), 0.0f, 0.2f) : v3s(0.0f);
        int mi = scene_add_material(s, &m);
        cr_assert_geq(mi, 0);
        vec3 c = chance(g, 0.5f) ? v3_add(at, v3(uniform(g, -1, 1), uniform(g, -1, 1), 0.0f))
                                 : random_place(g);
        shape b = shape_sphere(c, uniform(g, 0.8f, 2.2f));
        cr_assert_geq(scene_add_object(s, &b, mi, -1), 0);
    }
}

/* Scene `seed`, built on the active path, with the settings to render it
 * by into *st: 64 x 48, 1 or 4 samples (grid or jitter), depth 6, one
 * thread or two, alpha in a third; adaptive depth control at the
 * default, coarser, none (depth 4 then), or at the boundary
 * shared_materials gives. */
static scene *random_scene(uint64_t seed, glint_settings *st)
{
    rng g = rng_seed(seed, 77);
    scene *s = scene_new();
    cr_assert_not_null(s);
    texture checker = texture_checker(v3(0.9f, 0.2f, 0.1f), v3(0.1f, 0.3f, 0.9f), 8.0f, 4.0f);
    /* its x passes 2^53, where pattern_checker's sum in doubles rounds,
     * and for u above 0.8 overflows to infinity */
    texture fine = texture_checker(v3(0.2f, 0.8f, 0.3f), v3(1.0f, 0.9f, 0.2f), 3e38f, -2.5f);
    fine.offset = v3(1e38f, 0.5f, 3.0f);
    texture stripes = texture_pattern(TEXTURE_STRIPES);
    int tex = -1, shared[3];
    if (chance(&g, 0.5f)) {
        tex = scene_add_texture(s, &checker);
        cr_assert(scene_add_texture(s, &fine) == tex + 1 &&
                  scene_add_texture(s, &stripes) == tex + 2);
        add_images(s, &g, tex + 3);
    }
    float boundary = shared_materials(s, &g, shared);
    add_shapes(s, &g, shared, tex);
    add_csgs(s, &g, shared, tex);
    add_camera(s, &g);
    add_lights(s, &g);
    add_air(s, &g);
    if (seed >= FEW_GLASS)
        few_glass(s, &g);
    glint_error err = {0};
    cr_assert_eq(scene_build(s, &err), GLINT_OK, "seed %llu: %s", (unsigned long long)seed,
                 err.msg);
    glint_scene_settings(s, st, NULL);
    st->width = 64, st->height = 48;
    st->samples = seed % 2 ? 4 : 1;
    st->threads = 1 + (int)(seed / 2 % 2);
    st->alpha = seed % 3 == 0;
    st->sampler = seed % 4 == 3 ? GLINT_SAMPLER_JITTER : GLINT_SAMPLER_GRID;
    st->max_depth = 6;
    switch (boundary >= 0.0f ? -1 : pick(&g, 5)) {
    case -1:
        st->adc_bailout = boundary;
        break;
    case 0:
        st->adc_bailout = 0.03;
        break;
    case 1:
        st->adc_bailout = 0.0, st->max_depth = 4;
        break;
    default:
        break;
    }
    return s;
}

static const char *shape_name(shape_kind k)
{
    return k == SHAPE_SPHERE ? "sphere"
           : k == SHAPE_QUAD ? "quad"
           : k == SHAPE_BOX  ? "box"
           : k == SHAPE_PLANE ? "plane"
           : k == SHAPE_TORUS ? "torus"
           : k == SHAPE_CYLINDER ? "cylinder"
           : k == SHAPE_CSG ? "csg"
                              : "other";
}

/* What a failing scene holds, on stderr, and which object the pixel's
 * centre ray meets first. */
static void describe(uint64_t seed, const scene *s, const glint_settings *st, int px, int py)
{
    fprintf(stderr, "shade8: seed %llu: %d x %d, samples %d, depth %d, threads %d, bailout %g, "
                    "%s, alpha %d\n",
            (unsigned long long)seed, st->width, st->height, st->samples, st->max_depth,
            st->threads, st->adc_bailout, st->sampler == GLINT_SAMPLER_JITTER ? "jitter" : "grid",
            st->alpha);
    const camera *c = &s->camera;
    fprintf(stderr, "  camera eye (%g %g %g) target (%g %g %g) hfov %g projection %d; fog %d\n",
            (double)c->eye.x, (double)c->eye.y, (double)c->eye.z, (double)c->target.x,
            (double)c->target.y, (double)c->target.z, (double)c->hfov, (int)c->projection,
            (int)s->fog.kind);
    for (int i = 0; i < s->nlights; i++)
        fprintf(stderr, "  light %d: kind %d colour (%g %g %g)\n", i, (int)s->lights[i].kind,
                (double)s->lights[i].color.x, (double)s->lights[i].color.y,
                (double)s->lights[i].color.z);
    camera_frame f = camera_frame_make(c, st->width, st->height);
    ray r;
    scene_hit h;
    if (camera_ray(&f, (float)px + 0.5f, (float)py + 0.5f, 0.5f, 0.5f, &r) &&
        scene_intersect(s, &r, &h)) {
        const object *o = &s->objects[h.object];
        const material *m = &s->materials[o->material];
        fprintf(stderr,
                "  pixel (%d, %d) centre meets object %d, %s%s, t %g, material %d: colour (%g %g "
                "%g) ambient %g diffuse %g specular %g shininess %g reflect %g transmit %g ior %g "
                "fresnel %d tint (%g %g %g) absorption (%g %g %g) emission (%g %g %g) texture "
                "%d\n",
                px, py, h.object, shape_name(o->shape.kind), o->xform >= 0 ? " (turned)" : "",
                (double)h.h.t, o->material, (double)m->color.x, (double)m->color.y,
                (double)m->color.z, (double)m->ambient, (double)m->diffuse, (double)m->specular,
                (double)m->shininess, (double)m->reflect, (double)m->transmit, (double)m->ior,
                m->fresnel, (double)m->tint.x, (double)m->tint.y, (double)m->tint.z,
                (double)m->absorption.x, (double)m->absorption.y, (double)m->absorption.z,
                (double)m->emission.x, (double)m->emission.y, (double)m->emission.z, m->texture);
    } else {
        fprintf(stderr, "  pixel (%d, %d) centre meets nothing\n", px, py);
    }
}

/* The first float of n where a and b differ in their bytes, or -1. */
static long first_difference(const float *a, const float *b, long n, long *count)
{
    long first = -1;
    *count = 0;
    for (long i = 0; i < n; i++)
        if (memcmp(&a[i], &b[i], sizeof *a) != 0) {
            if (first < 0)
                first = i;
            ++*count;
        }
    return first;
}

/* Scene `seed` on every path this CPU has: the film (rgb, and alpha when
 * asked for) the same bytes as the scalar path's, and as many secondary
 * and shadow rays traced. Returns the number of paths whose film
 * differed. */
static int same_film_on_every_path(uint64_t seed)
{
    glint_film ref = {0};
    glint_stats ref_stats = {0};
    int failed = 0;
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        glint_settings st;
        scene *s = random_scene(seed, &st);
        if (path >= ACCEL_AVX2) /* camera rays in packets: the kernels shade them */
            cr_assert(scene_packets_pay(s), "seed %llu, %s: no packets",
                      (unsigned long long)seed, accel_isa_name((accel_isa)path));
        glint_error err = {0};
        glint_film film = {0};
        glint_stats stats;
        cr_assert_eq(glint_render(s, &st, NULL, &film, &stats, &err), GLINT_OK, "seed %llu: %s",
                     (unsigned long long)seed, err.msg);
        cr_assert_eq(film.alpha != NULL, st.alpha != 0);
        if (!ref.rgb) {
            ref = film;
            ref_stats = stats;
            scene_free(s);
            continue;
        }
        /* the same trees of rays: adaptive depth control kept the same
         * secondary rays, and the same shadow rays were cast */
        cr_expect(stats.secondary_rays == ref_stats.secondary_rays &&
                      stats.shadow_rays == ref_stats.shadow_rays,
                  "seed %llu, %s: %llu secondary and %llu shadow rays against scalar's %llu and "
                  "%llu",
                  (unsigned long long)seed, accel_isa_name((accel_isa)path),
                  (unsigned long long)stats.secondary_rays, (unsigned long long)stats.shadow_rays,
                  (unsigned long long)ref_stats.secondary_rays,
                  (unsigned long long)ref_stats.shadow_rays);
        long n = (long)st.width * st.height, count, count_a = 0;
        long at = first_difference(ref.rgb, film.rgb, 3 * n, &count);
        long at_a = st.alpha ? first_difference(ref.alpha, film.alpha, n, &count_a) : -1;
        if (at >= 0 || at_a >= 0) {
            long px = at >= 0 ? at / 3 : at_a;
            int x = (int)(px % st.width), y = (int)(px / st.width);
            failed++;
            cr_expect_fail("seed %llu, %s: %ld floats of rgb and %ld of alpha differ from "
                           "scalar's; the first at pixel (%d, %d) channel %ld: %a (%.9g) "
                           "against scalar's %a (%.9g)",
                           (unsigned long long)seed, accel_isa_name((accel_isa)path), count,
                           count_a, x, y, at >= 0 ? at % 3 : -1L,
                           at >= 0 ? (double)film.rgb[at] : (double)film.alpha[at_a],
                           at >= 0 ? (double)film.rgb[at] : (double)film.alpha[at_a],
                           at >= 0 ? (double)ref.rgb[at] : (double)ref.alpha[at_a],
                           at >= 0 ? (double)ref.rgb[at] : (double)ref.alpha[at_a]);
            describe(seed, s, &st, x, y);
        }
        glint_film_free(&film);
        scene_free(s);
    }
    glint_film_free(&ref);
    accel_isa_force(ACCEL_AUTO);
    return failed;
}

/* A transmitting csg (clear glass, no absorption) with an opaque,
 * absorbing box among its operands, over a floor, among small spheres
 * that make the camera rays go in packets: the shadow rays through it
 * cross the box too, whose absorption reads the ray (a packet's filter
 * once took the ray as not needed there, and crashed); every path
 * renders the scalar path's bytes. */
Test(shade8, absorbing_opaque_part_of_a_glass_csg)
{
    glint_film ref = {0};
    for (int path = ACCEL_SCALAR; path <= ACCEL_AVX512; path++) {
        if (accel_isa_force((accel_isa)path) != (accel_isa)path)
            continue;
        scene *s = scene_new();
        cr_assert_not_null(s);
        material floor = material_default(), glass = material_default(), dark = floor;
        glass.transmit = 0.9f, glass.ior = 1.0f;
        dark.color = v3s(0.5f), dark.absorption = v3s(0.5f);
        int mf = scene_add_material(s, &floor), mg = scene_add_material(s, &glass);
        int md = scene_add_material(s, &dark);
        shape ground = shape_plane(v3s(0.0f), v3(0, 1, 0));
        cr_assert_geq(scene_add_object(s, &ground, mf, -1), 0);
        csg *c = calloc(1, sizeof *c);
        cr_assert_not_null(c);
        shape box = shape_box(v3(-2, 3, -2), v3(2, 3.5f, 2));
        shape ball = shape_sphere(v3(3, 1, 0), 0.5f);
        int32_t both[2] = {csg_add_leaf(c, &box, NULL, md), csg_add_leaf(c, &ball, NULL, mg)};
        csg_add_node(c, CSG_UNION, both, 2);
        csg_finish(c);
        cr_assert_geq(scene_add_csg(s, c), 0);
        shape sh = shape_csg(c);
        cr_assert_geq(scene_add_object(s, &sh, -1, -1), 0);
        for (int i = 0; i < 20; i++) {
            shape b = shape_sphere(v3(-6.0f + 0.6f * (float)i, 0.2f, -4), 0.2f);
            cr_assert_geq(scene_add_object(s, &b, mf, -1), 0);
        }
        light l = light_point(v3(0, 8, 0), v3s(1.0f), v3(1, 0, 0));
        cr_assert_geq(scene_add_light(s, &l), 0);
        camera cam = {.eye = v3(0, 3, 8), .target = v3s(0.0f), .up = v3(0, 1, 0), .hfov = 50,
                      .projection = CAMERA_PERSPECTIVE};
        scene_set_camera(s, &cam);
        glint_error err = {0};
        cr_assert_eq(scene_build(s, &err), GLINT_OK, "%s", err.msg);
        glint_settings st;
        glint_scene_settings(s, &st, NULL);
        st.width = 64, st.height = 64, st.samples = 1, st.max_depth = 3, st.threads = 1;
        glint_film film = {0};
        cr_assert_eq(glint_render(s, &st, NULL, &film, NULL, &err), GLINT_OK, "%s", err.msg);
        if (!ref.rgb) {
            ref = film;
        } else {
            long count, at = first_difference(ref.rgb, film.rgb, 3L * 64 * 64, &count);
            cr_expect_eq(at, -1, "%s: %ld floats differ from the scalar path's, the first %ld",
                         accel_isa_name((accel_isa)path), count, at);
            glint_film_free(&film);
        }
        scene_free(s);
    }
    glint_film_free(&ref);
    accel_isa_force(ACCEL_AUTO);
}

/* Scenes 1 to 24, about 40 ms each on all four paths, optimised; or 1 to
 * GLINT_SHADE8_SEEDS for a longer search. */
Test(shade8, random_materials_render_the_same_on_every_path)
{
    const char *env = getenv("GLINT_SHADE8_SEEDS");
    uint64_t seeds = env && atoi(env) > 0 ? (uint64_t)atoi(env) : 24;
    int failed = 0;
    for (uint64_t seed = 1; seed <= seeds; seed++)
        failed += same_film_on_every_path(seed);
    cr_assert_eq(failed, 0, "%d renders differed from the scalar path's", failed);
}

/* The same with glass only in a few unturned spheres (few_glass): 12
 * scenes, or GLINT_SHADE8_SEEDS. */
Test(shade8, few_glass_spheres_render_the_same_on_every_path)
{
    const char *env = getenv("GLINT_SHADE8_SEEDS");
    uint64_t seeds = env && atoi(env) > 0 ? (uint64_t)atoi(env) : 12;
    int failed = 0;
    for (uint64_t seed = FEW_GLASS; seed < FEW_GLASS + seeds; seed++)
        failed += same_film_on_every_path(seed);
    cr_assert_eq(failed, 0, "%d renders differed from the scalar path's", failed);
}
