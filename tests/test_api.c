/* The public API (include/glint.h) as an embedding program uses it: a scene
 * built in code renders to the same bytes as the same scene in YAML; regions
 * and tile lists assemble into the whole image; progress, cancellation from
 * another thread, the camera, and the argument checks of every function. */
#include <criterion/criterion.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "api_test.h"
#include "glint.h"
#include "tmpdir.h"

/* Every shape, every transform step, each kind of material and texture,
 * two lights. */
static const char scene_yaml[] =
    "image: {width: 64, height: 48, samples: 4, depth: 5, background: [0.1, 0.2, 0.3]}\n"
    "camera: {eye: [0, 2, 10], look_at: [0, 0, 0], up: [0, 1, 0], fov: 50}\n"
    "ambient: [0.25, 0.2, 0.2]\n"
    "lights:\n"
    "  - {type: point, position: [5, 8, 6], color: [1, 0.9, 0.8]}\n"
    "  - {type: point, position: [-6, 4, 3], color: 0.4}\n"
    "  - {type: spot, position: [4, 6, -2], look_at: [0, 0, 0], inner_angle: 10, outer_angle: 35,\n"
    "     color: 0.3, attenuation: [1, 0.01, 0.001]}\n"
    "  - {type: area, position: [0, 6, 2], edge_u: [1, 0, 0], edge_v: [0, 0.5, 1], samples: 2,\n"
    "     color: 0.3}\n"
    "  - {type: directional, direction: [1, -1, -1], color: 0.1}\n"
    "materials:\n"
    "  mirror: {color: [0.2, 0.3, 0.9], specular: 1, shininess: 80, reflect: 0.75}\n"
    "  glass: {specular: 1, shininess: 200, transmit: 0.9, ior: 1.5, absorption: [0.1, 0.2, 0.3],\n"
    "          fresnel: false}\n"
    "  clear: {color: [0.9, 0.3, 0.2], transmit: 0.5, tint: [1, 0.5, 0.25], emission: [0.05, 0, 0]}\n"
    "  matte: {color: [0.5, 0.75, 0.25], ambient: 0.5, diffuse: 0.75}\n"
    "  floor: {texture: {type: checker, even: [0.9, 0.9, 0.8], odd: [0.1, 0.2, 0.3], scale: [0.5, 0.25],\n"
    "          offset: [0.5, 0]}}\n"
    "  globe: {specular: 0.5, texture: {type: image, file: " GLINT_SOURCE_DIR "/scenes/textures/globe.png,\n"
    "          wrap: [repeat, clamp], scale: [2, 1]}}\n"
    "objects:\n"
    "  - {type: plane, point: [0, -1, 0], normal: [0, 1, 0], material: floor}\n"
    "  - {type: sphere, center: [-2, 0, 0], radius: 1, material: mirror}\n"
    "  - {type: sphere, center: [3, 1.5, -1], radius: 1, material: globe}\n"
    "  - {type: sphere, center: [1, 0.5, 2], radius: 0.75, material: glass}\n"
    "  - {type: quad, origin: [-3, -1, -3], edge_u: [6, 0, 0], edge_v: [0, 4, 0], material: matte}\n"
    "  - {type: box, min: [-0.5, -1, -0.5], max: [0.5, 0, 0.5], material: clear,\n"
    "     transform: [rotate_y: 30, translate: [2, 0, 0]]}\n"
    "  - {type: cylinder, base: [0, 0, 0], radius: 0.5, height: 1.5, capped: false, material: mirror,\n"
    "     transform: [scale: [1, 0.5, 1], rotate: {axis: [1, 0, 1], angle: 20}, translate: [-1, -1, 2]]}\n"
    "  - {type: triangle, p0: [-3, 2, -2], p1: [-1, 2, -2], p2: [-2, 3.5, -2], material: clear,\n"
    "     transform: [shear: {xy: 0.25}]}\n"
    "  - {type: sphere, center: [0, 0, 0], radius: 1,\n"
    "     transform: [matrix: [0.5, 0, 0, 3,  0, 0.5, 0, 2,  0, 0, 0.5, -1]]}\n"
    "  - {type: mesh, file: tetra.obj, material: mirror, transform: [scale: 1.5, translate: [-3, -1, 1]]}\n"
    "  - {type: mesh, file: tetra.obj, transform: [translate: [2, 1, 3]]}\n";

/* A tetrahedron, written beside the scene. */
static const char tetra_obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

static glint_error err; /* the last call's, for OK and REFUSED */

static int material(glint_scene *s, glint_material m)
{
    int i = -1;
    OK(glint_scene_add_material(s, &m, &i, &err));
    return i;
}

static void object(glint_scene *s, glint_shape shape, int mat, const glint_step *steps, int n)
{
    glint_object o = {shape, mat, steps, n};
    OK(glint_scene_add_object(s, &o, NULL, &err));
}

/* scene_yaml, written in code; the mesh file is in dir. */
static glint_scene *scene_in_code(void)
{
    glint_scene *s = NULL;
    OK(glint_scene_new(&s, &err));
    glint_settings st = {64, 48, 4, 5, 0, GLINT_TRANSFER_NONE, 1.0 / 255,
                         GLINT_SAMPLER_GRID, 0.05, 3, 0};
    OK(glint_scene_set_settings(s, &st, &err));
    glint_camera cam = {{0, 2, 10}, {0, 0, 0}, {0, 1, 0}, 50, 0, 0, GLINT_PROJECTION_PERSPECTIVE, 0, 0};
    OK(glint_scene_set_camera(s, &cam, &err));
    OK(glint_scene_set_background(s, (double[3]){0.1, 0.2, 0.3}, &err));
    OK(glint_scene_set_ambient(s, (double[3]){0.25, 0.2, 0.2}, &err));
    glint_light l1 = {.kind = GLINT_LIGHT_POINT, .position = {5, 8, 6}, .color = {1, 0.9, 0.8}};
    glint_light l2 = {.kind = GLINT_LIGHT_POINT, .position = {-6, 4, 3}, .color = {0.4, 0.4, 0.4}};
    OK(glint_scene_add_light(s, &l1, NULL, &err));
    OK(glint_scene_add_light(s, &l2, NULL, &err));
    glint_light spot = {.kind = GLINT_LIGHT_SPOT, .position = {4, 6, -2}, .look_at = {0, 0, 0},
                         .inner_angle = 10, .outer_angle = 35, .color = {0.3, 0.3, 0.3},
                         .attenuation = {1, 0.01, 0.001}};
    OK(glint_scene_add_light(s, &spot, NULL, &err));
    glint_light area = glint_light_default(GLINT_LIGHT_AREA);
    area.position[1] = 6, area.position[2] = 2, area.samples = 2;
    area.edge_u[0] = 1, area.edge_v[1] = 0.5, area.edge_v[2] = 1;
    area.color[0] = area.color[1] = area.color[2] = 0.3;
    OK(glint_scene_add_light(s, &area, NULL, &err));
    glint_light sun = glint_light_default(GLINT_LIGHT_DIRECTIONAL);
    sun.direction[0] = 1, sun.direction[1] = -1, sun.direction[2] = -1;
    sun.color[0] = sun.color[1] = sun.color[2] = 0.1;
    OK(glint_scene_add_light(s, &sun, NULL, &err));

    glint_material m = glint_material_default();
    m = (glint_material){.color = {0.2, 0.3, 0.9}, .ambient = 1, .diffuse = 1, .specular = 1,
                         .shininess = 80, .reflect = 0.75, .transmit = 0, .ior = 1,
                         .tint = {1, 1, 1}, .texture = -1};
    int mirror = material(s, m);
    m = glint_material_default();
    m.specular = 1, m.shininess = 200, m.transmit = 0.9, m.ior = 1.5;
    m.absorption[0] = 0.1, m.absorption[1] = 0.2, m.absorption[2] = 0.3, m.fresnel_off = 1;
    int glass = material(s, m);
    m = glint_material_default();
    m.color[0] = 0.9, m.color[1] = 0.3, m.color[2] = 0.2, m.transmit = 0.5;
    m.tint[1] = 0.5, m.tint[2] = 0.25, m.emission[0] = 0.05;
    int clear = material(s, m);
    m = glint_material_default();
    m.color[0] = 0.5, m.color[1] = 0.75, m.color[2] = 0.25, m.ambient = 0.5, m.diffuse = 0.75;
    int matte = material(s, m);
    int white = material(s, glint_material_default());
    glint_texture t = glint_texture_default(GLINT_TEXTURE_CHECKER);
    t.even[0] = t.even[1] = 0.9, t.even[2] = 0.8;
    t.odd[0] = 0.1, t.odd[1] = 0.2, t.odd[2] = 0.3;
    t.scale[0] = 0.5, t.scale[1] = 0.25, t.offset[0] = 0.5;
    m = glint_material_default();
    OK(glint_scene_add_texture(s, &t, &m.texture, &err));
    int floor = material(s, m);
    t = glint_texture_default(GLINT_TEXTURE_IMAGE);
    t.file = GLINT_SOURCE_DIR "/scenes/textures/globe.png";
    t.wrap[1] = GLINT_WRAP_CLAMP;
    t.scale[0] = 2;
    m = glint_material_default();
    m.specular = 0.5;
    OK(glint_scene_add_texture(s, &t, &m.texture, &err));
    int globe = material(s, m);

    object(s, (glint_shape){GLINT_SHAPE_PLANE, .plane = {{0, -1, 0}, {0, 1, 0}}}, floor, NULL, 0);
    object(s, (glint_shape){GLINT_SHAPE_SPHERE, .sphere = {{-2, 0, 0}, 1}}, mirror, NULL, 0);
    object(s, (glint_shape){GLINT_SHAPE_SPHERE, .sphere = {{3, 1.5, -1}, 1}}, globe, NULL, 0);
    object(s, (glint_shape){GLINT_SHAPE_SPHERE, .sphere = {{1, 0.5, 2}, 0.75}}, glass, NULL, 0);
    object(s, (glint_shape){GLINT_SHAPE_QUAD, .quad = {{-3, -1, -3}, {6, 0, 0}, {0, 4, 0}}}, matte,
           NULL, 0);
    glint_step box_steps[] = {{GLINT_STEP_ROTATE, {0, 1, 0, 30}},
                              {GLINT_STEP_TRANSLATE, {2, 0, 0}}};
    object(s, (glint_shape){GLINT_SHAPE_BOX, .box = {{-0.5, -1, -0.5}, {0.5, 0, 0.5}}}, clear,
           box_steps, 2);
    glint_step cyl_steps[] = {{GLINT_STEP_SCALE, {1, 0.5, 1}},
                              {GLINT_STEP_ROTATE, {1, 0, 1, 20}},
                              {GLINT_STEP_TRANSLATE, {-1, -1, 2}}};
    object(s, (glint_shape){GLINT_SHAPE_CYLINDER, .cylinder = {{0, 0, 0}, 0.5, 1.5, 0}}, mirror,
           cyl_steps, 3);
    glint_step tri_steps[] = {{GLINT_STEP_SHEAR, {0.25}}};
    object(s, (glint_shape){GLINT_SHAPE_TRIANGLE, .triangle = {{-3, 2, -2}, {-1, 2, -2}, {-2, 3.5, -2}}},
           clear, tri_steps, 1);
    glint_step mat_steps[] = {{GLINT_STEP_MATRIX, {0.5, 0, 0, 3, 0, 0.5, 0, 2, 0, 0, 0.5, -1}}};
    object(s, (glint_shape){GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, 1}}, white, mat_steps, 1);
    char path[128];
    snprintf(path, sizeof path, "%s/tetra.obj", dir);
    int tetra = -1;
    OK(glint_scene_add_mesh(s, path, &tetra, &err));
    glint_step big[] = {{GLINT_STEP_SCALE, {1.5, 1.5, 1.5}}, {GLINT_STEP_TRANSLATE, {-3, -1, 1}}};
    glint_step moved[] = {{GLINT_STEP_TRANSLATE, {2, 1, 3}}};
    object(s, (glint_shape){GLINT_SHAPE_MESH, .mesh = {tetra}}, mirror, big, 2);
    object(s, (glint_shape){GLINT_SHAPE_MESH, .mesh = {tetra}}, -1, moved, 1);
    OK(glint_scene_build(s, &err));
    return s;
}

static glint_scene *scene_from_yaml(void)
{
    char path[128];
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    glint_scene *s = NULL;
    OK(glint_scene_load(path, &s, &err));
    return s;
}

Test(api, scene_in_code_renders_as_the_same_scene_in_yaml)
{
    tmpdir_make("api");
    tmpdir_write("scene.yaml", scene_yaml, NULL, 0);
    tmpdir_write("tetra.obj", tetra_obj, NULL, 0);
    glint_scene *code = scene_in_code(), *yaml = scene_from_yaml();
    tmpdir_remove();
    glint_film a = {0}, b = {0};
    OK(glint_render(code, NULL, NULL, &a, NULL, &err));
    OK(glint_render(yaml, NULL, NULL, &b, NULL, &err));
    cr_assert_eq(a.width, 64);
    test_expect_same_film(&a, &b);
    /* Not a blank picture: the objects are there. */
    int differ = 0;
    for (int i = 3; i < 64 * 48 * 3; i++)
        differ += a.rgb[i] != a.rgb[i % 3];
    cr_expect_gt(differ, 1000);
    glint_film_free(&a);
    glint_film_free(&b);
    glint_scene_free(code);
    glint_scene_free(yaml);
}

/* A small render of the built-in scene for the tests below. */
static glint_scene *builtin(glint_settings *st, int w, int h, int threads)
{
    glint_scene *s = NULL;
    OK(glint_scene_builtin(&s, &err));
    OK(glint_scene_settings(s, st, &err));
    st->width = w;
    st->height = h;
    st->samples = 1;
    st->threads = threads;
    return s;
}

Test(api, regions_and_tile_lists_assemble_into_the_whole_image)
{
    glint_settings st;
    glint_scene *s = builtin(&st, 83, 61, 2);
    glint_film whole = {0}, parts = {0}, tiles = {0};
    OK(glint_render(s, &st, NULL, &whole, NULL, &err));
    /* Four regions whose edges cut through tiles, into one image-sized film. */
    OK(glint_film_alloc(&parts, 83, 61, &err));
    glint_rect quarter[4] = {{0, 0, 37, 29}, {37, 0, 83, 29}, {0, 29, 37, 61}, {37, 29, 83, 61}};
    for (int i = 0; i < 4; i++)
        OK(glint_render_region(s, &st, &quarter[i], NULL, &parts, NULL, &err));
    test_expect_same_film(&whole, &parts);
    /* A region into a region-sized film lands at the film's top left. */
    glint_film small = {0};
    OK(glint_film_alloc(&small, 46, 32, &err));
    OK(glint_render_region(s, &st, &quarter[3], NULL, &small, NULL, &err));
    for (int y = 0; y < 32; y++)
        cr_assert_eq(memcmp(small.rgb + (size_t)y * 46 * 3,
                            whole.rgb + ((size_t)(29 + y) * 83 + 37) * 3, 46 * 3 * sizeof(float)),
                     0, "row %d of the region differs", y);
    /* Every tile, listed in reverse, in two batches. */
    int n = 0;
    OK(glint_tile_count(&st, &n, &err));
    cr_assert_eq(n, 6 * 4);
    int list[24];
    for (int i = 0; i < n; i++)
        list[i] = n - 1 - i;
    OK(glint_film_alloc(&tiles, 83, 61, &err));
    OK(glint_render_tiles(s, &st, list, 10, NULL, &tiles, NULL, &err));
    OK(glint_render_tiles(s, &st, list + 10, n - 10, NULL, &tiles, NULL, &err));
    test_expect_same_film(&whole, &tiles);
    glint_rect r;
    OK(glint_tile_rect(&st, n - 1, &r, &err));
    cr_expect(r.x0 == 80 && r.y0 == 48 && r.x1 == 83 && r.y1 == 61, "last tile cut to the image");
    /* Tiles 10, 11 (row 1) and 16 (row 2) into a film of their bounds:
     * x [64, 83), y [16, 48), pixel (64, 16) at its top left. */
    glint_film box = {0};
    OK(glint_film_alloc(&box, 19, 32, &err));
    int some[3] = {16, 10, 11};
    OK(glint_render_tiles(s, &st, some, 3, NULL, &box, NULL, &err));
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 19; x++) {
            const float *got = box.rgb + ((size_t)y * 19 + (size_t)x) * 3;
            const float *want = whole.rgb + ((size_t)(16 + y) * 83 + (size_t)(64 + x)) * 3;
            bool listed = y < 16 || x < 16; /* tile 17 (x >= 80, y >= 32) is not listed */
            if (listed)
                cr_assert_eq(memcmp(got, want, 3 * sizeof(float)), 0, "pixel (%d, %d)", 64 + x, 16 + y);
            else
                cr_assert(got[0] == 0 && got[1] == 0 && got[2] == 0, "unlisted pixel touched");
        }
    glint_film_free(&box);
    glint_film_free(&whole);
    glint_film_free(&parts);
    glint_film_free(&small);
    glint_film_free(&tiles);
    glint_scene_free(s);
}

typedef struct watch {
    double percent[1024];
    int calls, tiles;
    uint64_t samples_done, samples_total, rays;
    atomic_int started, cancel;
} watch;

static void on_progress(void *user, const glint_progress *p)
{
    watch *w = user;
    if (w->calls < 1024)
        w->percent[w->calls] = p->percent;
    w->calls++;
    w->samples_done = p->samples_done;
    w->samples_total = p->samples_total;
    w->rays = p->rays;
}

static void on_tile(void *user, const glint_film *f, int x0, int y0, int x1, int y1)
{
    (void)f, (void)x0, (void)y0, (void)x1, (void)y1;
    ((watch *)user)->tiles++;
}

Test(api, progress_is_monotone_and_reaches_100)
{
    glint_settings st;
    glint_scene *s = builtin(&st, 100, 70, 2);
    st.samples = 4;
    watch *w = calloc(1, sizeof *w);
    glint_callbacks cb = {.user = w, .tile_done = on_tile, .progress = on_progress};
    glint_film film = {0};
    glint_stats stats;
    OK(glint_render(s, &st, &cb, &film, &stats, &err));
    cr_assert_eq(w->calls, 7 * 5, "one call per tile");
    cr_expect_eq(w->tiles, 7 * 5);
    for (int i = 1; i < w->calls; i++)
        cr_expect_geq(w->percent[i], w->percent[i - 1], "percent went back at call %d", i);
    cr_expect_eq(w->percent[w->calls - 1], 100.0);
    cr_expect_eq(w->samples_done, 100 * 70 * 4);
    cr_expect_eq(w->samples_total, 100 * 70 * 4);
    cr_expect_eq(w->rays, stats.primary_rays + stats.secondary_rays + stats.shadow_rays);
    glint_film_free(&film);
    glint_scene_free(s);
    free(w);
}

static int is_cancelled(void *user) { return atomic_load(&((watch *)user)->cancel); }

/* Holds the first tile's callback until the other thread has cancelled, so
 * the render cannot finish first. */
static void hold_first_tile(void *user, const glint_progress *p)
{
    watch *w = user;
    on_progress(user, p);
    if (w->calls == 1) {
        atomic_store(&w->started, 1);
        while (!atomic_load(&w->cancel))
            sched_yield();
    }
}

static void *canceller(void *user)
{
    watch *w = user;
    while (!atomic_load(&w->started))
        sched_yield();
    atomic_store(&w->cancel, 1);
    return NULL;
}

Test(api, cancellation_from_another_thread_stops_within_a_tile)
{
    glint_settings st;
    glint_scene *s = builtin(&st, 160, 160, 2);
    watch *w = calloc(1, sizeof *w);
    glint_callbacks cb = {.user = w, .progress = hold_first_tile, .cancelled = is_cancelled};
    pthread_t th;
    cr_assert_eq(pthread_create(&th, NULL, canceller, w), 0);
    glint_film film = {0};
    cr_expect_eq(glint_render(s, &st, &cb, &film, NULL, &err), GLINT_ERR_CANCELLED);
    pthread_join(th, NULL);
    cr_expect_eq(err.code, GLINT_ERR_CANCELLED);
    cr_expect_null(film.rgb, "a cancelled glint_render leaves no film");
    /* The tile held and at most one tile in flight per other thread. */
    cr_expect_leq(w->calls, 2, "%d of 100 tiles finished after the cancel", w->calls);
    /* A region render keeps what finished. */
    atomic_store(&w->cancel, 0);
    atomic_store(&w->started, 0);
    w->calls = 0;
    cr_assert_eq(pthread_create(&th, NULL, canceller, w), 0);
    OK(glint_film_alloc(&film, 160, 160, &err));
    glint_rect all = {0, 0, 160, 160};
    cr_expect_eq(glint_render_region(s, &st, &all, &cb, &film, NULL, &err), GLINT_ERR_CANCELLED);
    pthread_join(th, NULL);
    cr_expect_not_null(film.rgb);
    glint_film_free(&film);
    glint_scene_free(s);
    free(w);
}

Test(api, camera_round_trip_and_refusals)
{
    glint_scene *s = NULL;
    OK(glint_scene_new(&s, &err));
    glint_camera c = {{1, 2, 3}, {0, 0.5, -4}, {0, 1, 0}, 35.5, 0, 0, GLINT_PROJECTION_PERSPECTIVE, 0, 0};
    OK(glint_scene_set_camera(s, &c, &err));
    glint_camera got;
    OK(glint_scene_camera(s, &got, &err));
    cr_expect_eq(memcmp(got.eye, c.eye, sizeof c.eye), 0);
    cr_expect_eq(memcmp(got.look_at, c.look_at, sizeof c.look_at), 0);
    cr_expect_eq(memcmp(got.up, c.up, sizeof c.up), 0);
    cr_expect_eq(got.fov, 35.5);
    cr_expect_eq(got.aperture, 0.0);
    cr_expect_eq(got.projection, GLINT_PROJECTION_PERSPECTIVE);
    cr_expect_float_eq(got.focus_distance, sqrt(1 + 2.25 + 49), 1e-5);

    struct { const char *what, *words; glint_camera cam; } bad[] = {
        {"eye == look_at", "differ", {{1, 2, 3}, {1, 2, 3}, {0, 1, 0}, 40, 0, 0, 0, 0, 0}},
        {"fov 0", "fov", {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0, 0, 0, 0, 0, 0}},
        {"fov 180", "fov", {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 180, 0, 0, 0, 0, 0}},
        {"fov NaN", "finite", {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, NAN, 0, 0, 0, 0, 0}},
        {"up parallel", "parallel", {{0, 0, 0}, {0, 0, -1}, {0, 0, 2}, 40, 0, 0, 0, 0, 0}},
        {"up zero", "parallel", {{0, 0, 0}, {0, 0, -1}, {0, 0, 0}, 40, 0, 0, 0, 0, 0}},
        {"aperture", "aperture", {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40, -1, 0, 0, 0, 0}},
        {"shutter", "shutter", {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40, 0, 0, 0, 0, 1.5}},
        {"width", "width", {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40, 0, 0, 1, 0, 0}},
        {"fisheye fov", "fov", {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 361, 0, 0, 3, 0, 0}},
        {"focus", "focus", {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40, 0, -1, 0, 0, 0}},
        {"projection", "projection", {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40, 0, 0, 7, 0, 0}},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        err = (glint_error){0};
        cr_expect_eq(glint_scene_set_camera(s, &bad[i].cam, &err), GLINT_ERR_INPUT, "%s",
                     bad[i].what);
        cr_expect_not_null(strstr(err.msg, bad[i].words), "%s: '%s'", bad[i].what, err.msg);
    }
    OK(glint_scene_camera(s, &got, &err));
    cr_expect_eq(got.fov, 35.5, "a refused camera leaves the last one");
    glint_scene_free(s);
}

Test(api, scene_settings_are_used_when_a_render_gives_none)
{
    glint_settings st;
    glint_scene *s = builtin(&st, 20, 10, 1);
    OK(glint_scene_set_settings(s, &st, &err));
    glint_film film = {0};
    OK(glint_render(s, NULL, NULL, &film, NULL, &err));
    cr_expect(film.width == 20 && film.height == 10);
    glint_film_free(&film);
    st.transfer = (glint_transfer)7;
    cr_expect_eq(glint_scene_set_settings(s, &st, &err), GLINT_ERR_INPUT);
    cr_expect_not_null(strstr(err.msg, "transfer"), "%s", err.msg);
    glint_scene_free(s);
}

Test(api, version) { cr_expect_str_eq(glint_version(), GLINT_VERSION); }

Test(api, null_arguments_are_refused)
{
    glint_settings st;
    glint_scene *s = builtin(&st, 16, 16, 1);
    glint_film film = {0};
    glint_camera cam;
    glint_rect r = {0, 0, 16, 16};
    int n, tiles[1] = {0};
    glint_material m = glint_material_default();
    glint_light l = {.kind = GLINT_LIGHT_POINT, .position = {0, 0, 0}, .color = {1, 1, 1}};
    glint_object o = {{GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, 1}}, 0, NULL, 0};
    double rgb[3] = {0, 0, 0};
    REFUSED(glint_scene_load(NULL, &s, &err), "path is NULL");
    REFUSED(glint_scene_load("x.yaml", NULL, &err), "out is NULL");
    REFUSED(glint_scene_builtin(NULL, &err), "out is NULL");
    REFUSED(glint_scene_new(NULL, &err), "out is NULL");
    REFUSED(glint_scene_settings(NULL, &st, &err), "scene is NULL");
    REFUSED(glint_scene_settings(s, NULL, &err), "out is NULL");
    glint_scene_counts counts;
    REFUSED(glint_scene_count(NULL, &counts, &err), "scene is NULL");
    REFUSED(glint_scene_count(s, NULL, &err), "out is NULL");
    REFUSED(glint_scene_set_settings(NULL, &st, &err), "scene is NULL");
    REFUSED(glint_scene_set_settings(s, NULL, &err), "settings is NULL");
    REFUSED(glint_settings_check(NULL, &err), "settings is NULL");
    REFUSED(glint_scene_camera(NULL, &cam, &err), "scene is NULL");
    REFUSED(glint_scene_camera(s, NULL, &err), "out is NULL");
    REFUSED(glint_scene_set_camera(s, NULL, &err), "camera is NULL");
    REFUSED(glint_scene_set_background(s, NULL, &err), "rgb is NULL");
    REFUSED(glint_scene_set_ambient(NULL, rgb, &err), "scene is NULL");
    REFUSED(glint_scene_add_material(s, NULL, NULL, &err), "material is NULL");
    REFUSED(glint_scene_add_material(NULL, &m, NULL, &err), "scene is NULL");
    REFUSED(glint_scene_add_light(s, NULL, NULL, &err), "light is NULL");
    REFUSED(glint_scene_add_light(NULL, &l, NULL, &err), "scene is NULL");
    REFUSED(glint_scene_add_object(s, NULL, NULL, &err), "object is NULL");
    REFUSED(glint_scene_add_object(NULL, &o, NULL, &err), "scene is NULL");
    o.nsteps = 1;
    REFUSED(glint_scene_add_object(s, &o, NULL, &err), "steps is NULL");
    REFUSED(glint_scene_build(NULL, &err), "scene is NULL");
    REFUSED(glint_render(NULL, &st, NULL, &film, NULL, &err), "scene is NULL");
    REFUSED(glint_render(s, &st, NULL, NULL, NULL, &err), "film is NULL");
    REFUSED(glint_render_region(s, &st, NULL, NULL, &film, NULL, &err), "region is NULL");
    REFUSED(glint_render_region(s, &st, &r, NULL, &film, NULL, &err), "film->rgb is NULL");
    REFUSED(glint_render_tiles(s, &st, NULL, 1, NULL, &film, NULL, &err), "NULL");
    REFUSED(glint_render_tiles(s, &st, tiles, 1, NULL, NULL, NULL, &err), "film is NULL");
    REFUSED(glint_tile_count(NULL, &n, &err), "settings is NULL");
    REFUSED(glint_tile_count(&st, NULL, &err), "count is NULL");
    REFUSED(glint_tile_rect(&st, 0, NULL, &err), "out is NULL");
    REFUSED(glint_film_alloc(NULL, 4, 4, &err), "film is NULL");
    REFUSED(glint_film_write(NULL, "x.png", NULL, &err), "film is NULL");
    REFUSED(glint_film_write(&film, "x.png", NULL, &err), "film->rgb is NULL");
    REFUSED(glint_output_check(NULL, NULL, &err), "path is NULL");
    REFUSED(glint_format_parse(NULL, NULL, &err), "name is NULL");
    glint_animation an;
    char name[16];
    REFUSED(glint_scene_animation(NULL, &an, &err), "scene is NULL");
    REFUSED(glint_scene_animation(s, NULL, &err), "out is NULL");
    REFUSED(glint_scene_set_time(NULL, 0, &err), "scene is NULL");
    REFUSED(glint_scene_set_frame(NULL, 1, &err), "scene is NULL");
    REFUSED(glint_frames_parse(NULL, 1, &n, &n, &err), "spec is NULL");
    REFUSED(glint_frames_parse("1", 1, NULL, &n, &err), "first is NULL");
    REFUSED(glint_frame_path(NULL, 1, name, sizeof name, &err), "pattern is NULL");
    REFUSED(glint_frame_path("a.png", 1, NULL, 4, &err), "out is NULL");
    cr_expect_eq(glint_output_complete(NULL, 0, 0), 0);
    cr_expect_eq(glint_scene_load(NULL, &s, NULL), GLINT_ERR_INPUT, "err may be NULL");
    glint_scene_free(NULL);
    glint_film_free(NULL);
    glint_film_free(&film);
    glint_scene_free(s);
}

Test(api, values_out_of_range_are_refused)
{
    glint_settings st;
    glint_scene *s = builtin(&st, 40, 30, 1);
    glint_settings bad = st;
    bad.transfer = (glint_transfer)7;
    REFUSED(glint_settings_check(&bad, &err), "transfer");
    bad = st;
    bad.sampler = (glint_sampler)3;
    REFUSED(glint_settings_check(&bad, &err), "sampler");
    bad = st;
    bad.threshold = 1.5;
    REFUSED(glint_settings_check(&bad, &err), "threshold");
    bad = st;
    bad.adaptive_depth = 6;
    REFUSED(glint_settings_check(&bad, &err), "max_depth");
    REFUSED(glint_scene_set_time(s, NAN, &err), "finite");
    REFUSED(glint_scene_set_frame(s, 2, &err), "frame 2 is out of range (1 to 1)");
    REFUSED(glint_frame_path("a.png", -1, (char[8]){0}, 8, &err), "frame must be >= 0");
    bad = st;
    bad.transfer = (glint_transfer)7;
    glint_film film = {0};
    REFUSED(glint_render(s, &bad, NULL, &film, NULL, &err), "transfer");
    cr_expect_null(film.rgb);
    OK(glint_film_alloc(&film, 40, 30, &err));
    glint_write_options opts = {.transfer = (glint_transfer)7};
    REFUSED(glint_film_write(&film, "/tmp/glint-api-refused.png", &opts, &err), "transfer");
    REFUSED(glint_film_alloc(&(glint_film){0}, 0, 5, &err), "film size");
    glint_rect outside = {30, 20, 41, 30}, empty = {5, 5, 5, 9};
    REFUSED(glint_render_region(s, &st, &outside, NULL, &film, NULL, &err), "not inside");
    REFUSED(glint_render_region(s, &st, &empty, NULL, &film, NULL, &err), "empty");
    glint_film odd = {0};
    OK(glint_film_alloc(&odd, 7, 7, &err));
    glint_rect r = {0, 0, 8, 8};
    REFUSED(glint_render_region(s, &st, &r, NULL, &odd, NULL, &err), "film is 7x7");
    int twice[2] = {1, 1}, far[1] = {6};
    REFUSED(glint_render_tiles(s, &st, twice, 2, NULL, &film, NULL, &err), "twice");
    REFUSED(glint_render_tiles(s, &st, far, 1, NULL, &film, NULL, &err), "out of range");
    REFUSED(glint_render_tiles(s, &st, far, -1, NULL, &film, NULL, &err), "ntiles");
    int two[2] = {0, 5};
    REFUSED(glint_render_tiles(s, &st, two, 2, NULL, &odd, NULL, &err), "tiles' bounds (40x30)");
    REFUSED(glint_tile_rect(&st, 6, &r, &err), "out of range");
    glint_film_free(&odd);
    glint_film_free(&film);
    glint_scene_free(s);

    OK(glint_scene_new(&s, &err));
    glint_material m = glint_material_default();
    m.reflect = 1.5;
    REFUSED(glint_scene_add_material(s, &m, NULL, &err), "reflect");
    m = glint_material_default();
    m.ior = 0;
    REFUSED(glint_scene_add_material(s, &m, NULL, &err), "ior");
    m = glint_material_default();
    m.color[1] = -1;
    REFUSED(glint_scene_add_material(s, &m, NULL, &err), "colours");
    m = glint_material_default();
    m.texture = 0;
    REFUSED(glint_scene_add_material(s, &m, NULL, &err), "texture 0 was not added");
    glint_texture t = glint_texture_default(GLINT_TEXTURE_IMAGE);
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "file is NULL");
    t.file = "/nonexistent/picture.png";
    cr_expect_neq(glint_scene_add_texture(s, &t, NULL, &err), GLINT_OK);
    cr_expect_not_null(strstr(err.msg, "picture.png"), "%s", err.msg);
    t = glint_texture_default(GLINT_TEXTURE_CHECKER);
    t.scale[1] = 0;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "scale");
    t = glint_texture_default((glint_texture_kind)42);
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "kind 42");
    REFUSED(glint_scene_add_texture(s, NULL, NULL, &err), "texture is NULL");
    REFUSED(glint_scene_add_mesh(s, NULL, NULL, &err), "path is NULL");
    REFUSED(glint_scene_add_mesh(s, "/nonexistent/m.obj", NULL, &err), "m.obj");
    glint_light l = {.kind = (glint_light_kind)4, .position = {0, 0, 0}, .color = {1, 1, 1}};
    REFUSED(glint_scene_add_light(s, &l, NULL, &err), "kind");
    l = glint_light_default(GLINT_LIGHT_SPOT);
    REFUSED(glint_scene_add_light(s, &l, NULL, &err), "look_at must differ");
    l.look_at[1] = -1, l.outer_angle = 10;
    REFUSED(glint_scene_add_light(s, &l, NULL, &err), "inner_angle < outer_angle");
    l = glint_light_default(GLINT_LIGHT_AREA);
    l.edge_u[0] = 1, l.edge_v[0] = 2;
    REFUSED(glint_scene_add_light(s, &l, NULL, &err), "parallel");
    l.edge_v[0] = 0, l.edge_v[2] = 1, l.samples = 65;
    REFUSED(glint_scene_add_light(s, &l, NULL, &err), "samples");
    l = glint_light_default(GLINT_LIGHT_DIRECTIONAL);
    REFUSED(glint_scene_add_light(s, &l, NULL, &err), "direction");
    l = glint_light_default(GLINT_LIGHT_POINT);
    l.attenuation[1] = -1;
    REFUSED(glint_scene_add_light(s, &l, NULL, &err), "attenuation");
    REFUSED(glint_scene_set_background(s, (double[3]){0, INFINITY, 0}, &err), "finite");
    glint_object o = {{GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, 1}}, 0, NULL, 0};
    REFUSED(glint_scene_add_object(s, &o, NULL, &err), "material 0 was not added");
    material(s, glint_material_default());
    struct { const char *words; glint_shape shape; } shapes[] = {
        {"radius", {GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, -1}}},
        {"normal", {GLINT_SHAPE_PLANE, .plane = {{0, 0, 0}, {0, 0, 0}}}},
        {"parallel", {GLINT_SHAPE_QUAD, .quad = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}}},
        {"greater than min", {GLINT_SHAPE_BOX, .box = {{0, 0, 0}, {1, 0, 1}}}},
        {"height", {GLINT_SHAPE_CYLINDER, .cylinder = {{0, 0, 0}, 1, 0, 1}}},
        {"degenerate", {GLINT_SHAPE_TRIANGLE, .triangle = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}}},
        {"mesh 0 was not added", {GLINT_SHAPE_MESH, .mesh = {0}}},
        {"shape kind", {(glint_shape_kind)42, .sphere = {{0, 0, 0}, 1}}},
    };
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++) {
        o.shape = shapes[i].shape;
        REFUSED(glint_scene_add_object(s, &o, NULL, &err), shapes[i].words);
    }
    o.shape = (glint_shape){GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, 1}};
    glint_step steps[][1] = {{{GLINT_STEP_SCALE, {1, 0, 1}}},
                             {{GLINT_STEP_ROTATE, {0, 0, 0, 30}}},
                             {{GLINT_STEP_MATRIX, {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0}}},
                             {{GLINT_STEP_SHEAR, {1, 0, 1}}},
                             {{(glint_step_kind)9, {0}}}};
    const char *step_words[] = {"scale", "axis", "not invertible", "not invertible", "kind 9"};
    for (int i = 0; i < 5; i++) {
        o.steps = steps[i];
        o.nsteps = 1;
        REFUSED(glint_scene_add_object(s, &o, NULL, &err), step_words[i]);
    }
    /* A scene changed after its build refuses to render until built again. */
    o.nsteps = 0;
    OK(glint_scene_build(s, &err));
    OK(glint_scene_add_object(s, &o, NULL, &err));
    REFUSED(glint_render(s, NULL, NULL, &film, NULL, &err), "not built");
    OK(glint_scene_build(s, &err));
    OK(glint_render(s, NULL, NULL, &film, NULL, &err));
    glint_film_free(&film);
    glint_scene_free(s);
}

/* What a scene holds, for front ends that warn about a scene without
 * lights or objects. */
Test(api, scene_counts)
{
    glint_scene *s = NULL;
    OK(glint_scene_new(&s, &err));
    glint_scene_counts n;
    OK(glint_scene_count(s, &n, &err));
    cr_expect(n.objects == 0 && n.lights == 0 && n.textures == 0 && n.meshes == 0);
    glint_light l = {.kind = GLINT_LIGHT_POINT, .position = {0, 5, 0}, .color = {1, 1, 1}};
    OK(glint_scene_add_light(s, &l, NULL, &err));
    glint_material m = glint_material_default();
    int mat;
    OK(glint_scene_add_material(s, &m, &mat, &err));
    glint_object o = {{GLINT_SHAPE_SPHERE, .sphere = {{0, 0, -5}, 1}}, mat, NULL, 0};
    OK(glint_scene_add_object(s, &o, NULL, &err));
    OK(glint_scene_add_object(s, &o, NULL, &err));
    OK(glint_scene_count(s, &n, &err));
    cr_expect_eq(n.objects, 2);
    cr_expect_eq(n.lights, 1);
    cr_expect_geq(n.materials, 1);
    glint_scene_free(s);
}
