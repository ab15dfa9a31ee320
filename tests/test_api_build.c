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
    tmpdir_write("scene.yaml", text, path, sizeof path);
    glint_scene *s = NULL;
    OK(glint_scene_load(path, &s, &err));
    return s;
}

/* Renders both with the YAML scene's settings; the films agree and show
 * something (many values differ from the first pixel's). */
static void expect_same_films(glint_scene *code, glint_scene *y)
{
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

static void expect_same_render(glint_scene *code, const char *yaml)
{
    tmpdir_make("api-build");
    glint_scene *y = from_yaml(yaml);
    tmpdir_remove();
    expect_same_films(code, y);
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

/* ---- mesh smoothing ------------------------------------------------------- */

/* An octahedron whose faces meet at 109.5 degrees (normals 70.5 apart):
 * smooth under smooth_angle 90, faceted under 0 or the default 30. */
static const char octahedron_obj[] = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
                                     "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\n"
                                     "f 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

static const char mesh_yaml[] =
    "image: {width: 48, height: 24, samples: 1, background: 0.2}\n"
    "camera: {eye: [0, 1, 6], look_at: [0, 0, 0], up: [0, 1, 0], fov: 38}\n"
    "lights: [{type: point, position: [3, 4, 5]}]\n"
    "objects:\n"
    "  - {type: mesh, file: oct.obj, smooth_angle: 90, material: {color: [0.8, 0.5, 0.2]},\n"
    "     transform: [translate: [-1.2, 0, 0]]}\n"
    "  - {type: mesh, file: oct.obj, smooth_angle: 0, material: {color: [0.8, 0.5, 0.2]},\n"
    "     transform: [translate: [1.2, 0, 0]]}\n";

Test(api_build, mesh_smoothing_angle_as_in_yaml)
{
    tmpdir_make("api-mesh");
    char path[128];
    tmpdir_write("oct.obj", octahedron_obj, path, sizeof path);
    glint_camera cam = {{0, 1, 6}, {0, 0, 0}, {0, 1, 0}, 38, 0, 0, GLINT_PROJECTION_PERSPECTIVE, 0, 0};
    glint_scene *s = new_scene(&cam, (double[3]){3, 4, 5});
    OK(glint_scene_set_background(s, (double[3]){0.2, 0.2, 0.2}, &err));
    int mat = colored(s, 0.8, 0.5, 0.2), smooth = -1, faceted = -1;
    OK(glint_scene_add_mesh_smoothed(s, path, 90, &smooth, &err));
    OK(glint_scene_add_mesh_smoothed(s, path, 0, &faceted, &err));
    glint_step left[] = {{GLINT_STEP_TRANSLATE, {-1.2, 0, 0}}};
    glint_step right[] = {{GLINT_STEP_TRANSLATE, {1.2, 0, 0}}};
    object(s, (glint_shape){GLINT_SHAPE_MESH, .mesh = {smooth}}, mat, left, 1);
    object(s, (glint_shape){GLINT_SHAPE_MESH, .mesh = {faceted}}, mat, right, 1);
    glint_scene *y = from_yaml(mesh_yaml);
    tmpdir_remove();
    expect_same_films(s, y);
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

/* ---- refusals ------------------------------------------------------------- */

/* Refuses the object, leaving the scene as it was: its objects, and all
 * that a pixel depends on (its fingerprint, transforms included). */
static void refuse_object(glint_scene *s, const glint_object *o, const char *words)
{
    glint_scene_counts before, after;
    glint_settings st;
    uint64_t fp_before, fp_after;
    OK(glint_scene_build(s, &err));
    OK(glint_scene_settings(s, &st, &err));
    OK(glint_scene_count(s, &before, &err));
    OK(glint_fingerprint(s, &st, &fp_before, &err));
    REFUSED(glint_scene_add_object(s, o, NULL, &err), words);
    OK(glint_scene_count(s, &after, &err));
    OK(glint_fingerprint(s, &st, &fp_after, &err));
    cr_expect_eq(after.objects, before.objects, "a refused object (%s) was added", words);
    cr_expect_eq(fp_after, fp_before, "a refused object (%s) changed the scene", words);
}

Test(api_build, shapes_out_of_their_rules_are_refused)
{
    glint_scene *s = NULL;
    OK(glint_scene_new(&s, &err));
    int mat = material(s, glint_material_default());
    struct {
        const char *words;
        glint_shape shape;
    } shapes[] = {
        {"cone radius and height must be > 0", {GLINT_SHAPE_CONE, .cone = {{0, 0, 0}, 0, 0, 1, 1}}},
        {"top_radius >= 0", {GLINT_SHAPE_CONE, .cone = {{0, 0, 0}, 1, -1, 1, 1}}},
        {"disk normal must not be zero", {GLINT_SHAPE_DISK, .disk = {{0, 0, 0}, {0, 0, 0}, 1, 0}}},
        {"inner_radius must be >= 0 and less than radius (got 2, radius 1)",
         {GLINT_SHAPE_DISK, .disk = {{0, 0, 0}, {0, 1, 0}, 1, 2}}},
        {"torus major_radius and minor_radius", {GLINT_SHAPE_TORUS, .torus = {{0, 0, 0}, 1, 0}}},
        {"torus major_radius and minor_radius", {GLINT_SHAPE_TORUS, .torus = {{0, NAN, 0}, 1, 1}}},
        {"preset 9 is not one of",
         {GLINT_SHAPE_POLYHEDRON, .polyhedron = {.preset = (glint_polyhedron_preset)9}}},
        {"polyhedron radius must be > 0",
         {GLINT_SHAPE_POLYHEDRON, .polyhedron = {.preset = GLINT_POLYHEDRON_CUBE}}},
        {"polyhedron vertices is NULL", {GLINT_SHAPE_POLYHEDRON, .polyhedron = {.nfaces = 4}}},
        {"triangle uv must be finite",
         {GLINT_SHAPE_TRIANGLE, .triangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, {{0, NAN}}}}},
    };
    glint_step moved[] = {{GLINT_STEP_TRANSLATE, {1, 2, 3}}};
    glint_object o = {.material = mat, .steps = moved, .nsteps = 1};
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++) {
        o.shape = shapes[i].shape;
        refuse_object(s, &o, shapes[i].words);
    }
    /* Vertices and faces: polyhedron_init's findings, in words. */
    glint_polyhedron p = {.vertices = pyramid, .nvertices = 5, .indices = pyramid_faces,
                          .face_sizes = pyramid_sizes, .nfaces = 5};
    o.shape = (glint_shape){GLINT_SHAPE_POLYHEDRON, .polyhedron = p};
    o.shape.polyhedron.nvertices = 3;
    refuse_object(s, &o, "at least 4 vertices and 4 faces (got 3 and 5)");
    o.shape.polyhedron = p;
    o.shape.polyhedron.nfaces = 4;
    refuse_object(s, &o, "the solid is not closed");
    int out_of_range[16], repeat[16], wound[16];
    memcpy(out_of_range, pyramid_faces, sizeof out_of_range);
    memcpy(repeat, pyramid_faces, sizeof repeat);
    memcpy(wound, pyramid_faces, sizeof wound);
    out_of_range[5] = 7;
    repeat[6] = 0;
    wound[5] = 1, wound[6] = 4; /* face 1 turned round */
    const int *bad[] = {out_of_range, repeat, wound};
    const char *why[] = {"vertex index 7 is out of range (the polyhedron has 5 vertices, 0 to 4)",
                         "face 1 names a vertex twice", "both run from vertex"};
    for (int i = 0; i < 3; i++) {
        o.shape.polyhedron = p;
        o.shape.polyhedron.indices = bad[i];
        refuse_object(s, &o, why[i]);
    }
    REFUSED(glint_scene_add_mesh_smoothed(s, "x.obj", 200, NULL, &err), "smooth_angle");
    REFUSED(glint_scene_add_mesh_smoothed(s, NULL, 30, NULL, &err), "path is NULL");
    OK(glint_scene_add_object(s, &(glint_object){{GLINT_SHAPE_POLYHEDRON, .polyhedron = p}, mat,
                                                  NULL, 0},
                              NULL, &err));
    glint_scene_free(s);
}

Test(api_build, csg_out_of_its_rules_is_refused)
{
    glint_scene *s = NULL;
    OK(glint_scene_new(&s, &err));
    int mat = material(s, glint_material_default());
    glint_shape ball = {GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, 1}};
    glint_object two[2] = {{ball, -1, NULL, 0}, {ball, -1, NULL, 0}};
    glint_step moved[] = {{GLINT_STEP_TRANSLATE, {1, 2, 3}}};
    glint_object o = {{GLINT_SHAPE_CSG, .csg = {GLINT_CSG_UNION, two, 1}}, mat, moved, 1};
    refuse_object(s, &o, "a csg needs at least 2 operands (got 1)");
    o.shape.csg = (glint_csg){(glint_csg_op)7, two, 2};
    refuse_object(s, &o, "csg op 7 is not one of glint_csg_op");
    o.shape.csg = (glint_csg){GLINT_CSG_UNION, NULL, 2};
    refuse_object(s, &o, "csg operands is NULL");
    o.shape.csg = (glint_csg){GLINT_CSG_DIFFERENCE, two, 2};
    two[1].shape = (glint_shape){GLINT_SHAPE_PLANE, .plane = {{0, 0, 0}, {0, 1, 0}}};
    refuse_object(s, &o, "operands[1]: does not enclose a solid");
    two[1].shape = (glint_shape){GLINT_SHAPE_CYLINDER, .cylinder = {{0, 0, 0}, 1, 1, 0}};
    refuse_object(s, &o, "operands[1]: does not enclose a solid");
    two[1].shape = ball;
    o.material = -1;
    refuse_object(s, &o, "operands[0]: material is -1 and no csg around it has one");
    two[0].material = 5;
    refuse_object(s, &o, "operands[0]: material 5 was not added");
    /* Nested: the message gives the operand's path. */
    glint_object inner[2] = {{ball, mat, NULL, 0}, {{GLINT_SHAPE_SPHERE, .sphere = {{0, 0, 0}, -1}},
                                                    mat, NULL, 0}};
    two[0] = (glint_object){ball, mat, NULL, 0};
    two[1] = (glint_object){{GLINT_SHAPE_CSG, .csg = {GLINT_CSG_UNION, inner, 2}}, -1, NULL, 0};
    refuse_object(s, &o, "operands[1].operands[1]: sphere radius must be > 0");
    inner[1].shape = ball;
    glint_step flat[] = {{GLINT_STEP_SCALE, {1, 0, 1}}};
    inner[0].steps = flat, inner[0].nsteps = 1;
    refuse_object(s, &o, "operands[1].operands[0]: steps[0]: scale factors must not be 0");
    inner[0].nsteps = 0;
    /* An operand that holds its own csg nests without end: refused. */
    inner[1] = two[1];
    refuse_object(s, &o, "nest more than 256 deep");
    inner[1] = (glint_object){ball, mat, NULL, 0};
    OK(glint_scene_add_object(s, &o, NULL, &err));

    /* A mesh is an operand when it is closed; with material -1 it keeps
     * its own materials. */
    tmpdir_make("api-csg");
    char open_path[128], closed_path[128];
    tmpdir_write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", open_path,
                 sizeof open_path);
    tmpdir_write("closed.obj",
                 "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
                 closed_path, sizeof closed_path);
    int open_mesh = -1, closed_mesh = -1;
    OK(glint_scene_add_mesh(s, open_path, &open_mesh, &err));
    OK(glint_scene_add_mesh_smoothed(s, closed_path, 0, &closed_mesh, &err));
    tmpdir_remove();
    two[0] = (glint_object){{GLINT_SHAPE_MESH, .mesh = {open_mesh}}, -1, NULL, 0};
    two[1] = (glint_object){{GLINT_SHAPE_MESH, .mesh = {closed_mesh}}, -1, NULL, 0};
    refuse_object(s, &o, "operands[0]: mesh cannot be a csg operand: it is not a closed surface");
    two[0] = two[1];
    OK(glint_scene_add_object(s, &o, NULL, &err));
    OK(glint_scene_build(s, &err));
    glint_scene_free(s);
}

Test(api_build, textures_materials_and_fog_out_of_their_rules_are_refused)
{
    glint_scene *s = NULL;
    OK(glint_scene_new(&s, &err));
    glint_texture t = glint_texture_default(GLINT_TEXTURE_IMAGE);
    t.file = GLINT_SOURCE_DIR "/scenes/textures/globe.png";
    t.mapping = GLINT_MAPPING_SPHERICAL;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err),
            "mapping spherical projects a point in space: space must be object or world");
    t.mapping = GLINT_MAPPING_UV, t.space = GLINT_SPACE_WORLD;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "an image with mapping uv is on (u, v)");
    t.mapping = GLINT_MAPPING_PLANAR, t.axis = 3;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "axis must be 0 (x), 1 (y) or 2 (z)");
    t.mapping = (glint_mapping)8;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "mapping 8 is not one of");
    t = glint_texture_default(GLINT_TEXTURE_NOISE);
    t.space = (glint_texture_space)4;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "space 4 is not one of");
    t = glint_texture_default(GLINT_TEXTURE_NOISE);
    t.scale_z = 0;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "scale_z must not be 0");
    t = glint_texture_default(GLINT_TEXTURE_STRIPES);
    t.ncolors = GLINT_COLOR_MAP_MAX + 1;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "colors must have 1 to 16 stops (got 17)");
    set_stops(&t, 2, (glint_color_stop[]){{1, {1, 1, 1}}, {0.5, {0, 0, 0}}});
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "ascending order of value (0.5 after 1)");
    set_stops(&t, 1, (glint_color_stop[]){{0, {-1, 0, 0}}});
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "colors[0]");
    t = glint_texture_default(GLINT_TEXTURE_TURBULENCE);
    t.octaves = 17;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "octaves must be 1 to 16 (got 17)");
    t = glint_texture_default(GLINT_TEXTURE_WOOD);
    t.gain = 0;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "lacunarity and gain must be > 0");
    t = glint_texture_default(GLINT_TEXTURE_MARBLE);
    t.turbulence = -1;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "turbulence must be >= 0");
    glint_step flat[] = {{GLINT_STEP_SCALE, {0, 1, 1}}};
    t = glint_texture_default(GLINT_TEXTURE_MARBLE);
    t.steps = flat, t.nsteps = 1;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "steps[0]: scale factors must not be 0");
    t.steps = NULL;
    REFUSED(glint_scene_add_texture(s, &t, NULL, &err), "steps is NULL");
    glint_scene_counts counts;
    OK(glint_scene_count(s, &counts, &err));
    cr_expect_eq(counts.textures, 0, "a refused texture was added");

    int on_uv = -1, in_space = -1;
    t = glint_texture_default(GLINT_TEXTURE_CHECKER);
    OK(glint_scene_add_texture(s, &t, &on_uv, &err));
    t = glint_texture_default(GLINT_TEXTURE_NOISE);
    OK(glint_scene_add_texture(s, &t, &in_space, &err));
    glint_material m = glint_material_default();
    m.bump = 1, m.bump_texture = on_uv;
    REFUSED(glint_scene_add_material(s, &m, NULL, &err),
            "a bump pattern must be in space object or world");
    m.bump_texture = 7;
    REFUSED(glint_scene_add_material(s, &m, NULL, &err), "bump_texture 7 was not added");
    m.bump_texture = in_space, m.bump_strength = INFINITY;
    REFUSED(glint_scene_add_material(s, &m, NULL, &err), "bump_strength must be finite");
    m.bump_strength = -2; /* any finite strength: negative bumps dent */
    OK(glint_scene_add_material(s, &m, NULL, &err));

    glint_fog f = glint_fog_default(GLINT_FOG_EXPONENTIAL);
    REFUSED(glint_scene_set_fog(s, &f, &err), "density must be > 0");
    f = glint_fog_default(GLINT_FOG_LINEAR);
    f.start = 5, f.end = 5;
    REFUSED(glint_scene_set_fog(s, &f, &err), "end greater than start");
    f.end = 6, f.height_falloff = -1;
    REFUSED(glint_scene_set_fog(s, &f, &err), "height_falloff must be >= 0");
    f.height_falloff = 0, f.color[1] = -0.5;
    REFUSED(glint_scene_set_fog(s, &f, &err), "colour components >= 0");
    f = glint_fog_default((glint_fog_kind)9);
    REFUSED(glint_scene_set_fog(s, &f, &err), "fog kind is not one of");
    REFUSED(glint_scene_set_fog(s, NULL, &err), "fog is NULL");
    f = glint_fog_default(GLINT_FOG_NONE);
    OK(glint_scene_set_fog(s, &f, &err));
    glint_scene_free(s);
}
