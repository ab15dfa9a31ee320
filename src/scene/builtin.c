/* The built-in scene: the nine objects of the assignment this renderer grew
 * from (see DESIGN.md), seen from the origin down -z through a 20 x 20
 * window at distance 40. */
#include <math.h>

#include "core/error.h"
#include "scene/assets.h"
#include "scene/scene.h"

static glint_rc add_asset_image(scene *s, const char *name, int *index, glint_error *err)
{
    const unsigned char *data;
    size_t size;
    if (!asset_find(name, &data, &size))
        return err_set(err, GLINT_ERR_IO, "built-in asset %s is missing", name);
    image img;
    glint_rc rc = image_load_memory(data, size, name, &img, err);
    if (rc != GLINT_OK)
        return rc;
    *index = scene_add_image(s, &img);
    if (*index < 0) {
        image_free(&img);
        return err_nomem(err);
    }
    return GLINT_OK;
}

static material phong(vec3 color, float specular, float shininess)
{
    material m = material_default();
    m.color = color;
    m.specular = specular;
    m.shininess = shininess;
    return m;
}

/* Adds a material and an object using it; false when out of memory. */
static bool add(scene *s, shape sh, material m, int xf)
{
    int mi = scene_add_material(s, &m);
    return mi >= 0 && scene_add_object(s, &sh, mi, xf) >= 0;
}

static glint_rc build(scene *s, glint_error *err)
{
    s->camera = (camera){v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0),
                         (float)(2.0 * atan(10.0 / 40.0) * 180.0 / M_PI)};
    s->settings.width = 500;
    s->settings.height = 500;
    s->settings.samples = 4;
    s->settings.max_depth = 5;
    s->background = v3s(0.0f);
    s->ambient = v3s(0.2f);
    /* Up and to the right, behind the camera's focus: every object's shadow,
     * the transparent sphere's lighter red one above all, falls on open floor
     * where the camera sees it. */
    light l = {LIGHT_POINT, v3(40, 50, -45), v3s(1.0f)};
    if (scene_add_light(s, &l) < 0)
        return err_nomem(err);

    int globe_img, flag_img;
    glint_rc rc = add_asset_image(s, "globe.png", &globe_img, err);
    if (rc == GLINT_OK)
        rc = add_asset_image(s, "flag.png", &flag_img, err);
    if (rc != GLINT_OK)
        return rc;
    texture globe = texture_image(globe_img);
    globe.wrap_v = WRAP_CLAMP; /* repeat round the sphere, clamp at the poles */
    texture flag = texture_image(flag_img);
    flag.wrap_u = flag.wrap_v = WRAP_CLAMP;
    texture chequer = texture_checker(v3(0.92f, 0.92f, 0.88f), v3(0.12f, 0.14f, 0.2f), 8, 32);
    int t_globe = scene_add_texture(s, &globe), t_flag = scene_add_texture(s, &flag);
    int t_chequer = scene_add_texture(s, &chequer);
    if (t_globe < 0 || t_flag < 0 || t_chequer < 0)
        return err_nomem(err);

    material blue = phong(v3(0.05f, 0.15f, 0.9f), 1.0f, 80.0f);
    blue.reflect = 0.8f;
    material glass = phong(v3s(1.0f), 1.0f, 200.0f);
    glass.transmit = 0.95f;
    glass.ior = 1.5f;
    material clear = phong(v3(0.95f, 0.25f, 0.2f), 0.8f, 100.0f);
    clear.transmit = 0.7f;
    clear.tint = v3(1.0f, 0.55f, 0.45f);
    material globe_m = phong(v3s(1.0f), 0.4f, 40.0f);
    globe_m.texture = t_globe;
    material floor_m = phong(v3s(1.0f), 0.1f, 20.0f);
    floor_m.texture = t_chequer;
    material flag_m = phong(v3s(1.0f), 0.0f, 1.0f);
    flag_m.texture = t_flag;

    /* The cuboid: a 4 x 12 x 4 box centred at the origin, turned 30 degrees
     * about y, then moved to stand on the floor at x = -14, z = -80. */
    xform turn = xform_rotate(v3(0, 1, 0), 30.0f), move = xform_translate(v3(-14, -9, -80));
    xform cuboid = xform_then(&turn, &move);
    int xf = scene_add_xform(s, &cuboid);

    bool ok = xf >= 0 &&
              add(s, shape_sphere(v3(-5, 0, -90), 15), blue, -1) &&
              add(s, shape_sphere(v3(5, 5, -70), 4), glass, -1) &&
              add(s, shape_sphere(v3(10, 10, -60), 3), clear, -1) &&
              add(s, shape_sphere(v3(8, -11, -55), 3), globe_m, -1) &&
              add(s, shape_cylinder(v3(10, -15, -80), 3, 10, true),
                  phong(v3(0.1f, 0.75f, 0.2f), 0.6f, 60.0f), -1) &&
              add(s, shape_box(v3(-2, -15, -75), v3(4, -9, -69)),
                  phong(v3(0.95f, 0.85f, 0.1f), 0.5f, 40.0f), -1) &&
              add(s, shape_box(v3(-2, -6, -2), v3(2, 6, 2)), phong(v3(1.0f, 0.5f, 0.05f), 0.5f, 40.0f),
                  xf) &&
              add(s, shape_quad(v3(-20, -15, -40), v3(40, 0, 0), v3(0, 0, -160)), floor_m, -1) &&
              add(s, shape_quad(v3(9, 8, -100), v3(12, 0, 0), v3(0, 8, 0)), flag_m, -1);
    if (!ok)
        return err_nomem(err);
    return scene_build(s, err);
}

glint_rc glint_scene_builtin(glint_scene **out, glint_error *err)
{
    scene *s = scene_new();
    if (!s)
        return err_nomem(err);
    glint_rc rc = build(s, err);
    if (rc != GLINT_OK) {
        scene_free(s);
        return rc;
    }
    *out = s;
    return GLINT_OK;
}
