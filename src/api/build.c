/* Building a scene in code (include/glint.h): each glint_scene_add_* checks
 * its input with the scene format's rules and words, converts it to the
 * world's types and adds it through scene_add_*, exactly as the YAML front
 * end does, so the same numbers give the same scene and the same image. */
#include "glint.h"

#include <math.h>

#include "api/build.h"
#include "api/check.h"
#include "core/error.h"
#include "core/mat4.h"
#include "geom/shape.h"
#include "io/image.h"
#include "load/mesh_import.h"
#include "scene/scene.h"

glint_rc glint_scene_new(glint_scene **out, glint_error *err)
{
    if (!out)
        return api_null(err, __func__, "out");
    *out = scene_new();
    return *out ? GLINT_OK : err_nomem(err);
}

glint_rc glint_scene_set_background(glint_scene *s, const double rgb[3], glint_error *err)
{
    if (!s || !rgb)
        return api_null(err, __func__, !s ? "scene" : "rgb");
    if (!api_color_ok(rgb))
        return api_bad(err, __func__, "colour components must be finite and >= 0");
    scene_set_background(s, api_vec3(rgb));
    return GLINT_OK;
}

glint_rc glint_scene_set_ambient(glint_scene *s, const double rgb[3], glint_error *err)
{
    if (!s || !rgb)
        return api_null(err, __func__, !s ? "scene" : "rgb");
    if (!api_color_ok(rgb))
        return api_bad(err, __func__, "colour components must be finite and >= 0");
    scene_set_ambient(s, api_vec3(rgb));
    return GLINT_OK;
}

glint_material glint_material_default(void)
{
    return (glint_material){.color = {1, 1, 1}, .ambient = 1, .diffuse = 1, .specular = 0,
                            .shininess = 50, .reflect = 0, .transmit = 0, .ior = 1,
                            .tint = {1, 1, 1}, .texture = -1, .absorption = {0, 0, 0},
                            .emission = {0, 0, 0}, .fresnel_off = 0, .bump = 0,
                            .bump_texture = -1, .bump_strength = 1};
}

glint_rc api_added(int i, int *index, glint_error *err)
{
    if (i < 0)
        return err_nomem(err);
    if (index)
        *index = i;
    return GLINT_OK;
}

glint_rc glint_scene_add_material(glint_scene *s, const glint_material *in, int *index,
                                  glint_error *err)
{
    static const char fn[] = "glint_scene_add_material";
    if (!s || !in)
        return api_null(err, fn, !s ? "scene" : "material");
    const double scalars[] = {in->ambient, in->diffuse, in->specular, in->shininess,
                              in->reflect, in->transmit, in->ior};
    if (!api_color_ok(in->color) || !api_color_ok(in->tint) || !api_finite(scalars, 7) ||
        !api_color_ok(in->absorption) || !api_color_ok(in->emission))
        return api_bad(err, fn, "every value must be finite and colours >= 0");
    if (in->ambient < 0 || in->diffuse < 0 || in->specular < 0 || in->shininess < 0)
        return api_bad(err, fn, "ambient, diffuse, specular and shininess must be >= 0");
    if (!(in->reflect <= 1.0 && in->reflect >= 0.0 && in->transmit >= 0.0 && in->transmit <= 1.0))
        return api_bad(err, fn, "reflect and transmit must be 0 to 1 (got %g and %g)",
                       in->reflect, in->transmit);
    if (!((float)in->ior > 0.0f))
        return api_bad(err, fn, "ior must be > 0 (got %g)", in->ior);
    int ntextures = scene_texture_count(s);
    if (in->texture < -1 || in->texture >= ntextures)
        return api_bad(err, fn, "texture %d was not added (the scene has %d)", in->texture,
                       ntextures);
    material m = material_default();
    m.color = api_vec3(in->color);
    m.ambient = (float)in->ambient;
    m.diffuse = (float)in->diffuse;
    m.specular = (float)in->specular;
    m.shininess = (float)in->shininess;
    m.reflect = (float)in->reflect;
    m.transmit = (float)in->transmit;
    m.ior = (float)in->ior;
    m.tint = api_vec3(in->tint);
    m.texture = in->texture;
    m.absorption = api_vec3(in->absorption);
    m.emission = api_vec3(in->emission);
    m.fresnel = !in->fresnel_off;
    if (in->bump) {
        if (in->bump_texture < 0 || in->bump_texture >= ntextures)
            return api_bad(err, fn, "bump_texture %d was not added (the scene has %d)",
                           in->bump_texture, ntextures);
        if (s->textures[in->bump_texture].space == SPACE_UV)
            return api_bad(err, fn, "a bump pattern must be in space object or world (its "
                                    "gradient is taken in space), not on (u, v)");
        if (!api_finite(&in->bump_strength, 1))
            return api_bad(err, fn, "bump_strength must be finite");
        m.bump = in->bump_texture;
        m.bump_strength = (float)in->bump_strength;
    }
    return api_added(scene_add_material(s, &m), index, err);
}

glint_light glint_light_default(glint_light_kind kind)
{
    return (glint_light){.kind = kind, .color = {1, 1, 1}, .attenuation = {1, 0, 0},
                         .inner_angle = 20, .outer_angle = 30, .samples = 4};
}

/* The checks of one kind (src/load/lights.c states the same rules). */
static const char *light_problem(const glint_light *in)
{
    vec3 eu = api_vec3(in->edge_u), ev = api_vec3(in->edge_v);
    switch (in->kind) {
    case GLINT_LIGHT_POINT:
        return NULL;
    case GLINT_LIGHT_DIRECTIONAL:
        return v3_is_zero(api_vec3(in->direction)) ? "direction must not be zero" : NULL;
    case GLINT_LIGHT_SPOT:
        if (v3_is_zero(v3_sub(api_vec3(in->look_at), api_vec3(in->position))))
            return "look_at must differ from position";
        if (!(in->inner_angle >= 0 && in->inner_angle < in->outer_angle && in->outer_angle < 180))
            return "spot angles must satisfy 0 <= inner_angle < outer_angle < 180";
        return NULL;
    case GLINT_LIGHT_AREA:
        if (!(in->samples >= 1 && in->samples <= LIGHT_MAX_AREA_SAMPLES))
            return "samples must be 1 to 64";
        if (!(v3_len2(v3_cross(eu, ev)) > 0.0f))
            return "edge_u and edge_v must be non-zero and not parallel";
        return NULL;
    }
    return "unknown kind";
}

glint_rc glint_scene_add_light(glint_scene *s, const glint_light *in, int *index,
                               glint_error *err)
{
    static const char fn[] = "glint_scene_add_light";
    if (!s || !in)
        return api_null(err, fn, !s ? "scene" : "light");
    if ((unsigned)in->kind > GLINT_LIGHT_AREA)
        return api_bad(err, fn, "light kind %d is not one of glint_light_kind", (int)in->kind);
    const double angles[] = {in->inner_angle, in->outer_angle};
    if (!api_finite(in->position, 3) || !api_finite(in->direction, 3) ||
        !api_finite(in->look_at, 3) || !api_finite(in->edge_u, 3) ||
        !api_finite(in->edge_v, 3) || !api_finite(angles, 2))
        return api_bad(err, fn, "every coordinate and angle must be finite");
    if (!api_color_ok(in->color))
        return api_bad(err, fn, "colour components must be finite and >= 0");
    if (!api_color_ok(in->attenuation))
        return api_bad(err, fn, "attenuation terms must be finite and >= 0");
    const char *problem = light_problem(in);
    if (problem)
        return api_bad(err, fn, "%s", problem);
    vec3 pos = api_vec3(in->position), color = api_vec3(in->color);
    vec3 att = v3_is_zero(api_vec3(in->attenuation)) ? v3(1, 0, 0) : api_vec3(in->attenuation);
    light l;
    switch (in->kind) {
    case GLINT_LIGHT_POINT:
        l = light_point(pos, color, att);
        break;
    case GLINT_LIGHT_DIRECTIONAL:
        l = light_directional(api_vec3(in->direction), color);
        break;
    case GLINT_LIGHT_SPOT:
        l = light_spot(pos, api_vec3(in->look_at), (float)in->inner_angle,
                       (float)in->outer_angle, color, att);
        break;
    case GLINT_LIGHT_AREA:
        l = light_area(pos, api_vec3(in->edge_u), api_vec3(in->edge_v), in->samples, color, att);
        break;
    }
    return api_added(scene_add_light(s, &l), index, err);
}

glint_rc glint_scene_add_object(glint_scene *s, const glint_object *in, int *index,
                                glint_error *err)
{
    static const char fn[] = "glint_scene_add_object";
    if (!s || !in || (!in->steps && in->nsteps > 0))
        return api_null(err, fn, !s ? "scene" : !in ? "object" : "object->steps");
    int nmaterials = scene_material_count(s);
    bool own = in->material == -1 &&
               (in->shape.kind == GLINT_SHAPE_MESH || in->shape.kind == GLINT_SHAPE_CSG);
    if (!own && (in->material < 0 || in->material >= nmaterials))
        return api_bad(err, fn, "material %d was not added (the scene has %d)", in->material,
                       nmaterials);
    xform x;
    glint_rc rc = api_xform(fn, "", in->steps, in->nsteps, &x, err);
    if (rc != GLINT_OK)
        return rc;
    /* The shape is checked before the transform joins the scene, so that
     * a refused object leaves no transform behind. */
    if (in->shape.kind == GLINT_SHAPE_CSG)
        return api_add_csg(s, in, in->nsteps > 0 ? &x : NULL, index, err);
    shape sh;
    rc = api_shape(s, fn, "", &in->shape, &sh, err);
    int xf = -1;
    if (rc == GLINT_OK && in->nsteps > 0)
        rc = api_added(scene_add_xform(s, &x), &xf, err);
    if (rc != GLINT_OK)
        return rc;
    return api_added(scene_add_object(s, &sh, in->material, xf), index, err);
}

glint_rc glint_scene_add_mesh(glint_scene *s, const char *path, int *index, glint_error *err)
{
    if (!s || !path)
        return api_null(err, __func__, !s ? "scene" : "path");
    return glint_scene_add_mesh_smoothed(s, path, MESH_DEFAULT_SMOOTH_ANGLE, index, err);
}

glint_rc glint_scene_add_mesh_smoothed(glint_scene *s, const char *path, double smooth_angle,
                                       int *index, glint_error *err)
{
    if (!s || !path)
        return api_null(err, __func__, !s ? "scene" : "path");
    if (!(smooth_angle >= 0.0 && smooth_angle <= 180.0))
        return api_bad(err, __func__, "smooth_angle must be 0 to 180 degrees (got %g)",
                       smooth_angle);
    mesh_options mo = {(float)smooth_angle, s->threads};
    mesh_file mf = {0};
    glint_rc rc = mesh_import(path, &mo, &mf, err);
    int i = -1;
    if (rc == GLINT_OK)
        rc = mesh_file_add(s, &mf, &i, err);
    if (rc == GLINT_OK && !scene_add_warnings(s, mf.warnings))
        rc = err_nomem(err);
    mesh_file_free(&mf);
    if (rc == GLINT_OK && index)
        *index = i;
    return rc;
}

glint_fog glint_fog_default(glint_fog_kind kind)
{
    return (glint_fog){.kind = kind, .color = {0.5, 0.5, 0.5}};
}

/* The checks of one kind (src/load/fog.c states the same rules). */
static const char *fog_problem(const glint_fog *in)
{
    const double v[] = {in->density, in->start, in->end, in->height_falloff};
    if ((unsigned)in->kind > GLINT_FOG_LINEAR)
        return "fog kind is not one of glint_fog_kind";
    if (!api_color_ok(in->color) || !api_finite(v, 4))
        return "every value must be finite and colour components >= 0";
    if (in->kind == GLINT_FOG_EXPONENTIAL && !((float)in->density > 0.0f))
        return "density must be > 0";
    if (in->kind == GLINT_FOG_LINEAR && !(in->start >= 0.0 && (float)in->end > (float)in->start))
        return "start must be >= 0 and end greater than start";
    if (!(in->height_falloff >= 0.0))
        return "height_falloff must be >= 0";
    return NULL;
}

glint_rc glint_scene_set_fog(glint_scene *s, const glint_fog *in, glint_error *err)
{
    if (!s || !in)
        return api_null(err, __func__, !s ? "scene" : "fog");
    const char *problem = fog_problem(in);
    if (problem)
        return api_bad(err, __func__, "%s", problem);
    static const fog_kind kinds[] = {FOG_NONE, FOG_EXPONENTIAL, FOG_LINEAR};
    fog f = {kinds[in->kind], api_vec3(in->color), (float)in->density, (float)in->start,
             (float)in->end, (float)in->height_falloff};
    scene_set_fog(s, &f);
    return GLINT_OK;
}

glint_rc glint_scene_build(glint_scene *s, glint_error *err)
{
    if (!s)
        return api_null(err, __func__, "scene");
    return scene_build(s, err);
}
