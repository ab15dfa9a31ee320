/* The scene loader (src/load/): what each part of the
 * format means, that scenes/seed.yaml is exactly the built-in scene, that
 * every scene in scenes/ loads and renders, and one test per class of bad
 * input asserting the exact one-line message and GLINT_ERR_INPUT (exit
 * code 2). Most scenes here live in memory, served with their includes and
 * textures by mem_reader, so messages name short, stable paths. */
#include <criterion/criterion.h>
#include <errno.h>
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "glint.h"
#include "core/error.h"
#include "load/assets.h"
#include "load/load.h"
#include "load/yaml_doc.h"
#include "scene/scene.h"
#include "film.h"
#include "load_check.h"

/* ---- the seed scene and the gallery ----------------------------------- */

Test(load, seed_yaml_renders_exactly_like_the_builtin_scene)
{
    scene *file = NULL, *builtin = NULL;
    glint_error err = {0};
    glint_rc rc = access(SCENES "/textures/globe.png", R_OK) == 0
                      ? scene_load_file(SCENES "/seed.yaml", &file, &err)
                      : load_path(SCENES "/seed.yaml", &file, &err);
    cr_assert_eq(rc, GLINT_OK, "%s", err.msg);
    cr_assert_eq(glint_scene_builtin(&builtin, &err), GLINT_OK, "%s", err.msg);

    glint_settings a, b;
    glint_scene_settings(file, &a, NULL);
    glint_scene_settings(builtin, &b, NULL);
    cr_expect_eq(memcmp(&a, &b, sizeof a), 0, "the image settings differ");
    cr_expect_eq(file->nobjects, builtin->nobjects);
    cr_expect_eq(file->nlights, builtin->nlights);

    glint_film fa = render(file, 100, 100, 0), fb = render(builtin, 100, 100, 0);
    cr_expect_eq(memcmp(fa.rgb, fb.rgb, sizeof(float) * 100 * 100 * 3), 0,
                 "scenes/seed.yaml must render byte-for-byte as the built-in scene");
    glint_film_free(&fa);
    glint_film_free(&fb);
    scene_free(file);
    scene_free(builtin);
}

Test(load, every_scene_in_scenes_loads_and_renders)
{
    glob_t g;
    cr_assert_eq(glob(SCENES "/*.yaml", 0, NULL, &g), 0, "no scenes in " SCENES);
    cr_expect_geq(g.gl_pathc, 6u, "the gallery has a scene per feature");
    for (size_t i = 0; i < g.gl_pathc; i++) {
        scene *s = NULL;
        glint_error err = {0};
        glint_rc rc = load_path(g.gl_pathv[i], &s, &err);
        cr_expect_eq(rc, GLINT_OK, "%s", err.msg);
        if (rc != GLINT_OK)
            continue;
        cr_expect_gt(s->nobjects, 0, "%s has no objects", g.gl_pathv[i]);
        glint_film film = render(s, 64, 64, 1);
        float peak = 0.0f;
        for (size_t k = 0; k < 64 * 64 * 3; k++)
            peak = film.rgb[k] > peak ? film.rgb[k] : peak;
        cr_expect_gt(peak, 0.05f, "%s renders black", g.gl_pathv[i]);
        /* Every feature renders the same for any thread count. */
        for (int threads = 1; threads <= 3; threads += 2) {
            glint_film other = test_render(s, 64, 64, 1, threads);
            cr_expect_eq(memcmp(film.rgb, other.rgb, sizeof(float) * 64 * 64 * 3), 0,
                         "%s differs with %d threads", g.gl_pathv[i], threads);
            glint_film_free(&other);
        }
        glint_film_free(&film);
        scene_free(s);
    }
    globfree(&g);
}

Test(load, include_resolves_against_the_including_file_on_disk)
{
    scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(load_path(SCENES "/include.yaml", &s, &err), GLINT_OK, "%s", err.msg);
    cr_expect_gt(s->nlights, 0, "lights come from parts/lights.yaml");
    scene_free(s);
}

/* ---- what the format means -------------------------------------------- */

Test(load, settings_camera_and_defaults)
{
    scene *s = load_ok("image: {width: 320, height: 200, samples: 9, depth: 3,\n"
                       "        background: [0.1, 0.2, 0.3], transfer: srgb, adc_bailout: 0.01}\n"
                       "camera: {eye: [1, 2, 3], look_at: [0, 0, 0], fov: 45}\n"
                       "ambient: [0.1, 0.2, 0.3]\n"
                       "objects: [{type: sphere, center: [0, 0, 0], radius: 1}]\n");
    cr_expect_eq(s->settings.width, 320);
    cr_expect_eq(s->settings.height, 200);
    cr_expect_eq(s->settings.samples, 9);
    cr_expect_eq(s->settings.max_depth, 3);
    cr_expect_eq(s->settings.transfer, GLINT_TRANSFER_SRGB);
    cr_expect_float_eq(s->settings.adc_bailout, 0.01, 1e-9);
    cr_expect_eq(s->background.z, 0.3f);
    cr_expect_eq(s->camera.eye.y, 2.0f);
    cr_expect_eq(s->camera.up.y, 1.0f, "up defaults to +y");
    cr_expect_eq(s->camera.hfov, 45.0f);
    cr_expect_eq(s->ambient.y, 0.2f);
    cr_expect_eq(s->nmaterials, 1, "objects without a material share the default");
    cr_expect_eq(s->materials[0].diffuse, 1.0f);
    cr_expect_eq(s->objects[0].xform, -1);
    scene_free(s);

    s = load_ok("objects: [{type: plane, point: [0, 0, 0], normal: [0, 2, 0]}]\n");
    cr_expect_eq(s->settings.width, 500, "defaults are scene_new's");
    cr_expect_eq(s->settings.samples, 1);
    cr_expect_float_eq(s->settings.adc_bailout, 1.0 / 255, 1e-12, "POV-Ray's default");
    cr_expect_eq(s->ambient.x, 0.2f);
    cr_expect_eq(s->objects[0].shape.plane.normal.y, 1.0f, "plane normals are normalised");
    scene_free(s);
}

Test(load, an_empty_mapping_is_an_empty_scene)
{
    scene *s = load_ok("{}");
    cr_expect_eq(s->nobjects, 0);
    cr_expect(s->built);
    scene_free(s);
    s = load_ok("objects: []\nlights: []\ntextures: {}\nmaterials: {}\ninclude: []\n");
    cr_expect_eq(s->nobjects, 0);
    scene_free(s);
}

Test(load, every_shape)
{
    scene *s = load_ok("objects:\n"
                       "  - {type: sphere, center: [1, 2, 3], radius: 4}\n"
                       "  - {type: plane, point: [0, -1, 0], normal: [0, 1, 0]}\n"
                       "  - {type: quad, origin: [0, 0, 0], edge_u: [1, 0, 0], edge_v: [0, 1, 0]}\n"
                       "  - {type: box, min: [-1, -2, -3], max: [1, 2, 3]}\n"
                       "  - {type: cylinder, base: [0, 0, 0], radius: 2, height: 5, capped: false}\n"
                       "  - {type: triangle, p0: [0, 0, 0], p1: [1, 0, 0], p2: [0, 1, 0],\n"
                       "     uv: [[0, 0], [0.5, 0], [0, 0.25]]}\n");
    cr_assert_eq(s->nobjects, 6);
    cr_expect_eq(s->objects[0].shape.kind, SHAPE_SPHERE);
    cr_expect_eq(s->objects[0].shape.sphere.radius, 4.0f);
    cr_expect_eq(s->objects[1].shape.kind, SHAPE_PLANE);
    cr_expect_eq(s->objects[2].shape.kind, SHAPE_QUAD);
    cr_expect_eq(s->objects[3].shape.box.lo.z, -3.0f);
    cr_expect_eq(s->objects[4].shape.cylinder.height, 5.0f);
    cr_expect_not(s->objects[4].shape.cylinder.capped);
    cr_expect_eq(s->objects[5].shape.triangle.uv[2][1], 0.25f);
    scene_free(s);

    s = load_ok("objects: [{type: cylinder, base: [0, 0, 0], radius: 1, height: 1}]\n");
    cr_expect(s->objects[0].shape.cylinder.capped, "cylinders are capped by default");
    scene_free(s);
}

Test(load, materials_textures_and_names_in_any_order)
{
    scene *s = load_ok("objects:\n"
                       "  - {type: sphere, center: [0, 0, 0], radius: 1, material: tiles}\n"
                       "  - {type: sphere, center: [0, 0, 0], radius: 1,\n"
                       "     material: {color: 0.5, texture: {type: checker, scale: 4}}}\n"
                       "materials:\n"
                       "  tiles: {texture: chequer, ambient: 0.5, diffuse: 0.7, specular: 0.3,\n"
                       "          shininess: 12, reflect: 0.25, transmit: 0.5, ior: 1.33,\n"
                       "          tint: [1, 0.5, 0.25], color: [0.9, 0.8, 0.7]}\n"
                       "textures:\n"
                       "  chequer: {type: checker, even: 1, odd: [0.5, 0, 0], scale: [2, 3],\n"
                       "            offset: [0.5, 0.25]}\n"
                       "  picture: {type: image, file: textures/globe.png, wrap: [clamp, repeat]}\n"
                       "  same: {type: image, file: ./textures/../textures/globe.png}\n");
    cr_assert_eq(s->nobjects, 2);
    const material *tiles = &s->materials[s->objects[0].material];
    cr_expect_eq(tiles->ior, 1.33f);
    cr_expect_eq(tiles->tint.z, 0.25f);
    cr_expect_eq(tiles->reflect, 0.25f);
    cr_assert_geq(tiles->texture, 0);
    const texture *t = &s->textures[tiles->texture];
    cr_expect_eq(t->kind, TEXTURE_CHECKER);
    cr_expect_eq(t->scale.y, 3.0f);
    cr_expect_eq(t->offset.x, 0.5f);
    cr_expect_eq(t->pattern.map.color[1].x, 0.5f);
    const material *inline_m = &s->materials[s->objects[1].material];
    cr_expect_eq(inline_m->color.y, 0.5f);
    cr_expect_eq(s->textures[inline_m->texture].scale.x, 4.0f);
    cr_expect_eq(s->nimages, 1, "one image for two spellings of the same path");
    bool found = false;
    for (int i = 0; i < s->ntextures; i++)
        if (s->textures[i].kind == TEXTURE_IMAGE && s->textures[i].image.wrap_u == WRAP_CLAMP) {
            cr_expect_eq(s->textures[i].image.wrap_v, WRAP_REPEAT);
            found = true;
        }
    cr_expect(found);
    scene_free(s);
}

Test(load, transforms_apply_in_order)
{
    scene *s = load_ok("objects:\n"
                       "  - type: sphere\n"
                       "    center: [0, 0, 0]\n"
                       "    radius: 1\n"
                       "    transform: [scale: 2, translate: [1, 0, 0]]\n"
                       "  - type: sphere\n"
                       "    center: [0, 0, 0]\n"
                       "    radius: 1\n"
                       "    transform: [translate: [1, 0, 0], scale: [2, 1, 1]]\n"
                       "  - type: sphere\n"
                       "    center: [0, 0, 0]\n"
                       "    radius: 1\n"
                       "    transform:\n"
                       "      - rotate: {axis: [0, 0, 1], angle: 90}\n"
                       "      - shear: {xy: 1}\n"
                       "      - matrix: [1, 0, 0, 5,  0, 1, 0, 0,  0, 0, 1, 0]\n"
                       "      - matrix: [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 1,  0, 0, 0, 1]\n"
                       "      - rotate_x: 0\n"
                       "      - rotate_z: 0\n"
                       "  - {type: sphere, center: [0, 0, 0], radius: 1, transform: []}\n");
    cr_assert_eq(s->nobjects, 4);
    vec3 p = mat4_point(&s->xforms[s->objects[0].xform].fwd, v3(1, 0, 0));
    cr_expect_float_eq(p.x, 3.0f, 1e-6f, "scale first, then translate");
    p = mat4_point(&s->xforms[s->objects[1].xform].fwd, v3(1, 0, 0));
    cr_expect_float_eq(p.x, 4.0f, 1e-6f, "translate first, then scale");
    /* (1, 0, 0) -> rotate -> (0, 1, 0) -> shear x += y -> (1, 1, 0)
     * -> x += 5 -> (6, 1, 0) -> z += 1 -> (6, 1, 1). */
    p = mat4_point(&s->xforms[s->objects[2].xform].fwd, v3(1, 0, 0));
    cr_expect_float_eq(p.x, 6.0f, 1e-5f);
    cr_expect_float_eq(p.y, 1.0f, 1e-5f);
    cr_expect_float_eq(p.z, 1.0f, 1e-5f);
    cr_expect_eq(s->objects[3].xform, -1, "an empty list is no transform");
    cr_expect_eq(s->nxforms, 3);
    scene_free(s);
}

Test(load, anchors_aliases_and_merge_keys)
{
    scene *s = load_ok("materials:\n"
                       "  base: &base {color: [1, 0, 0], specular: 0.5, shininess: 10}\n"
                       "  shiny: {<<: *base, specular: 1}\n"
                       "objects:\n"
                       "  - &ball {type: sphere, center: [0, 0, -5], radius: 1, material: shiny}\n"
                       "  - {<<: *ball, center: [3, 0, -5]}\n"
                       "  - *ball\n"
                       "  - <<: [{radius: 7}, *ball]\n"
                       "    material: *base\n");
    cr_assert_eq(s->nobjects, 4);
    cr_expect_eq(s->objects[1].shape.sphere.center.x, 3.0f, "own keys win over merged ones");
    cr_expect_eq(s->objects[1].shape.sphere.radius, 1.0f);
    cr_expect_eq(s->objects[2].shape.sphere.center.z, -5.0f);
    cr_expect_eq(s->objects[3].shape.sphere.radius, 7.0f, "earlier merged mappings win");
    const material *shiny = &s->materials[s->objects[0].material];
    cr_expect_eq(shiny->color.x, 1.0f);
    cr_expect_eq(shiny->specular, 1.0f);
    cr_expect_eq(shiny->shininess, 10.0f);
    cr_expect_eq(s->materials[s->objects[3].material].specular, 0.5f, "an alias inlines");
    scene_free(s);
}

Test(load, numbers_in_every_core_schema_form)
{
    scene *s = load_ok("image: {width: 0x40, height: 0o100, samples: !!int 4}\n"
                       "objects:\n"
                       "  - {type: sphere, center: [.5, -1., +2e1], radius: 1E-1}\n");
    cr_expect_eq(s->settings.width, 64);
    cr_expect_eq(s->settings.height, 64);
    cr_expect_eq(s->settings.samples, 4);
    vec3 c = s->objects[0].shape.sphere.center;
    cr_expect_eq(c.x, 0.5f);
    cr_expect_eq(c.y, -1.0f);
    cr_expect_eq(c.z, 20.0f);
    cr_expect_eq(s->objects[0].shape.sphere.radius, 0.1f, "rounded like the C literal 0.1f");
    scene_free(s);
}

Test(load, include_merges_after_the_includer)
{
    vfile files[] = {
        {"parts/look.yaml",
         "camera: {fov: 60, eye: [0, 1, 0]}\n"
         "image: {samples: 16}\n"
         "lights: [{type: point, position: [0, 9, 0]}]\n"
         "materials: {red: {color: [1, 0, 0]}}\n"
         "objects: [{type: box, min: [0, 0, 0], max: [1, 1, 1], material: red}]\n"
         "include: more.yaml\n"},
        {"parts/more.yaml", "objects: [{type: sphere, center: [0, 0, 0], radius: 2}]\n"},
        {NULL, NULL},
    };
    scene *s = load_ok_with("include: [parts/look.yaml]\n"
                            "camera: {fov: 30}\n"
                            "objects: [{type: sphere, center: [0, 0, -5], radius: 1, "
                            "material: red}]\n",
                            files);
    cr_expect_eq(s->camera.hfov, 30.0f, "the includer's settings win");
    cr_expect_eq(s->camera.eye.y, 1.0f, "the rest come from the include");
    cr_expect_eq(s->settings.samples, 16);
    cr_expect_eq(s->nlights, 1);
    cr_assert_eq(s->nobjects, 3);
    cr_expect_eq(s->objects[0].shape.kind, SHAPE_SPHERE, "the includer's objects first");
    cr_expect_eq(s->objects[1].shape.kind, SHAPE_BOX);
    cr_expect_eq(s->objects[2].shape.sphere.radius, 2.0f, "nested includes resolve from parts/");
    cr_expect_eq(s->materials[s->objects[0].material].color.y, 0.0f);
    scene_free(s);
}

Test(load, scene_load_file_reads_from_disk)
{
    char dir[] = "/tmp/glint-load-XXXXXX", path[128];
    cr_assert_not_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f);
    fputs("objects: [{type: sphere, center: [0, 0, -5], radius: 1}]\n", f);
    fclose(f);
    scene *s = NULL;
    glint_error err = {0};
    cr_expect_eq(glint_scene_load(path, &s, &err), GLINT_OK, "%s", err.msg);
    cr_expect_eq(s->nobjects, 1);
    scene_free(s);
    remove(path);

    snprintf(path, sizeof path, "%s/missing.yaml", dir);
    s = NULL;
    cr_expect_eq(scene_load_file(path, &s, &err), GLINT_ERR_INPUT);
    char want[256];
    snprintf(want, sizeof want, "%s: cannot read scene: No such file or directory", path);
    cr_expect_str_eq(err.msg, want);
    cr_expect_null(s);
    rmdir(dir);
}

/* ---- bad input: one test per class ------------------------------------ */

Test(load_errors, yaml_syntax)
{
    expect_error("objects:\n  - {type: sphere\n",
                 "scene.yaml:3:1: did not find expected ',' or '}' (while parsing a flow "
                 "mapping at line 2, column 5)");
    expect_error("camera:\n  eye: [0, 0, 0]\n fov: 30\n",
                 "scene.yaml:3:2: did not find expected key (while parsing a block mapping at "
                 "line 1, column 1)");
    expect_error("ambient: \"0.2\n", "scene.yaml:2:1: found unexpected end of stream (while "
                                     "scanning a quoted scalar at line 1, column 10)");
    /* libyaml's words for a tab in the indentation did not say what was
     * wrong ("found character that cannot start any token"). */
    expect_error("ambient: 0.2\n\tlights: []\n",
                 "scene.yaml:2:1: tabs cannot indent YAML; use spaces");
    expect_error("camera:\n\teye: [0, 0, 0]\n",
                 "scene.yaml:2:1: tabs cannot indent YAML; use spaces");
    expect_error("camera:\n  eye: [0, 0, 0]\n \t fov: 30\n",
                 "scene.yaml:3:2: tabs cannot indent YAML; use spaces");
    expect_error("objects:\n\t- {type: sphere}\n",
                 "scene.yaml:2:1: tabs cannot indent YAML; use spaces");
    /* A tab between a key and its value is white space, as YAML says. */
    scene *s = load_ok("image:\t{width: 7, height: 5}\n");
    cr_expect_eq(scene_settings(s).width, 7);
    scene_free(s);
    expect_error("ambient: \"\xff\"\n", "scene.yaml:1:11: invalid leading UTF-8 octet (byte 0xFF)");
    expect_error("objects: *nothing\n",
                 "scene.yaml:1:10: alias '*nothing' names no anchor defined before it");
    expect_error("ambient: 0.2\n---\nambient: 0.3\n",
                 "scene.yaml:2:1: a second YAML document: a scene file holds one document");
    expect_error("ambient: !color 0.2\n", "scene.yaml:1:10: unsupported tag '!color'");
    expect_error("ambient: !!int 0.2\n", "scene.yaml:1:10: '0.2' is not a valid !!int");
    /* Found by fuzzing: an empty collection before any other. */
    expect_error("# She\n {}x, c", "scene.yaml:2:4: did not find expected <document start>");
}

Test(load_errors, unknown_keys_with_suggestions)
{
    expect_error("objects:\n"
                 "  - type: sphere\n"
                 "    center: [0, 0, -5]\n"
                 "    radus: 3\n",
                 "scene.yaml:4:5: unknown key 'radus' in sphere (did you mean 'radius'?)");
    expect_error("objets: []\n",
                 "scene.yaml:1:1: unknown key 'objets' at the top level (did you mean "
                 "'objects'?)");
    expect_error("materials: {m: {colour_map: 1}}\n",
                 "scene.yaml:1:17: unknown key 'colour_map' in material (valid: color, "
                 "texture, ambient, diffuse, specular, shininess, reflect, transmit, ior, tint, "
                 "fresnel, absorption, emission, bump)");
    expect_error("camera: {fov: 30, look-at: [0, 0, -1]}\n",
                 "scene.yaml:1:19: unknown key 'look-at' in camera (did you mean 'look_at'?)");
    expect_error("objects: [{type: box, min: [0, 0, 0], max: [1, 1, 1], radius: 1}]\n",
                 "scene.yaml:1:55: unknown key 'radius' in box (valid: type, min, max, "
                 "material, transform)");
    expect_error("objects: [{type: sphear, center: [0, 0, 0], radius: 1}]\n",
                 "scene.yaml:1:18: unknown object type 'sphear' (did you mean 'sphere'?)");
    expect_error("lights: [{type: spott, position: [0, 0, 0]}]\n",
                 "scene.yaml:1:17: unknown light type 'spott' (did you mean 'spot'?)");
    expect_error("lights: [{type: laser, position: [0, 0, 0]}]\n",
                 "scene.yaml:1:17: unknown light type 'laser' (valid: point, directional, "
                 "spot, area)");
    expect_error("image: {transfer: sRGB}\n",
                 "scene.yaml:1:19: unknown transfer 'sRGB' (did you mean 'srgb'?)");
    expect_error("textures: {t: {type: image, file: x.png, wrap: [repeat, mirror]}}\n",
                 "scene.yaml:1:57: unknown wrap mode 'mirror' (valid: repeat, clamp)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [{rotate_q: 30}]}]\n",
                 "scene.yaml:2:26: unknown transform 'rotate_q' (did you mean 'rotate_x'?)");
    /* Distant words get the list, not another word: 'type' is two edits
     * from 'eye', too many for four letters; a swap of two letters is one. */
    expect_error("camera: {type: thin_lens}\n",
                 "scene.yaml:1:10: unknown key 'type' in camera (valid: eye, look_at, up, fov, "
                 "aperture, focus_distance, width, shutter, projection)");
    expect_error("camera: {eey: [0, 0, 0]}\n",
                 "scene.yaml:1:10: unknown key 'eey' in camera (did you mean 'eye'?)");
    expect_error("objects: [{type: cyl, base: [0, 0, 0]}]\n",
                 "scene.yaml:1:18: unknown object type 'cyl' (valid: sphere, plane, quad, box, "
                 "cylinder, triangle, mesh, cone, disk, torus, polyhedron, csg)");
}

Test(load_errors, wrong_types_and_lengths)
{
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: [3]}]\n",
                 "scene.yaml:1:53: expected a number for 'radius', got a sequence");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: \"3\"}]\n",
                 "scene.yaml:1:53: expected a number for 'radius', got the string '3'");
    expect_error("objects: [{type: sphere, center: [0, 0], radius: 3}]\n",
                 "scene.yaml:1:34: expected 3 numbers for 'center', got 2");
    expect_error("objects: [{type: sphere, center: [0, zero, 0], radius: 3}]\n",
                 "scene.yaml:1:38: expected a number for 'center', got the string 'zero'");
    expect_error("objects: [{type: sphere, center: 0, radius: 3}]\n",
                 "scene.yaml:1:34: expected [x, y, z] for 'center', got a number");
    expect_error("ambient: [1, 1, 1, 1]\n", "scene.yaml:1:10: expected 3 numbers for 'ambient', got 4");
    expect_error("ambient: white\n",
                 "scene.yaml:1:10: expected a number or [r, g, b] for 'ambient', got the string "
                 "'white'");
    expect_error("objects: [{type: cylinder, base: [0, 0, 0], radius: 1, height: 1, capped: yes}]\n",
                 "scene.yaml:1:75: expected true or false for 'capped', got the string 'yes'");
    expect_error("image: {width: 640.5}\n",
                 "scene.yaml:1:16: expected a whole number for 'width', got 640.5");
    expect_error("objects: {type: sphere}\n", "scene.yaml:1:10: expected a list for 'objects', got a mapping");
    expect_error("objects: [sphere]\n",
                 "scene.yaml:1:11: expected a mapping for 'objects', got the string 'sphere'");
    expect_error("camera: [0, 0, 0]\n", "scene.yaml:1:9: expected a mapping for 'camera', got a sequence");
    expect_error("materials: {m: {texture: [1]}}\n",
                 "scene.yaml:1:26: expected a texture name or mapping for 'texture', got a sequence");
    expect_error("materials: {m: 3}\n", "scene.yaml:1:16: expected a mapping for material 'm', got a number");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1, material: ~}]\n",
                 "scene.yaml:1:66: expected a material name or mapping for 'material', got nothing");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1, transform: {scale: 2}}]\n",
                 "scene.yaml:1:67: expected a list of steps for 'transform', got a mapping");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [{scale: 2, translate: [0, 0, 0]}]}]\n",
                 "scene.yaml:2:25: a transform step is a mapping with one key, such as "
                 "{translate: [1, 2, 3]}, got a mapping with 2 keys");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [matrix: [1, 0, 0, 0, 1, 0, 0, 0, 1]]}]\n",
                 "scene.yaml:2:33: expected 12 or 16 numbers for 'matrix', got 9");
    expect_error("objects: [{type: triangle, p0: [0, 0, 0], p1: [1, 0, 0], p2: [0, 1, 0],\n"
                 "            uv: [[0, 0], [1, 0]]}]\n",
                 "scene.yaml:2:17: expected 3 [u, v] pairs for 'uv', got 2");
    expect_error("textures: {t: {type: checker, scale: [1, 2, 3]}}\n",
                 "scene.yaml:1:38: expected 2 numbers for 'scale', got 3");
    expect_error("include: 3\n", "scene.yaml:1:10: expected a file path or a list of them for 'include', got a number");
    expect_error("materials: {[a]: {}}\n",
                 "scene.yaml:1:13: a mapping key must be a single value, not a sequence");
    expect_error("materials: {~: {}}\n", "scene.yaml:1:13: a material name must be a string, got nothing");
    expect_error("objects: [{<<: 3}]\n",
                 "scene.yaml:1:16: a merge key '<<' takes a mapping or a list of mappings, not a number");
}

Test(load_errors, missing_required_fields)
{
    expect_error("objects:\n  - type: sphere\n    center: [0, 0, -5]\n",
                 "scene.yaml:2:5: sphere needs 'radius'");
    expect_error("objects: [{center: [0, 0, 0]}]\n", "scene.yaml:1:11: object needs 'type'");
    expect_error("objects: [{type: quad, origin: [0, 0, 0], edge_u: [1, 0, 0]}]\n",
                 "scene.yaml:1:11: quad needs 'edge_v'");
    expect_error("lights: [{type: point}]\n", "scene.yaml:1:10: point light needs 'position'");
    expect_error("textures: {t: {type: image}}\n", "scene.yaml:1:15: image texture needs 'file'");
    expect_error("textures: {t: {file: a.png}}\n", "scene.yaml:1:15: texture needs 'type'");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [rotate: {angle: 3}]}]\n",
                 "scene.yaml:2:33: rotate needs 'axis'");
}

Test(load_errors, out_of_range_and_non_finite_numbers)
{
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: -3}]\n",
                 "scene.yaml:1:53: radius must be > 0 (got -3)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: .nan}]\n",
                 "scene.yaml:1:53: radius must be a finite number (got .nan)");
    expect_error("objects: [{type: sphere, center: [0, -.inf, 0], radius: 1}]\n",
                 "scene.yaml:1:38: center must be a finite number (got -.inf)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1e39}]\n",
                 "scene.yaml:1:53: radius is too large (got 1e39)");
    expect_error("objects: [{type: cylinder, base: [0, 0, 0], radius: 1, height: 0}]\n",
                 "scene.yaml:1:64: height must be > 0 (got 0)");
    expect_error("objects: [{type: box, min: [0, 0, 0], max: [1, -1, 1]}]\n",
                 "scene.yaml:1:44: max must be greater than min on every axis (y: min 0, max -1)");
    expect_error("objects: [{type: plane, point: [0, 0, 0], normal: [0, 0, 0]}]\n",
                 "scene.yaml:1:51: normal must not be [0, 0, 0]");
    expect_error("objects: [{type: quad, origin: [0, 0, 0], edge_u: [1, 0, 0], edge_v: [2, 0, 0]}]\n",
                 "scene.yaml:1:70: edge_v must not be parallel to edge_u (nor either be zero)");
    expect_error("objects: [{type: triangle, p0: [0, 0, 0], p1: [1, 1, 1], p2: [2, 2, 2]}]\n",
                 "scene.yaml:1:11: triangle is degenerate: p0, p1 and p2 lie on one line");
    /* Corners near 1e38: the float cross product overflowed and the
     * triangle was kept with no normal (and never seen). */
    expect_error("objects: [{type: triangle, p0: [0, 0, 0], p1: [1e38, 0, 0], p2: [0, 1e38, 0]}]\n",
                 "scene.yaml:1:11: triangle is too large for single precision (its normal "
                 "overflows); scale it down");
    expect_error("materials: {m: {reflect: 1.5}}\n",
                 "scene.yaml:1:26: reflect must be between 0 and 1 (got 1.5)");
    expect_error("image: {adc_bailout: -0.1}\n",
                 "scene.yaml:1:22: adc_bailout must be between 0 and 1 (got -0.1)");
    expect_error("materials: {m: {ior: 0}}\n", "scene.yaml:1:22: ior must be > 0 (got 0)");
    expect_error("materials: {m: {color: [1, -0.5, 1]}}\n",
                 "scene.yaml:1:28: color components must be >= 0 (got -0.5)");
    expect_error("ambient: -1\n", "scene.yaml:1:10: ambient must be >= 0 (got -1)");
    expect_error("camera: {fov: 180}\n", "scene.yaml:1:15: fov must be > 0 and < 180 degrees (got 180)");
    expect_error("camera: {eye: [0, 0, 0], look_at: [0, 0, 0]}\n",
                 "scene.yaml:1:9: camera look_at must differ from eye");
    expect_error("camera: {look_at: [0, 5, 0]}\n",
                 "scene.yaml:1:9: camera up must not be parallel to the view direction");
    expect_error("image: {depth: 65}\n", "scene.yaml:1:16: depth must be 0 to 64 (got 65)");
    expect_error("textures: {t: {type: checker, scale: 0}}\n",
                 "scene.yaml:1:38: scale must not be 0 (got 0)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [scale: [1, 0, 1]]}]\n",
                 "scene.yaml:2:36: scale must not be 0 (got 0)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [scale: 1e-39]}]\n",
                 "scene.yaml:2:32: scale makes the transform degenerate (not invertible in floats)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [shear: {xy: 1, yx: 1}]}]\n",
                 "scene.yaml:2:32: shear is not invertible (it flattens space)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [matrix: [1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0]]}]\n",
                 "scene.yaml:2:33: matrix is not invertible");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [matrix: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1]]}]\n",
                 "scene.yaml:2:70: the last row of a 16-number matrix must be 0, 0, 0, 1 "
                 "(transforms are affine)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1,\n"
                 "            transform: [rotate: {axis: [0, 0, 0], angle: 3}]}]\n",
                 "scene.yaml:2:40: axis must not be [0, 0, 0]");
}

Test(load_errors, unknown_material_and_texture_names)
{
    expect_error("materials: {blue: {color: [0, 0, 1]}}\n"
                 "objects: [{type: sphere, center: [0, 0, 0], radius: 1, material: bleu}]\n",
                 "scene.yaml:2:66: unknown material 'bleu' (did you mean 'blue'?)");
    expect_error("objects: [{type: sphere, center: [0, 0, 0], radius: 1, material: red}]\n",
                 "scene.yaml:1:66: unknown material 'red' (no materials are defined)");
    expect_error("materials: {blue: {color: [0, 0, 1]}}\n"
                 "objects: [{type: sphere, center: [0, 0, 0], radius: 1, material: crimson}]\n",
                 "scene.yaml:2:66: unknown material 'crimson'");
    expect_error("textures: {wood: {type: checker}}\n"
                 "materials: {m: {texture: woood}}\n",
                 "scene.yaml:2:26: unknown texture 'woood' (did you mean 'wood'?)");
}

/* Texture files are decoded together at the end of the first pass, on
 * several threads: the first one met that does not decode is the error,
 * even when the pass went on to another; each image lands in its
 * texture. */
Test(load_errors, textures_decoded_together_report_the_first_bad_file)
{
    vfile files[] = {
        {"textures/bad.png", "this is not a PNG file"},
        {"textures/bad2.png", "nor is this"},
        {NULL, NULL},
    };
    const char *bad = ": not an image glint reads (PNG, JPEG, HDR, EXR, PFM, PPM, BMP, TGA, GIF)";
    char want[256];
    snprintf(want, sizeof want, "scene.yaml:2:35: textures/bad.png%s", bad);
    expect_error_with("textures: {a: {type: image, file: textures/flag.png},\n"
                      "           b: {type: image, file: textures/bad.png}}\n"
                      "objects: [{type: sphere, center: [0, 0, 0], radius: -1}]\n",
                      files, want);
    snprintf(want, sizeof want, "scene.yaml:1:35: textures/bad2.png%s", bad);
    expect_error_with("textures: {a: {type: image, file: textures/bad2.png},\n"
                      "           b: {type: image, file: textures/bad.png}}\n",
                      files, want);
    expect_error_with("textures: {a: {type: image, file: textures/flag.png},\n"
                      "           b: {type: image, file: textures/globe.png}}\n"
                      "objects: [{type: sphere, center: [0, 0, 0], radius: -1}]\n",
                      files, "scene.yaml:3:53: radius must be > 0 (got -1)");
    scene *sc = load_ok_with("textures: {a: {type: image, file: textures/globe.png},\n"
                             "           b: {type: image, file: textures/flag.png},\n"
                             "           c: {type: image, file: textures/globe.png}}\n"
                             "materials: {m: {texture: a}, n: {texture: b}, o: {texture: c}}\n",
                             files);
    cr_assert_eq(sc->nimages, 2, "one image per file");
    const int sizes[3][2] = {{1024, 512}, {600, 400}, {1024, 512}};
    for (int t = 0; t < 3; t++) {
        const image *im = &sc->images[sc->textures[t].image.image];
        cr_expect(im->width == sizes[t][0] && im->height == sizes[t][1] && im->rgb,
                  "texture %d: %dx%d", t, im->width, im->height);
    }
    scene_free(sc);
}

Test(load_errors, missing_or_unreadable_files)
{
    vfile files[] = {
        {"locked.yaml", NULL},
        {"textures/locked.png", NULL},
        {"textures/bad.png", "this is not a PNG file"},
        {NULL, NULL},
    };
    expect_error_with("textures: {t: {type: image, file: textures/nope.png}}\n", files,
                      "scene.yaml:1:35: cannot read texture 'textures/nope.png': No such file "
                      "or directory");
    expect_error_with("textures: {t: {type: image, file: ./textures/locked.png}}\n", files,
                      "scene.yaml:1:35: cannot read texture './textures/locked.png' "
                      "(textures/locked.png): Permission denied");
    expect_error_with("textures: {t: {type: image, file: textures/bad.png}}\n", files,
                      "scene.yaml:1:35: textures/bad.png: not an image glint reads (PNG, JPEG, HDR, EXR, PFM, PPM, BMP, TGA, GIF)");
    expect_error_with("include: [parts/nope.yaml]\n", files,
                      "scene.yaml:1:11: cannot read include 'parts/nope.yaml': No such file or "
                      "directory");
    expect_error_with("include: locked.yaml\n", files,
                      "scene.yaml:1:10: cannot read include 'locked.yaml': Permission denied");
    expect_error_with("include: \"\"\n", files, "scene.yaml:1:10: include must not be empty");
    /* Paths with control characters are escaped: a message is one line. */
    expect_error_with("include: \"parts/a\\nb.yaml\"\n", files,
                      "scene.yaml:1:10: cannot read include 'parts/a\\x0Ab.yaml': No such file or "
                      "directory");
    expect_error_with("include: \"a\\0b.yaml\"\n", files,
                      "scene.yaml:1:10: include must not contain a NUL character");

    /* From disk, with the operating system's own reasons. */
    char dir[] = "/tmp/glint-load-XXXXXX", path[128], want[512];
    cr_assert_not_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f);
    fputs("# a scene\ntextures: {t: {type: image, file: missing.png}}\ninclude: [.]\n", f);
    fclose(f);
    scene *s = NULL;
    glint_error err = {0};
    cr_expect_eq(scene_load_file(path, &s, &err), GLINT_ERR_INPUT);
    snprintf(want, sizeof want,
             "%s:2:35: cannot read texture 'missing.png' (%s/missing.png): No such file or "
             "directory",
             path, dir);
    cr_expect_str_eq(err.msg, want);
    f = fopen(path, "w");
    cr_assert_not_null(f);
    fputs("include: [.]\n", f);
    fclose(f);
    cr_expect_eq(scene_load_file(path, &s, &err), GLINT_ERR_INPUT);
    snprintf(want, sizeof want, "%s:1:11: cannot read include '.' (%s): Is a directory", path,
             dir);
    cr_expect_str_eq(err.msg, want);
    cr_expect_null(s);
    remove(path);
    rmdir(dir);
}

Test(load_errors, include_cycles)
{
    vfile files[] = {
        {"a.yaml", "# a\ninclude: b.yaml\n"},
        {"b.yaml", "include: [a.yaml]\n"},
        {"self.yaml", "include: ./self.yaml\n"},
        {"parts/c.yaml", "include: ../parts/d.yaml\n"},
        {"parts/d.yaml", "include: c.yaml\n"},
        {NULL, NULL},
    };
    scene *s = NULL;
    glint_error err = {0};
    const char *a = files[0].text;
    cr_expect_eq(scene_load_text(a, strlen(a), "a.yaml", NULL, mem_reader, files, &s, &err),
                 GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, "a.yaml:2:10: include cycle: a.yaml -> b.yaml -> a.yaml");
    expect_error_with("include: self.yaml\n", files,
                      "self.yaml:1:10: include cycle: self.yaml -> self.yaml");
    expect_error_with("include: parts/c.yaml\n", files,
                      "parts/c.yaml:1:10: include cycle: parts/c.yaml -> parts/d.yaml -> "
                      "parts/c.yaml");
}

Test(load_errors, absurd_sizes_are_refused_before_allocating)
{
    expect_error("image: {width: 100000, height: 10}\n",
                 "scene.yaml:1:16: width must be 1 to 32768 (got 100000)");
    expect_error("image: {width: 99999999999999999999999}\n",
                 "scene.yaml:1:16: width must be 1 to 32768 (got 99999999999999999999999)");
    expect_error("image: {height: 0}\n", "scene.yaml:1:17: height must be 1 to 32768 (got 0)");
    expect_error("image: {width: 32768, height: 32768}\n",
                 "scene.yaml:1:8: resolution 32768x32768 needs more than the 134217728-pixel "
                 "limit");
    expect_error("image: {samples: 4096}\n", "scene.yaml:1:18: samples must be 1 to 1024 (got 4096)");
    expect_error("image: {samples: 5}\n",
                 "scene.yaml:1:18: samples must be a perfect square (1, 4, 9, 16, ...) (got 5)");
}

Test(load_errors, duplicate_keys_and_names)
{
    expect_error("objects:\n"
                 "  - type: sphere\n"
                 "    radius: 1\n"
                 "    center: [0, 0, 0]\n"
                 "    radius: 2\n",
                 "scene.yaml:5:5: duplicate key 'radius' (first at line 3, column 5)");
    expect_error("materials: {a: {}}\nmaterials: {b: {}}\n",
                 "scene.yaml:2:1: duplicate key 'materials' (first at line 1, column 1)");
    vfile files[] = {
        {"more.yaml", "materials:\n  blue: {color: [0, 0, 1]}\n"},
        {NULL, NULL},
    };
    expect_error_with("materials:\n  blue: {color: [0, 0, 0.5]}\ninclude: more.yaml\n", files,
                      "more.yaml:2:3: duplicate material name 'blue' (first defined at "
                      "scene.yaml:2:3)");
}

Test(load_errors, empty_files_and_documents_that_are_not_mappings)
{
    expect_error("", "scene.yaml:1:1: the scene is empty (expected a mapping with keys such as "
                     "camera, lights and objects)");
    expect_error("# nothing but a comment\n\n",
                 "scene.yaml:1:1: the scene is empty (expected a mapping with keys such as "
                 "camera, lights and objects)");
    expect_error("---\n", "scene.yaml:2:1: the scene is empty (expected a mapping with keys such "
                          "as camera, lights and objects)");
    expect_error("- sphere\n- box\n",
                 "scene.yaml:1:1: expected a mapping at the top of the scene, got a sequence");
    expect_error("sphere\n",
                 "scene.yaml:1:1: expected a mapping at the top of the scene, got the string "
                 "'sphere'");
}

/* Serves "chain/N.yaml" as a file including chain/N+1.yaml, and
 * "wide.yaml" as one including leaf.yaml 300 times. */
static glint_rc generated_reader(void *user, const char *path, char **data, size_t *size,
                                 glint_error *err)
{
    (void)user;
    char *text = calloc(1, 8192);
    cr_assert_not_null(text);
    int n;
    if (sscanf(path, "chain/%d.yaml", &n) == 1) {
        snprintf(text, 8192, "include: %d.yaml\n", n + 1);
    } else if (strcmp(path, "wide.yaml") == 0) {
        strcpy(text, "include:\n");
        for (int i = 0; i < 300; i++)
            strcat(text, "  - leaf.yaml\n");
    } else if (strcmp(path, "leaf.yaml") == 0) {
        strcpy(text, "lights: [{type: point, position: [0, 0, 0]}]\n");
    } else {
        free(text);
        return err_set(err, GLINT_ERR_IO, "No such file or directory");
    }
    *data = text;
    *size = strlen(text);
    return GLINT_OK;
}

Test(load_errors, include_depth_and_count_are_bounded)
{
    scene *s = NULL;
    glint_error err = {0};
    const char *deep = "include: chain/1.yaml\n";
    cr_expect_eq(scene_load_text(deep, strlen(deep), "scene.yaml", NULL, generated_reader, NULL,
                                 &s, &err),
                 GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, "chain/31.yaml:1:10: includes nested more than 32 deep");
    const char *wide = "include: wide.yaml\n";
    cr_expect_eq(scene_load_text(wide, strlen(wide), "scene.yaml", NULL, generated_reader, NULL,
                                 &s, &err),
                 GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, "wide.yaml:256:5: more than 256 files included");
    cr_expect_null(s);
}

Test(load_errors, hostile_files_hit_limits_not_the_stack_or_memory)
{
    /* Nesting: far deeper than any scene needs. */
    char deep[4096] = "objects: ";
    for (int i = 0; i < 1000; i++)
        strcat(deep, "[");
    expect_error(deep, "scene.yaml:1:73: collections nested more than 64 deep");

    /* A "billion laughs": each level doubles the tree a walk would visit. */
    char bomb[8192] = "a0: &a0 [1, 2]\n";
    for (int i = 1; i < 64; i++) {
        char line[64];
        snprintf(line, sizeof line, "a%d: &a%d [*a%d, *a%d]\n", i, i, i - 1, i - 1);
        strcat(bomb, line);
    }
    expect_error(bomb, "scene.yaml:18:18: aliases expand the document beyond 1000156 nodes");

    /* An alias inside the collection it names. */
    expect_error("objects: &o [*o]\n",
                 "scene.yaml:1:14: alias '*o' refers to a collection that contains it");
}

/* ---- meshes ----------------------------------------------------------- */

/* A unit tetrahedron, corners at the origin and on the three axes. */
#define TETRA_OBJ                                                                                  \
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"                                                         \
    "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"

Test(load, meshes_are_read_once_and_placed_by_instances)
{
    vfile files[] = {{"models/tetra.obj", TETRA_OBJ}, {NULL, NULL}};
    scene *s = load_ok_with("camera: {eye: [3, 3, 3], look_at: [0.3, 0.3, 0.3], fov: 40}\n"
                            "lights: [{type: point, position: [5, 5, 5]}]\n"
                            "objects:\n"
                            "  - {type: mesh, file: models/tetra.obj, material: {color: [1, 0, 0]}}\n"
                            "  - {type: mesh, file: ./models/../models/tetra.obj,\n"
                            "     transform: [translate: [0, 0, -2]]}\n",
                            files);
    cr_expect_eq(s->nmeshes, 1, "one file, read once");
    cr_assert_eq(s->nobjects, 2);
    cr_expect_eq(s->objects[0].shape.kind, SHAPE_MESH);
    cr_expect_eq(s->objects[0].shape.mesh, s->objects[1].shape.mesh);
    cr_expect_geq(s->objects[0].material, 0, "a material given in the scene wins");
    cr_expect_eq(s->objects[1].material, -1, "without one, the file's own materials");
    const mesh *m = s->objects[0].shape.mesh;
    cr_expect_eq(m->ntris, 4);
    for (int t = 0; t < m->ntris; t++)
        cr_expect(m->tri_material[t] >= 0 && m->tri_material[t] < s->nmaterials);

    /* A ray down the diagonal meets the slanted face x + y + z = 1. */
    ray r = ray_make(v3(2, 2, 2), v3_norm(v3(-1, -1, -1)), INFINITY);
    scene_hit hit;
    cr_assert(scene_intersect(s, &r, &hit));
    cr_expect_eq(hit.object, 0);
    cr_expect_float_eq(hit.h.t, sqrtf(12.0f) - sqrtf(3.0f) / 3.0f, 1e-4f);
    scene_free(s);
}

Test(load, mesh_from_disk_keeps_the_files_materials)
{
    char dir[] = "/tmp/glint-mesh-XXXXXX", path[160];
    cr_assert_not_null(mkdtemp(dir));
    const char *names[] = {"tetra.obj", "tetra.mtl", "scene.yaml"};
    const char *texts[] = {
        "mtllib tetra.mtl\nusemtl green\n" TETRA_OBJ,
        "newmtl green\nKd 0.1 0.8 0.2\nKs 0.5 0.5 0.5\nNs 30\n",
        "objects: [{type: mesh, file: tetra.obj}]\n",
    };
    for (int i = 0; i < 3; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        FILE *f = fopen(path, "w");
        cr_assert_not_null(f);
        fputs(texts[i], f);
        fclose(f);
    }
    scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(scene_load_file(path, &s, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(s->nobjects, 1);
    scene_hit hit = {.object = 0};
    hit.h.part = 0;
    const material *mat = scene_hit_material(s, &hit);
    cr_expect_float_eq(mat->color.y, 0.8f, 1e-6f, "Kd from the .mtl beside the OBJ");
    cr_expect_float_eq(mat->shininess, 30.0f, 1e-6f);
    scene_free(s);
    for (int i = 0; i < 3; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        remove(path);
    }
    rmdir(dir);
}

Test(load_errors, meshes)
{
    vfile files[] = {
        {"bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n"},
        {"text.obj", "this is not a mesh\n"},
        {"huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e38 0 0\nv 0 1e38 0\nf 1 2 3\nf 1 4 5\n"},
        {"lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n"},
        {NULL, NULL},
    };
    expect_error("objects: [{type: mesh}]\n", "scene.yaml:1:11: mesh needs 'file'");
    expect_error("objects: [{type: mesh, file: m.obj, radius: 2}]\n",
                 "scene.yaml:1:37: unknown key 'radius' in mesh (valid: type, file, smooth_angle, "
                 "material, transform)");
    expect_error_with("objects: [{type: mesh, file: nope.obj}]\n", files,
                      "scene.yaml:1:30: cannot read mesh 'nope.obj': No such file or directory");
    expect_error_with("objects: [{type: mesh, file: lines.obj}]\n", files,
                      "scene.yaml:1:30: lines.obj: mesh has no triangles");
    /* assimp's validation spoke of its structures ("Mesh  contains no faces") */
    expect_error_with("objects: [{type: mesh, file: text.obj}]\n", files,
                      "scene.yaml:1:30: text.obj: mesh has no triangles");
    /* A triangle near 1e38 was dropped without a word: now it is dropped
     * with a warning that counts it. */
    {
        scene *hs = NULL;
        glint_error herr = {0};
        const char *htext = "objects: [{type: mesh, file: huge.obj}]\n";
        cr_expect_eq(scene_load_text(htext, strlen(htext), "scene.yaml", NULL, mem_reader, files,
                                     &hs, &herr),
                     GLINT_OK, "%s", herr.msg);
        if (hs)
            cr_expect_str_eq(scene_warnings(hs), "huge.obj: 1 of 2 triangles dropped (1 too large "
                                                 "for single precision (overflow))\n");
        scene_free(hs);
    }

    /* assimp's own reason follows; the start of the message is ours. */
    scene *s = NULL;
    glint_error err = {0};
    const char *text = "objects: [{type: mesh, file: bad.obj}]\n";
    cr_expect_eq(scene_load_text(text, strlen(text), "scene.yaml", NULL, mem_reader, files, &s,
                                 &err),
                 GLINT_ERR_INPUT);
    const char *want = "scene.yaml:1:30: bad.obj: cannot import mesh: ";
    cr_expect_eq(strncmp(err.msg, want, strlen(want)), 0, "got: %s", err.msg);
    cr_expect_null(s);
}

/* Writes text to dir/name. */
static void put_file(const char *dir, const char *name, const char *text)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f, "%s", path);
    fputs(text, f);
    fclose(f);
}

/* A FIFO blocked the loader for ever (nothing writes to it) and devices
 * were read up to the size limit: every path to a file that is not a
 * regular one is refused at once, before a byte is read, naming it. The
 * timeout is the failure on the old code. */
Test(load_errors, fifos_and_devices_are_refused_at_once, .timeout = 20)
{
    char dir[] = "/tmp/glint-fifo-XXXXXX", path[160], want[512];
    cr_assert_not_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/fifo", dir);
    cr_assert_eq(mkfifo(path, 0600), 0);
    static const struct {
        const char *scene, *want; /* want: the message after "DIR/scene.yaml:" */
    } cases[] = {
        {"include: fifo\n", "1:10: cannot read include 'fifo' (%s/fifo): not a regular file"},
        {"textures: {t: {type: image, file: fifo}}\n",
         "1:35: cannot read texture 'fifo' (%s/fifo): not a regular file"},
        {"objects: [{type: mesh, file: fifo}]\n",
         "1:30: cannot read mesh 'fifo' (%s/fifo): not a regular file"},
        {"textures: {t: {type: image, file: /dev/zero}}\n",
         "1:35: cannot read texture '/dev/zero': not a regular file"},
        {"objects: [{type: mesh, file: /dev/urandom}]\n",
         "1:30: cannot read mesh '/dev/urandom': not a regular file"},
        {"include: /dev/zero\n", "1:10: cannot read include '/dev/zero': not a regular file"},
        /* a folder given as a mesh reached assimp ("aiScene::mNumMeshes is 0") */
        {"objects: [{type: mesh, file: .}]\n",
         "1:30: cannot read mesh '.' (%s): Is a directory"},
    };
    snprintf(path, sizeof path, "%s/scene.yaml", dir);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        put_file(dir, "scene.yaml", cases[i].scene);
        scene *s = NULL;
        glint_error err = {0};
        cr_expect_eq(scene_load_file(path, &s, &err), GLINT_ERR_INPUT, "%s", cases[i].scene);
        char tail[256];
        snprintf(tail, sizeof tail, cases[i].want, dir);
        snprintf(want, sizeof want, "%s:%s", path, tail);
        cr_expect_str_eq(err.msg, want);
        cr_expect_null(s);
    }
    /* The scene itself. */
    const char *scenes[] = {"fifo", "/dev/zero", "/dev/null"};
    for (int i = 0; i < 3; i++) {
        char p[160];
        snprintf(p, sizeof p, i == 0 ? "%s/%s" : "%.0s%s", dir, scenes[i]);
        scene *s = NULL;
        glint_error err = {0};
        cr_expect_eq(scene_load_file(p, &s, &err), GLINT_ERR_INPUT);
        snprintf(want, sizeof want, "%s: cannot read scene: not a regular file", p);
        cr_expect_str_eq(err.msg, want);
    }
    remove(path);
    snprintf(path, sizeof path, "%s/fifo", dir);
    remove(path);
    rmdir(dir);
}

/* "-" and /dev/stdin read the scene from standard input: paths in it are
 * relative to the current folder, and messages call it <stdin>. */
Test(load, dash_reads_the_scene_from_standard_input)
{
    char path[] = "/tmp/glint-stdin-XXXXXX";
    int fd = mkstemp(path);
    cr_assert_geq(fd, 0);
    const char *text = "image: {width: 3, height: 2}\ncamera: {fov: [1]}\n";
    cr_assert_eq(write(fd, text, strlen(text)), (ssize_t)strlen(text));
    int saved = dup(STDIN_FILENO);
    const char *names[] = {"-", "/dev/stdin"};
    for (int i = 0; i < 2; i++) {
        cr_assert_eq(lseek(fd, 0, SEEK_SET), 0);
        cr_assert_eq(dup2(fd, STDIN_FILENO), STDIN_FILENO);
        scene *s = NULL;
        glint_error err = {0};
        cr_expect_eq(scene_load_file(names[i], &s, &err), GLINT_ERR_INPUT);
        cr_expect_str_eq(err.msg, "<stdin>:2:15: expected a number for 'fov', got a sequence");
    }
    /* Through a pipe, which a path on disk may not be. */
    int p[2];
    cr_assert_eq(pipe(p), 0);
    cr_assert_eq(write(p[1], text, 29), 29);
    close(p[1]);
    cr_assert_eq(dup2(p[0], STDIN_FILENO), STDIN_FILENO);
    close(p[0]);
    scene *s = NULL;
    glint_error err = {0};
    cr_expect_eq(scene_load_file("-", &s, &err), GLINT_OK, "%s", err.msg);
    cr_expect_eq(scene_settings(s).width, 3);
    scene_free(s);
    dup2(saved, STDIN_FILENO);
    close(saved);
    close(fd);
    remove(path);
}

/* Numbers as the loader reads them are the floats nearest their decimals,
 * as strtof gives them, whether or not they are short enough for the
 * quick conversion (seven digits or fewer, no exponent). */
Test(load, numbers_read_as_strtof_does)
{
    static const char *const forms[] = {
        "0", "-0", "+0.0", "1", "0.1", "-0.3", "0.42", "49.5", "-48.75", "1920", "3.1415927",
        "0.0000001", "9999999", "999999.9", ".5", "5.", "-.25", "16777217", "0.1000000001",
        "1e-3", "2.5E+2", "123456789012", "0.30000000000000004", "1.17549435e-38"};
    char text[1024];
    size_t o = 0;
    o += (size_t)snprintf(text + o, sizeof text - o, "[");
    for (size_t i = 0; i < sizeof forms / sizeof *forms; i++)
        o += (size_t)snprintf(text + o, sizeof text - o, "%s%s", i ? ", " : "", forms[i]);
    snprintf(text + o, sizeof text - o, "]");
    ydoc *d = NULL;
    glint_error err = {0};
    cr_assert_eq(ydoc_parse(text, strlen(text), "numbers", &d, &err), GLINT_OK, "%s", err.msg);
    const ynode *seq = ydoc_node(d, d->root);
    cr_assert_eq(seq->count, sizeof forms / sizeof *forms);
    for (uint32_t i = 0; i < seq->count; i++) {
        float got = ydoc_float(d, ydoc_node(d, ydoc_item(d, seq, i)));
        float want = strtof(forms[i], NULL);
        cr_assert(memcmp(&got, &want, sizeof got) == 0, "%s: %a, strtof %a", forms[i], (double)got,
                  (double)want);
    }
    ydoc_free(d);
}
