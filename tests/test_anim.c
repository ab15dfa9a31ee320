/* Animation: tracks and their interpolation (scene/anim.h), keyed values
 * in scene files, scenes set to a time, moving objects and their bounds
 * over the shutter interval. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "glint.h"
#include "load/load.h"
#include "near.h"
#include "scene/anim.h"
#include "scene/scene.h"

static float eval1(const anim_track *t, float time)
{
    float v[ANIM_MAX_DIM];
    anim_track_eval(t, time, v);
    return v[0];
}

Test(anim, linear_smooth_and_step_interpolation)
{
    anim a = {0};
    float times[] = {0, 1, 3, 4}, values[] = {0, 10, 30, 0};
    int lin = anim_add_track(&a, ANIM_INTERP_LINEAR, 4, 1, times, values);
    int smo = anim_add_track(&a, ANIM_INTERP_SMOOTH, 4, 1, times, values);
    int stp = anim_add_track(&a, ANIM_INTERP_STEP, 4, 1, times, values);
    cr_assert(lin >= 0 && smo >= 0 && stp >= 0);
    const anim_track *L = &a.tracks[lin], *S = &a.tracks[smo], *T = &a.tracks[stp];
    /* before the first key and after the last: held */
    for (int k = 0; k < 3; k++) {
        ASSERT_NEAR(eval1(&a.tracks[k], -5.0f), 0.0f, 0);
        ASSERT_NEAR(eval1(&a.tracks[k], 9.0f), 0.0f, 0);
    }
    /* at the keys: the keys' values, whatever the interpolation */
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 4; i++)
            ASSERT_NEAR(eval1(&a.tracks[k], times[i]), values[i], 1e-5);
    ASSERT_NEAR(eval1(L, 0.5f), 5.0f, 1e-5);
    ASSERT_NEAR(eval1(L, 2.0f), 20.0f, 1e-5);
    ASSERT_NEAR(eval1(L, 3.75f), 7.5f, 1e-5);
    ASSERT_NEAR(eval1(T, 0.99f), 0.0f, 0);
    ASSERT_NEAR(eval1(T, 2.5f), 10.0f, 0);
    ASSERT_NEAR(eval1(T, 3.0f), 30.0f, 0);
    /* Catmull-Rom between keys 1 and 2 (t 1..3): tangents (30-0)/3 = 10 at
     * t = 1 and (0-10)/3 at t = 3, per second; Hermite at s = 1/2 over a
     * span of 2 s: (p0 + p1)/2 + (m0 - m1) * span / 8 */
    ASSERT_NEAR(eval1(S, 2.0f), 20.0f + (10.0f - (-10.0f / 3.0f)) * 2.0f / 8.0f, 1e-4);
    /* the first span's end tangent is one-sided: (10 - 0) / 1 at t = 0 */
    ASSERT_NEAR(eval1(S, 0.5f), 5.0f + (10.0f - 10.0f) / 8.0f, 1e-4);
    anim_free(&a);
}

Test(anim, vectors_interpolate_per_component)
{
    anim a = {0};
    float times[] = {0, 2}, values[] = {0, 10, -4, 2, 20, 4};
    int t = anim_add_track(&a, ANIM_INTERP_LINEAR, 2, 3, times, values);
    float v[3];
    anim_track_eval(&a.tracks[t], 0.5f, v);
    ASSERT_NEAR(v[0], 0.5, 1e-6);
    ASSERT_NEAR(v[1], 12.5, 1e-6);
    ASSERT_NEAR(v[2], -2.0, 1e-6);
    anim_free(&a);
}

static scene *load_text(const char *text)
{
    scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(scene_load_text(text, strlen(text), "scene.yaml", NULL, NULL, NULL, &s, &err),
                 GLINT_OK, "%s", err.msg);
    return s;
}

static void expect_error(const char *text, const char *message)
{
    scene *s = NULL;
    glint_error err = {0};
    glint_rc rc = scene_load_text(text, strlen(text), "scene.yaml", NULL, NULL, NULL, &s, &err);
    cr_expect_eq(rc, GLINT_ERR_INPUT, "accepted:\n%s", text);
    cr_expect_str_eq(err.msg, message, "\n got: %s\nwant: %s", err.msg, message);
    if (rc == GLINT_OK)
        scene_free(s);
}

static const char animated[] =
    "animation: {frames: 48, fps: 24}\n"
    "camera:\n"
    "  eye: {keys: [[0, [0, 0, 10]], [2, [0, 0, 20]]]}\n"
    "  look_at: [0, 0, 0]\n"
    "  fov: {keys: [[0, 40], [1, 60]], interpolation: step}\n"
    "lights:\n"
    "  - {type: point, position: [0, 5, 0], color: {keys: [[0, 0], [1, [1, 0.5, 0.25]]]}}\n"
    "materials:\n"
    "  m: {color: {keys: [[0, [1, 0, 0]], [2, [0, 0, 1]]]}}\n"
    "objects:\n"
    "  - type: sphere\n"
    "    center: [0, 0, 0]\n"
    "    radius: 1\n"
    "    material: m\n"
    "    transform:\n"
    "      - rotate_y: {keys: [[0, 0], [2, 360]]}\n"
    "      - translate: {keys: [[0, [0, 0, 0]], [2, [4, 0, 0]]]}\n";

/* Each kind of animated value takes its value at the scene's time. */
Test(anim, scenes_take_their_values_at_a_time)
{
    glint_scene *s = load_text(animated);
    glint_animation an;
    glint_error err = {0};
    cr_assert_eq(glint_scene_animation(s, &an, &err), GLINT_OK);
    cr_expect_eq(an.frames, 48);
    ASSERT_NEAR(an.fps, 24, 0);
    ASSERT_NEAR(s->camera.eye.z, 10, 1e-6); /* loaded at frame 1 */
    cr_assert_eq(glint_scene_set_frame(s, 25, &err), GLINT_OK, "%s", err.msg); /* t = 1 s */
    ASSERT_NEAR(s->time, 1.0, 1e-6);
    ASSERT_NEAR(s->camera.eye.z, 15, 1e-5);
    ASSERT_NEAR(s->camera.hfov, 60, 0);
    ASSERT_V3_NEAR(s->lights[0].color, 1, 0.5, 0.25, 1e-6);
    ASSERT_V3_NEAR(s->materials[0].color, 0.5, 0, 0.5, 1e-6);
    /* half a turn about y, then 2 units along x: (1, 0, 0) goes to (1, 0, 0) */
    const xform *x = &s->xforms[s->objects[0].xform];
    vec3 p = mat4_point(&x->fwd, v3(1, 0, 0));
    ASSERT_V3_NEAR(p, 1, 0, 0, 1e-5);
    p = mat4_point(&x->fwd, v3(0, 0, 1));
    ASSERT_V3_NEAR(p, 2, 0, -1, 1e-5);
    cr_expect(!s->objects[0].moving, "no shutter: nothing moves during a frame");
    cr_expect_eq(glint_scene_set_frame(s, 49, &err), GLINT_ERR_INPUT);
    glint_scene_free(s);
}

/* With the shutter open the object's bounds hold it at every time of the
 * interval, and a ray finds it where it is at the ray's time. */
Test(anim, motion_bounds_hold_the_moving_object)
{
    char text[2048];
    snprintf(text, sizeof text, "%s", animated);
    char *cam = strstr(text, "  look_at");
    memmove(cam + 16, cam, strlen(cam) + 1);
    memcpy(cam, "  shutter: 1.0\n\n", 16); /* a whole frame */
    glint_scene *s = load_text(text);
    glint_error err = {0};
    cr_assert_eq(glint_scene_set_frame(s, 7, &err), GLINT_OK, "%s", err.msg);
    const object *o = &s->objects[0];
    cr_assert(o->moving, "the shutter is open");
    ASSERT_NEAR(s->shutter_seconds, 1.0 / 24, 1e-7);
    aabb b = s->bounds[0];
    int n = 0;
    for (int k = 0; k <= 200; k++) {
        float t = s->time + s->shutter_seconds * (float)k / 200;
        xform x = scene_object_xform_at(s, o, t);
        /* points of the unit sphere, moved */
        for (int i = 0; i < 26; i++) {
            float th = (float)i * 0.7f, ph = (float)i * 1.3f;
            vec3 q = mat4_point(&x.fwd, v3(sinf(th) * cosf(ph), cosf(th), sinf(th) * sinf(ph)));
            cr_expect(q.x >= b.lo.x && q.y >= b.lo.y && q.z >= b.lo.z && q.x <= b.hi.x &&
                          q.y <= b.hi.y && q.z <= b.hi.z,
                      "at t %g the point (%g, %g, %g) is outside the bounds", (double)t,
                      (double)q.x, (double)q.y, (double)q.z);
            n++;
        }
        /* a ray down the centre's path finds the sphere at its time */
        vec3 c = mat4_point(&x.fwd, v3(0, 0, 0));
        ray r = ray_make(v3(c.x, 10, c.z), v3(0, -1, 0), INFINITY);
        r.time = t;
        scene_hit hit;
        cr_expect(scene_intersect(s, &r, &hit), "at t %g the ray misses", (double)t);
        cr_expect(fabsf(hit.h.t - 9.0f) < 1e-3f, "at t %g hit at %g", (double)t, (double)hit.h.t);
    }
    cr_expect_eq(n, 201 * 26);
    glint_scene_free(s);
}

Test(anim, animation_block_and_keyed_value_errors)
{
    expect_error("animation: {frames: 0}\n", "scene.yaml:1:21: frames must be 1 to 1000000 (got 0)");
    expect_error("animation: {frames: 10, end: 2}\n",
                 "scene.yaml:1:30: animation takes frames or end, not both");
    expect_error("animation: {fps: 24}\n",
                 "scene.yaml:1:12: animation needs frames (a count) or end (seconds)");
    expect_error("animation: {frame: 2}\n",
                 "scene.yaml:1:13: unknown key 'frame' in animation (did you mean 'frames'?)");
    /* a block of another kind is refused before any key is looked up in it */
    expect_error("animation:\n ot\n or mr:ound a\n",
                 "scene.yaml:2:2: expected a mapping for 'animation', got the string "
                 "'ot or mr:ound a'");
    expect_error("animation: [frames, 2, fps, 3, end, 4]\n",
                 "scene.yaml:1:12: expected a mapping for 'animation', got a sequence");
    expect_error("camera: {eye: {keys: [[1, [0, 0, 1]], [1, [0, 0, 2]]]}}\n",
                 "scene.yaml:1:39: key times must increase (1 s comes after 1 s)");
    expect_error("camera: {eye: {keys: []}}\n",
                 "scene.yaml:1:22: keys needs at least one key [time, value]");
    expect_error("camera: {eye: {keys: [[0, 1]]}}\n",
                 "scene.yaml:1:27: expected [x, y, z] for 'eye', got a number");
    expect_error("camera: {fov: {keys: [[0, 40]], interpolation: cubic}}\n",
                 "scene.yaml:1:48: unknown interpolation 'cubic' (valid: linear, smooth, step)");
    expect_error("camera: {fov: {keys: [[0, 40], [1, 400]]}}\n",
                 "scene.yaml:1:36: fov must be > 0 and < 180 degrees (up to 360 for a fisheye) "
                 "(got 400)");
    expect_error("camera: {shutter: {keys: [[0, 0.5]]}}\n",
                 "scene.yaml:1:19: shutter cannot be keyed");
    expect_error("lights: [{type: point, position: [0, 0, 0], color: {keys: [[0, -1]]}}]\n",
                 "scene.yaml:1:64: color must be >= 0 (got -1)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1, transform: "
                 "[{scale: {keys: [[0, 1], [1, 0]]}}]}]\n",
                 "scene.yaml:1:96: scale must not be 0 (got 0)");
}

/* Opening the shutter through the API makes the keyed object move during
 * the frame, and closing it stops it. */
Test(anim, shutter_set_through_the_api)
{
    glint_scene *s = load_text(animated);
    glint_error err = {0};
    glint_camera cam;
    cr_assert_eq(glint_scene_camera(s, &cam, &err), GLINT_OK);
    cr_expect(!s->objects[0].moving);
    cam.shutter = 0.5;
    cr_assert_eq(glint_scene_set_camera(s, &cam, &err), GLINT_OK, "%s", err.msg);
    cr_expect(s->objects[0].moving, "the shutter is open");
    ASSERT_NEAR(s->shutter_seconds, 0.5 / 24, 1e-7);
    cr_expect(s->built, "the scene is built again");
    cam.shutter = 0;
    cr_assert_eq(glint_scene_set_camera(s, &cam, &err), GLINT_OK, "%s", err.msg);
    cr_expect(!s->objects[0].moving, "the shutter is closed");
    glint_scene_free(s);
}

/* Every kind of light's colour may be keyed, and a material's emission;
 * a texture's transform may not. */
Test(anim, lights_and_materials_of_every_kind)
{
    glint_scene *s = load_text(
        "animation: {frames: 3, fps: 1}\n"
        "lights:\n"
        "  - {type: spot, position: [0, 5, 0], look_at: [0, 0, 0],\n"
        "     color: {keys: [[0, 0], [2, [2, 4, 6]]]}}\n"
        "  - {type: directional, direction: [0, -1, 0], color: {keys: [[1, 1], [2, 0]]}}\n"
        "materials:\n"
        "  m: {emission: {keys: [[0, 0], [2, 1]], interpolation: step}}\n"
        "objects: [{type: sphere, center: [0, 0, 0], radius: 1, material: m}]\n");
    glint_error err = {0};
    cr_assert_eq(glint_scene_set_frame(s, 2, &err), GLINT_OK, "%s", err.msg); /* t = 1 */
    ASSERT_V3_NEAR(s->lights[0].color, 1, 2, 3, 1e-6);
    ASSERT_V3_NEAR(s->lights[1].color, 1, 1, 1, 1e-6);
    ASSERT_V3_NEAR(s->materials[0].emission, 0, 0, 0, 0);
    cr_assert_eq(glint_scene_set_frame(s, 3, &err), GLINT_OK, "%s", err.msg);
    ASSERT_V3_NEAR(s->lights[1].color, 0, 0, 0, 1e-6);
    ASSERT_V3_NEAR(s->materials[0].emission, 1, 1, 1, 0);
    glint_scene_free(s);
    expect_error("textures: {t: {type: checker, transform: [{rotate_z: {keys: [[0, 0]]}}]}}\n",
                 "scene.yaml:1:42: only an object's own transform may be keyed, not this one");
}

Test(anim, light_positions_and_directions)
{
    glint_scene *s = load_text(
        "animation: {frames: 3, fps: 1}\n"
        "lights:\n"
        "  - {type: spot, position: {keys: [[0, [0, 5, 0]], [2, [4, 5, 0]]]},\n"
        "     look_at: {keys: [[0, [0, 0, 0]], [2, [4, 0, 0]]]}}\n"
        "  - {type: area, position: {keys: [[0, [0, 9, 0]], [2, [0, 9, 4]]]},\n"
        "     edge_u: {keys: [[0, [2, 0, 0]], [2, [4, 0, 0]]]}, edge_v: [0, 0, 2]}\n"
        "  - {type: directional, direction: {keys: [[0, [0, -1, 0]], [2, [2, 0, 0]]]}}\n"
        "objects: [{type: sphere, center: [0, 0, 0], radius: 1}]\n");
    glint_error err = {0};
    cr_assert_eq(glint_scene_set_frame(s, 2, &err), GLINT_OK, "%s", err.msg); /* t = 1 */
    ASSERT_V3_NEAR(s->lights[0].spot.position, 2, 5, 0, 1e-6);
    ASSERT_V3_NEAR(s->lights[0].spot.axis, 0, -1, 0, 1e-6);
    /* centre (0, 9, 2), edge_u (3, 0, 0): corner = centre - (3, 0, 2) / 2 */
    ASSERT_V3_NEAR(s->lights[1].area.corner, -1.5, 9, 1, 1e-6);
    ASSERT_V3_NEAR(s->lights[1].area.edge_u, 3, 0, 0, 1e-6);
    /* halfway between (0, -1, 0) and (2, 0, 0), made unit */
    ASSERT_V3_NEAR(s->lights[2].directional.direction, 1 / sqrt(1.25), -0.5 / sqrt(1.25), 0,
                   1e-6);
    cr_assert_eq(glint_scene_set_frame(s, 1, &err), GLINT_OK, "%s", err.msg); /* t = 0 */
    ASSERT_V3_NEAR(s->lights[0].spot.axis, 0, -1, 0, 1e-6);
    ASSERT_V3_NEAR(s->lights[1].area.corner, -1, 9, -1, 1e-6);
    ASSERT_V3_NEAR(s->lights[2].directional.direction, 0, -1, 0, 1e-6);
    glint_scene_free(s);
}
