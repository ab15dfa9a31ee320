/* Building in code what the scene format's extensions describe: cones,
 * disks, tori, polyhedra, csg trees, triangles with their own (u, v), the
 * procedural patterns with their colour maps, spaces, mappings and
 * transforms, bump maps and fog. Each scene is built in code and written
 * in YAML, and the two render alike; then the refusals, one rule at a
 * time. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "api_test.h"
#include "glint.h"
#include "tmpdir.h"

static glint_error err; /* the last call's, for OK and REFUSED */

static glint_scene *from_yaml(const char *text)
{
    char path[128];
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f);
    fputs(text, f);
    fclose(f);
    glint_scene *s = NULL;
    OK(glint_scene_load(path, &s, &err));
    return s;
}

/* Renders both with the YAML scene's settings; the films agree and show
 * something (many values differ from the first pixel's). */
static void expect_same_render(glint_scene *code, const char *yaml)
{
    tmpdir_make("api-build");
    glint_scene *y = from_yaml(yaml);
    tmpdir_remove();
    OK(glint_scene_build(code, &err));
    glint_settings st;
    OK(glint_scene_settings(y, &st, &err));
    OK(glint_scene_set_settings(code, &st, &err));
    glint_film a = {0}, b = {0};
    OK(glint_render(code, NULL, NULL, &a, NULL, &err));
    OK(glint_render(y, NULL, NULL, &b, NULL, &err));
    test_expect_same_film(&a, &b);
    int differ = 0, n = a.width * a.height * 3;
    for (int i = 3; i < n; i++)
        differ += fabsf(a.rgb[i] - a.rgb[i % 3]) > 0.02f;
    cr_expect_gt(differ, n / 4, "the picture is nearly blank (%d of %d values differ)", differ, n);
    glint_film_free(&a);
    glint_film_free(&b);
    glint_scene_free(code);
    glint_scene_free(y);
}

static glint_scene *new_scene(const glint_camera *cam, const double light[3])
{
    glint_scene *s = NULL;
    OK(glint_scene_new(&s, &err));
    OK(glint_scene_set_camera(s, cam, &err));
    glint_light l = glint_light_default(GLINT_LIGHT_POINT);
    memcpy(l.position, light, sizeof l.position);
    OK(glint_scene_add_light(s, &l, NULL, &err));
    return s;
}

static int material(glint_scene *s, glint_material m)
{
    int i = -1;
    OK(glint_scene_add_material(s, &m, &i, &err));
    return i;
}

static int colored(glint_scene *s, double r, double g, double b)
{
    glint_material m = glint_material_default();
    m.color[0] = r, m.color[1] = g, m.color[2] = b;
    return material(s, m);
}

static int textured(glint_scene *s, const glint_texture *t)
{
    glint_material m = glint_material_default();
    OK(glint_scene_add_texture(s, t, &m.texture, &err));
    return material(s, m);
}

static void object(glint_scene *s, glint_shape shape, int mat, const glint_step *steps, int n)
{
    glint_object o = {shape, mat, steps, n};
    OK(glint_scene_add_object(s, &o, NULL, &err));
}

/* ---- shapes and fog ------------------------------------------------------ */

static const char shapes_yaml[] =
    "image: {width: 48, height: 36, samples: 4, background: [0.2, 0.3, 0.4]}\n"
    "camera: {eye: [0, 3, 12], look_at: [0, 0, 0], up: [0, 1, 0], fov: 50}\n"
    "fog: {type: exponential, color: [0.6, 0.6, 0.7], density: 0.03, height_falloff: 0.2}\n"
    "lights: [{type: point, position: [5, 8, 6]}]\n"
    "materials:\n"
    "  red: {color: [0.9, 0.2, 0.1]}\n"
    "  blue: {color: [0.2, 0.3, 0.9]}\n"
    "  grid: {texture: {type: checker, even: 1, odd: [0.1, 0.1, 0.1], scale: [4, 4]}}\n"
    "objects:\n"
    "  - {type: cone, base: [-3, -1, 0], radius: 1, top_radius: 0.3, height: 2, material: red}\n"
    "  - {type: cone, base: [-3, -1, 3], radius: 0.6, height: 1.5, capped: false, material: blue,\n"
    "     transform: [rotate_z: 20]}\n"
    "  - {type: disk, center: [0, -1, 0], normal: [0, 1, 0], radius: 6, inner_radius: 1,\n"
    "     material: grid}\n"
    "  - {type: torus, center: [0, 0.5, 0], major_radius: 1.2, minor_radius: 0.3, material: blue,\n"
    "     transform: [rotate_x: 60]}\n"
    "  - {type: polyhedron, preset: tetrahedron, center: [3, 0, 0], radius: 1, material: red}\n"
    "  - {type: polyhedron, preset: icosahedron, radius: 0.7, material: blue,\n"
    "     transform: [translate: [3, 1.5, 2]]}\n"
    "  - {type: polyhedron, vertices: [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1], [0.5, 1, 0.5]],\n"
    "     faces: [[0, 1, 2, 3], [0, 4, 1], [1, 4, 2], [2, 4, 3], [3, 4, 0]], material: red,\n"
    "     transform: [translate: [-1, -1, 2]]}\n"
    "  - {type: triangle, p0: [-2, 1, -2], p1: [0, 1, -2], p2: [-1, 3, -2],\n"
    "     uv: [[0, 0], [4, 0], [2, 4]], material: grid}\n";

static const double pyramid[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, {0.5, 1, 0.5}};
static const int pyramid_faces[] = {0, 1, 2, 3, 0, 4, 1, 1, 4, 2, 2, 4, 3, 3, 4, 0};
static const int pyramid_sizes[] = {4, 3, 3, 3, 3};

Test(api_build, cone_disk_torus_polyhedra_triangle_uv_and_fog_as_in_yaml)
{
    glint_camera cam = {{0, 3, 12}, {0, 0, 0}, {0, 1, 0}, 50, 0, 0, GLINT_PROJECTION_PERSPECTIVE, 0, 0};
    glint_scene *s = new_scene(&cam, (double[3]){5, 8, 6});
    OK(glint_scene_set_background(s, (double[3]){0.2, 0.3, 0.4}, &err));
    glint_fog fog = glint_fog_default(GLINT_FOG_EXPONENTIAL);
    fog.color[0] = fog.color[1] = 0.6, fog.color[2] = 0.7;
    fog.density = 0.03, fog.height_falloff = 0.2;
    OK(glint_scene_set_fog(s, &fog, &err));
    int red = colored(s, 0.9, 0.2, 0.1), blue = colored(s, 0.2, 0.3, 0.9);
    glint_texture t = glint_texture_default(GLINT_TEXTURE_CHECKER);
    t.odd[0] = t.odd[1] = t.odd[2] = 0.1, t.scale[0] = t.scale[1] = 4;
    int grid = textured(s, &t);

    object(s, (glint_shape){GLINT_SHAPE_CONE, .cone = {{-3, -1, 0}, 1, 0.3, 2, 1}}, red, NULL, 0);
    glint_step tilt[] = {{GLINT_STEP_ROTATE, {0, 0, 1, 20}}};
    object(s, (glint_shape){GLINT_SHAPE_CONE, .cone = {{-3, -1, 3}, 0.6, 0, 1.5, 0}}, blue, tilt, 1);
    object(s, (glint_shape){GLINT_SHAPE_DISK, .disk = {{0, -1, 0}, {0, 1, 0}, 6, 1}}, grid, NULL, 0);
    glint_step turn[] = {{GLINT_STEP_ROTATE, {1, 0, 0, 60}}};
    object(s, (glint_shape){GLINT_SHAPE_TORUS, .torus = {{0, 0.5, 0}, 1.2, 0.3}}, blue, turn, 1);
    glint_shape p = {GLINT_SHAPE_POLYHEDRON,
                     .polyhedron = {.preset = GLINT_POLYHEDRON_TETRAHEDRON, .center = {3, 0, 0},
                                    .radius = 1}};
    object(s, p, red, NULL, 0);
    p.polyhedron = (glint_polyhedron){.preset = GLINT_POLYHEDRON_ICOSAHEDRON, .radius = 0.7};
    glint_step up[] = {{GLINT_STEP_TRANSLATE, {3, 1.5, 2}}};
    object(s, p, blue, up, 1);
    p.polyhedron = (glint_polyhedron){.vertices = pyramid, .nvertices = 5,
                                      .indices = pyramid_faces, .face_sizes = pyramid_sizes,
                                      .nfaces = 5};
    glint_step aside[] = {{GLINT_STEP_TRANSLATE, {-1, -1, 2}}};
    object(s, p, red, aside, 1);
    glint_shape tri = {GLINT_SHAPE_TRIANGLE, .triangle = {{-2, 1, -2}, {0, 1, -2}, {-1, 3, -2}, 1,
                                                          {{0, 0}, {4, 0}, {2, 4}}}};
    object(s, tri, grid, NULL, 0);
    expect_same_render(s, shapes_yaml);
}

/* ---- textures, bump maps and linear fog ----------------------------------- */

static const char textures_yaml[] =
    "image: {width: 64, height: 48, samples: 1}\n"
    "camera: {eye: [0, 0, 14], look_at: [0, 0, 0], up: [0, 1, 0], fov: 60}\n"
    "fog: {type: linear, color: 0.3, start: 12, end: 40, height_falloff: 0.05}\n"
    "lights: [{type: point, position: [4, 6, 10]}]\n"
    "objects:\n"
    "  - {type: sphere, center: [-4, 3, 0], radius: 1.6, material: {texture: {type: stripes,\n"
    "     colors: [[0, [1, 0, 0]], [1, [0, 0, 1]]], scale: [3, 1, 1], space: world}}}\n"
    "  - {type: sphere, center: [0, 3, 0], radius: 1.6, material: {texture: {type: rings,\n"
    "     scale: 4, transform: [rotate_x: 90]}}}\n"
    "  - {type: sphere, center: [4, 3, 0], radius: 1.6, material: {texture: {type: gradient,\n"
    "     space: uv, scale: [2, 1], offset: [0.25, 0], colors: [[0, 0], [0.5, [1, 0.5, 0]], [1, 1]]}}}\n"
    "  - {type: sphere, center: [-4, 0, 0], radius: 1.6, material: {texture: {type: noise,\n"
    "     scale: 3, offset: [1, 2, 3]}}}\n"
    "  - {type: sphere, center: [0, 0, 0], radius: 1.6, material: {texture: {type: turbulence,\n"
    "     octaves: 3, lacunarity: 2.5, gain: 0.6, scale: 2}}}\n"
    "  - {type: sphere, center: [4, 0, 0], radius: 1.6, material: {specular: 0.5,\n"
    "     texture: {type: marble, turbulence: 2, scale: [1, 2, 1],\n"
    "       colors: [[0, [0.9, 0.9, 0.9]], [1, [0.2, 0.2, 0.3]]]},\n"
    "     bump: {pattern: {type: noise, scale: 4}, strength: 0.5}}}\n"
    "  - {type: sphere, center: [-4, -3, 0], radius: 1.6, material: {texture: {type: wood,\n"
    "     scale: 3, octaves: 4, space: world}}}\n"
    "  - {type: sphere, center: [0, -3, 0], radius: 1.6, material: {texture: {type: checker,\n"
    "     space: object, scale: 2, colors: [[0, [1, 1, 0]], [1, [0, 0.5, 0]]]}}}\n"
    "  - {type: sphere, center: [4, -3, 0], radius: 1.6, material: {texture: {type: image,\n"
    "     file: " GLINT_SOURCE_DIR "/scenes/textures/globe.png, mapping: spherical,\n"
    "     transform: [rotate_y: -40]}}}\n"
    "  - {type: quad, origin: [-8, -6, -3], edge_u: [16, 0, 0], edge_v: [0, 12, 0],\n"
    "     material: {texture: {type: image, file: " GLINT_SOURCE_DIR "/scenes/textures/flag.png,\n"
    "       mapping: planar, axis: z, space: world, scale: [0.25, 0.25], wrap: [repeat, clamp]}}}\n";

static void sphere(glint_scene *s, double x, double y, int mat)
{
    object(s, (glint_shape){GLINT_SHAPE_SPHERE, .sphere = {{x, y, 0}, 1.6}}, mat, NULL, 0);
}

static void set_stops(glint_texture *t, int n, const glint_color_stop *stops)
{
    t->ncolors = n;
    memcpy(t->colors, stops, sizeof *stops * (size_t)n);
}

/* The nine spheres' textures, in the order of textures_yaml. */
static void add_patterns(glint_scene *s)
{
    glint_texture t = glint_texture_default(GLINT_TEXTURE_STRIPES);
    set_stops(&t, 2, (glint_color_stop[]){{0, {1, 0, 0}}, {1, {0, 0, 1}}});
    t.scale[0] = 3, t.space = GLINT_SPACE_WORLD;
    sphere(s, -4, 3, textured(s, &t));
    t = glint_texture_default(GLINT_TEXTURE_RINGS);
    t.scale[0] = t.scale[1] = t.scale_z = 4;
    glint_step rx[] = {{GLINT_STEP_ROTATE, {1, 0, 0, 90}}};
    t.steps = rx, t.nsteps = 1;
    sphere(s, 0, 3, textured(s, &t));
    t = glint_texture_default(GLINT_TEXTURE_GRADIENT);
    t.space = GLINT_SPACE_UV, t.scale[0] = 2, t.offset[0] = 0.25;
    set_stops(&t, 3, (glint_color_stop[]){{0, {0, 0, 0}}, {0.5, {1, 0.5, 0}}, {1, {1, 1, 1}}});
    sphere(s, 4, 3, textured(s, &t));
    t = glint_texture_default(GLINT_TEXTURE_NOISE);
    t.scale[0] = t.scale[1] = t.scale_z = 3;
    t.offset[0] = 1, t.offset[1] = 2, t.offset_z = 3;
    sphere(s, -4, 0, textured(s, &t));
    t = glint_texture_default(GLINT_TEXTURE_TURBULENCE);
    t.octaves = 3, t.lacunarity = 2.5, t.gain = 0.6;
    t.scale[0] = t.scale[1] = t.scale_z = 2;
    sphere(s, 0, 0, textured(s, &t));
    t = glint_texture_default(GLINT_TEXTURE_MARBLE);
    t.turbulence = 2, t.scale[1] = 2;
    set_stops(&t, 2, (glint_color_stop[]){{0, {0.9, 0.9, 0.9}}, {1, {0.2, 0.2, 0.3}}});
    glint_material m = glint_material_default();
    m.specular = 0.5;
    OK(glint_scene_add_texture(s, &t, &m.texture, &err));
    t = glint_texture_default(GLINT_TEXTURE_NOISE);
    t.scale[0] = t.scale[1] = t.scale_z = 4;
    OK(glint_scene_add_texture(s, &t, &m.bump_texture, &err));
    m.bump = 1, m.bump_strength = 0.5;
    sphere(s, 4, 0, material(s, m));
    t = glint_texture_default(GLINT_TEXTURE_WOOD);
    t.scale[0] = t.scale[1] = t.scale_z = 3;
    t.octaves = 4, t.space = GLINT_SPACE_WORLD;
    sphere(s, -4, -3, textured(s, &t));
    t = glint_texture_default(GLINT_TEXTURE_CHECKER);
    t.space = GLINT_SPACE_OBJECT, t.scale[0] = t.scale[1] = t.scale_z = 2;
    set_stops(&t, 2, (glint_color_stop[]){{0, {1, 1, 0}}, {1, {0, 0.5, 0}}});
    sphere(s, 0, -3, textured(s, &t));
}

Test(api_build, patterns_images_mappings_bump_and_linear_fog_as_in_yaml)
{
    glint_camera cam = {{0, 0, 14}, {0, 0, 0}, {0, 1, 0}, 60, 0, 0, GLINT_PROJECTION_PERSPECTIVE, 0, 0};
    glint_scene *s = new_scene(&cam, (double[3]){4, 6, 10});
    glint_fog fog = glint_fog_default(GLINT_FOG_LINEAR);
    fog.color[0] = fog.color[1] = fog.color[2] = 0.3;
    fog.start = 12, fog.end = 40, fog.height_falloff = 0.05;
    OK(glint_scene_set_fog(s, &fog, &err));
    add_patterns(s);
    glint_texture t = glint_texture_default(GLINT_TEXTURE_IMAGE);
    t.file = GLINT_SOURCE_DIR "/scenes/textures/globe.png";
    t.space = GLINT_SPACE_OBJECT, t.mapping = GLINT_MAPPING_SPHERICAL;
    glint_step ry[] = {{GLINT_STEP_ROTATE, {0, 1, 0, -40}}};
    t.steps = ry, t.nsteps = 1;
    sphere(s, 4, -3, textured(s, &t));
    t = glint_texture_default(GLINT_TEXTURE_IMAGE);
    t.file = GLINT_SOURCE_DIR "/scenes/textures/flag.png";
    t.space = GLINT_SPACE_WORLD, t.mapping = GLINT_MAPPING_PLANAR, t.axis = 2;
    t.scale[0] = t.scale[1] = 0.25, t.wrap[1] = GLINT_WRAP_CLAMP;
    object(s, (glint_shape){GLINT_SHAPE_QUAD, .quad = {{-8, -6, -3}, {16, 0, 0}, {0, 12, 0}}},
           textured(s, &t), NULL, 0);
    expect_same_render(s, textures_yaml);
}

/* ---- csg ------------------------------------------------------------------ */

static const char csg_yaml[] =
    "image: {width: 48, height: 36, samples: 4}\n"
    "camera: {eye: [0, 2, 8], look_at: [0, 0, 0], up: [0, 1, 0], fov: 50}\n"
    "lights: [{type: point, position: [4, 6, 6]}]\n"
    "materials:\n"
    "  red: {color: [0.9, 0.1, 0.1]}\n"
    "  green: {color: [0.1, 0.8, 0.2], specular: 0.5, shininess: 30}\n"
    "  glass: {color: [0.8, 0.9, 1], transmit: 0.8, ior: 1.3}\n"
    "objects:\n"
    "  - {type: plane, point: [0, -1.5, 0], normal: [0, 1, 0], material: green}\n"
    "  - type: csg\n"
    "    op: difference\n"
    "    material: red\n"
    "    transform: [rotate_y: 30, translate: [-1.5, 0, 0]]\n"
    "    objects:\n"
    "      - {type: box, min: [-1, -1, -1], max: [1, 1, 1]}\n"
    "      - {type: sphere, center: [0, 0, 0], radius: 1.3, material: green}\n"
    "      - {type: cylinder, base: [0, -2, 0], radius: 0.4, height: 4, transform: [rotate_x: 90]}\n"
    "  - type: csg\n"
    "    op: intersection\n"
    "    transform: [translate: [1.8, 0, 0]]\n"
    "    objects:\n"
    "      - {type: sphere, center: [0, 0, 0], radius: 1.2, material: glass}\n"
    "      - type: csg\n"
    "        op: union\n"
    "        material: green\n"
    "        transform: [rotate_z: 45]\n"
    "        objects:\n"
    "          - {type: box, min: [-2, -0.3, -2], max: [2, 0.3, 2]}\n"
    "          - {type: torus, center: [0, 0, 0], major_radius: 1, minor_radius: 0.4, material: red}\n"
    "          - {type: polyhedron, preset: octahedron, radius: 1.1}\n"
    "          - {type: cone, base: [0, -1.5, 0], radius: 0.5, height: 3}\n";

Test(api_build, csg_trees_with_operand_materials_and_transforms_as_in_yaml)
{
    glint_camera cam = {{0, 2, 8}, {0, 0, 0}, {0, 1, 0}, 50, 0, 0, GLINT_PROJECTION_PERSPECTIVE, 0, 0};
    glint_scene *s = new_scene(&cam, (double[3]){4, 6, 6});
    int red = colored(s, 0.9, 0.1, 0.1);
    glint_material m = glint_material_default();
    m.color[0] = 0.1, m.color[1] = 0.8, m.color[2] = 0.2, m.specular = 0.5, m.shininess = 30;
    int green = material(s, m);
    m = glint_material_default();
    m.color[0] = 0.8, m.color[1] = 0.9, m.transmit = 0.8, m.ior = 1.3;
    int glass = material(s, m);
    object(s, (glint_shape){GLINT_SHAPE_PLANE, .plane = {{0, -1.5, 0}, {0, 1, 0}}}, green, NULL, 0);

    glint_step rx[] = {{GLINT_STEP_ROTATE, {1, 0, 0, 90}}};
    glint_object cut[] = {
        {{GLINT_SHAPE_BOX, .box = {{-1, -1, -1}, {1, 1, 1}}}, -1, NULL, 0},
        {{GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, 1.3}}, green, NULL, 0},
        {{GLINT_SHAPE_CYLINDER, .cylinder = {{0, -2, 0}, 0.4, 4, 1}}, -1, rx, 1},
    };
    glint_step place[] = {{GLINT_STEP_ROTATE, {0, 1, 0, 30}}, {GLINT_STEP_TRANSLATE, {-1.5, 0, 0}}};
    object(s, (glint_shape){GLINT_SHAPE_CSG, .csg = {GLINT_CSG_DIFFERENCE, cut, 3}}, red, place, 2);

    glint_shape octa = {GLINT_SHAPE_POLYHEDRON,
                        .polyhedron = {.preset = GLINT_POLYHEDRON_OCTAHEDRON, .radius = 1.1}};
    glint_object joined[] = {
        {{GLINT_SHAPE_BOX, .box = {{-2, -0.3, -2}, {2, 0.3, 2}}}, -1, NULL, 0},
        {{GLINT_SHAPE_TORUS, .torus = {{0, 0, 0}, 1, 0.4}}, red, NULL, 0},
        {octa, -1, NULL, 0},
        {{GLINT_SHAPE_CONE, .cone = {{0, -1.5, 0}, 0.5, 0, 3, 1}}, -1, NULL, 0},
    };
    glint_step rz[] = {{GLINT_STEP_ROTATE, {0, 0, 1, 45}}};
    glint_object both[] = {
        {{GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, 1.2}}, glass, NULL, 0},
        {{GLINT_SHAPE_CSG, .csg = {GLINT_CSG_UNION, joined, 4}}, green, rz, 1},
    };
    glint_step right[] = {{GLINT_STEP_TRANSLATE, {1.8, 0, 0}}};
    object(s, (glint_shape){GLINT_SHAPE_CSG, .csg = {GLINT_CSG_INTERSECTION, both, 2}}, -1, right, 1);
    expect_same_render(s, csg_yaml);
}
