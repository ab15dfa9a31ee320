/* The public API (include/glint.h) as an embedding program uses it: a scene
 * built in code renders to the same bytes as the same scene in YAML; regions
 * and tile lists assemble into the whole image; progress, cancellation from
 * another thread, the camera, and the argument checks of every function. */
#include <criterion/criterion.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "glint.h"
#include "tmpdir.h"

/* Every shape, every transform step, each kind of material, two lights. */
static const char scene_yaml[] =
    "image: {width: 64, height: 48, samples: 4, depth: 5, background: [0.1, 0.2, 0.3]}\n"
    "camera: {eye: [0, 2, 10], look_at: [0, 0, 0], up: [0, 1, 0], fov: 50}\n"
    "ambient: [0.25, 0.2, 0.2]\n"
    "lights:\n"
    "  - {type: point, position: [5, 8, 6], color: [1, 0.9, 0.8]}\n"
    "  - {type: point, position: [-6, 4, 3], color: 0.4}\n"
    "materials:\n"
    "  mirror: {color: [0.2, 0.3, 0.9], specular: 1, shininess: 80, reflect: 0.75}\n"
    "  glass: {specular: 1, shininess: 200, transmit: 0.9, ior: 1.5}\n"
    "  clear: {color: [0.9, 0.3, 0.2], transmit: 0.5, tint: [1, 0.5, 0.25]}\n"
    "  matte: {color: [0.5, 0.75, 0.25], ambient: 0.5, diffuse: 0.75}\n"
    "objects:\n"
    "  - {type: plane, point: [0, -1, 0], normal: [0, 1, 0], material: matte}\n"
    "  - {type: sphere, center: [-2, 0, 0], radius: 1, material: mirror}\n"
    "  - {type: sphere, center: [1, 0.5, 2], radius: 0.75, material: glass}\n"
    "  - {type: quad, origin: [-3, -1, -3], edge_u: [6, 0, 0], edge_v: [0, 4, 0], material: matte}\n"
    "  - {type: box, min: [-0.5, -1, -0.5], max: [0.5, 0, 0.5], material: clear,\n"
    "     transform: [rotate_y: 30, translate: [2, 0, 0]]}\n"
    "  - {type: cylinder, base: [0, 0, 0], radius: 0.5, height: 1.5, capped: false, material: mirror,\n"
    "     transform: [scale: [1, 0.5, 1], rotate: {axis: [1, 0, 1], angle: 20}, translate: [-1, -1, 2]]}\n"
    "  - {type: triangle, p0: [-3, 2, -2], p1: [-1, 2, -2], p2: [-2, 3.5, -2], material: clear,\n"
    "     transform: [shear: {xy: 0.25}]}\n"
    "  - {type: sphere, center: [0, 0, 0], radius: 1,\n"
    "     transform: [matrix: [0.5, 0, 0, 3,  0, 0.5, 0, 2,  0, 0, 0.5, -1]]}\n";

#define OK(call)                                                                             \
    do {                                                                                     \
        glint_error e_ = {0};                                                                \
        glint_rc rc_ = (call);                                                               \
        (void)e_;                                                                            \
        cr_assert_eq(rc_, GLINT_OK, "%s: %s", #call, err.msg);                               \
    } while (0)

static glint_error err;

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

/* scene_yaml, written in code. */
static glint_scene *scene_in_code(void)
{
    glint_scene *s = NULL;
    OK(glint_scene_new(&s, &err));
    glint_settings st = {64, 48, 4, 5, 0, GLINT_TRANSFER_NONE};
    OK(glint_scene_set_settings(s, &st, &err));
    glint_camera cam = {{0, 2, 10}, {0, 0, 0}, {0, 1, 0}, 50, 0, 0, GLINT_PROJECTION_PERSPECTIVE};
    OK(glint_scene_set_camera(s, &cam, &err));
    OK(glint_scene_set_background(s, (double[3]){0.1, 0.2, 0.3}, &err));
    OK(glint_scene_set_ambient(s, (double[3]){0.25, 0.2, 0.2}, &err));
    glint_light l1 = {GLINT_LIGHT_POINT, {5, 8, 6}, {1, 0.9, 0.8}};
    glint_light l2 = {GLINT_LIGHT_POINT, {-6, 4, 3}, {0.4, 0.4, 0.4}};
    OK(glint_scene_add_light(s, &l1, NULL, &err));
    OK(glint_scene_add_light(s, &l2, NULL, &err));

    glint_material m = glint_material_default();
    m = (glint_material){{0.2, 0.3, 0.9}, 1, 1, 1, 80, 0.75, 0, 1, {1, 1, 1}};
    int mirror = material(s, m);
    m = glint_material_default();
    m.specular = 1, m.shininess = 200, m.transmit = 0.9, m.ior = 1.5;
    int glass = material(s, m);
    m = glint_material_default();
    m.color[0] = 0.9, m.color[1] = 0.3, m.color[2] = 0.2, m.transmit = 0.5;
    m.tint[1] = 0.5, m.tint[2] = 0.25;
    int clear = material(s, m);
    m = glint_material_default();
    m.color[0] = 0.5, m.color[1] = 0.75, m.color[2] = 0.25, m.ambient = 0.5, m.diffuse = 0.75;
    int matte = material(s, m);
    int white = material(s, glint_material_default());

    object(s, (glint_shape){GLINT_SHAPE_PLANE, .plane = {{0, -1, 0}, {0, 1, 0}}}, matte, NULL, 0);
    object(s, (glint_shape){GLINT_SHAPE_SPHERE, .sphere = {{-2, 0, 0}, 1}}, mirror, NULL, 0);
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
    OK(glint_scene_build(s, &err));
    return s;
}

static glint_scene *scene_from_yaml(void)
{
    tmpdir_make("api");
    char path[128];
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f);
    fputs(scene_yaml, f);
    fclose(f);
    glint_scene *s = NULL;
    OK(glint_scene_load(path, &s, &err));
    tmpdir_remove();
    return s;
}

static void expect_same_film(const glint_film *a, const glint_film *b)
{
    cr_assert_eq(a->width, b->width);
    cr_assert_eq(a->height, b->height);
    size_t n = (size_t)a->width * (size_t)a->height * 3;
    cr_expect_eq(memcmp(a->rgb, b->rgb, n * sizeof(float)), 0, "the films differ");
}

Test(api, scene_in_code_renders_as_the_same_scene_in_yaml)
{
    glint_scene *code = scene_in_code(), *yaml = scene_from_yaml();
    glint_film a = {0}, b = {0};
    OK(glint_render(code, NULL, NULL, &a, NULL, &err));
    OK(glint_render(yaml, NULL, NULL, &b, NULL, &err));
    cr_assert_eq(a.width, 64);
    expect_same_film(&a, &b);
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
