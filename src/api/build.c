/* Building a scene in code (include/glint.h): each glint_scene_add_* checks
 * its input with the scene format's rules and words, converts it to the
 * world's types and adds it through scene_add_*, exactly as the YAML front
 * end does, so the same numbers give the same scene and the same image. */
#include "glint.h"

#include <math.h>

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

/* A colour: finite, components >= 0. */
static bool color_ok(const double c[3])
{
    return api_finite(c, 3) && c[0] >= 0.0 && c[1] >= 0.0 && c[2] >= 0.0;
}

glint_rc glint_scene_set_background(glint_scene *s, const double rgb[3], glint_error *err)
{
    if (!s || !rgb)
        return api_null(err, __func__, !s ? "scene" : "rgb");
    if (!color_ok(rgb))
        return api_bad(err, __func__, "colour components must be finite and >= 0");
    scene_set_background(s, api_vec3(rgb));
    return GLINT_OK;
}

glint_rc glint_scene_set_ambient(glint_scene *s, const double rgb[3], glint_error *err)
{
    if (!s || !rgb)
        return api_null(err, __func__, !s ? "scene" : "rgb");
    if (!color_ok(rgb))
        return api_bad(err, __func__, "colour components must be finite and >= 0");
    scene_set_ambient(s, api_vec3(rgb));
    return GLINT_OK;
}

glint_material glint_material_default(void)
{
    return (glint_material){.color = {1, 1, 1}, .ambient = 1, .diffuse = 1, .specular = 0,
                            .shininess = 50, .reflect = 0, .transmit = 0, .ior = 1,
                            .tint = {1, 1, 1}, .texture = -1, .absorption = {0, 0, 0},
                            .emission = {0, 0, 0}, .fresnel_off = 0};
}

/* Stores the index of a new element, or says memory ran out. */
static glint_rc added(int i, int *index, glint_error *err)
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
    if (!color_ok(in->color) || !color_ok(in->tint) || !api_finite(scalars, 7) ||
        !color_ok(in->absorption) || !color_ok(in->emission))
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
    return added(scene_add_material(s, &m), index, err);
}

glint_texture glint_texture_default(glint_texture_kind kind)
{
    return (glint_texture){.kind = kind, .file = NULL, .wrap = {GLINT_WRAP_REPEAT, GLINT_WRAP_REPEAT},
                           .even = {1, 1, 1}, .odd = {0, 0, 0}, .scale = {1, 1}, .offset = {0, 0}};
}

/* Reads the image file and adds it to the scene; *index gets its place. */
static glint_rc add_image(glint_scene *s, const char *path, int *index, glint_error *err)
{
    image img;
    glint_rc rc = image_load(path, &img, err);
    if (rc != GLINT_OK)
        return rc;
    *index = scene_add_image(s, &img);
    if (*index < 0) {
        image_free(&img);
        return err_nomem(err);
    }
    return GLINT_OK;
}

glint_rc glint_scene_add_texture(glint_scene *s, const glint_texture *in, int *index,
                                 glint_error *err)
{
    static const char fn[] = "glint_scene_add_texture";
    if (!s || !in)
        return api_null(err, fn, !s ? "scene" : "texture");
    if ((unsigned)in->kind > GLINT_TEXTURE_CHECKER)
        return api_bad(err, fn, "texture kind %d is not one of glint_texture_kind",
                       (int)in->kind);
    if (!api_finite(in->scale, 2) || !api_finite(in->offset, 2) ||
        (float)in->scale[0] == 0.0f || (float)in->scale[1] == 0.0f)
        return api_bad(err, fn, "scale must not be 0 and scale and offset must be finite");
    texture t;
    switch (in->kind) {
    case GLINT_TEXTURE_IMAGE: {
        if (!in->file)
            return api_null(err, fn, "texture->file");
        if ((unsigned)in->wrap[0] > GLINT_WRAP_CLAMP || (unsigned)in->wrap[1] > GLINT_WRAP_CLAMP)
            return api_bad(err, fn, "wrap must be GLINT_WRAP_REPEAT or GLINT_WRAP_CLAMP");
        int img = -1;
        glint_rc rc = add_image(s, in->file, &img, err);
        if (rc != GLINT_OK)
            return rc;
        t = texture_image(img);
        t.image.wrap_u = in->wrap[0] == GLINT_WRAP_CLAMP ? WRAP_CLAMP : WRAP_REPEAT;
        t.image.wrap_v = in->wrap[1] == GLINT_WRAP_CLAMP ? WRAP_CLAMP : WRAP_REPEAT;
        break;
    }
    case GLINT_TEXTURE_CHECKER:
        if (!color_ok(in->even) || !color_ok(in->odd))
            return api_bad(err, fn, "colour components must be finite and >= 0");
        t = texture_checker(api_vec3(in->even), api_vec3(in->odd), 1.0f, 1.0f);
        break;
    }
    t.scale = v3((float)in->scale[0], (float)in->scale[1], 1.0f);
    t.offset = v3((float)in->offset[0], (float)in->offset[1], 0.0f);
    return added(scene_add_texture(s, &t), index, err);
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
    if (!color_ok(in->color))
        return api_bad(err, fn, "colour components must be finite and >= 0");
    if (!color_ok(in->attenuation))
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
    return added(scene_add_light(s, &l), index, err);
}

/* The shape with the scene format's rules (docs/scene-format.md). */
static glint_rc make_shape(const glint_scene *s, const glint_shape *in, shape *out,
                           glint_error *err)
{
    static const char fn[] = "glint_scene_add_object";
    switch (in->kind) {
    case GLINT_SHAPE_SPHERE:
        if (!api_finite(in->sphere.center, 3) || !api_finite(&in->sphere.radius, 1) ||
            !((float)in->sphere.radius > 0.0f))
            return api_bad(err, fn, "sphere radius must be > 0 and every value finite");
        *out = shape_sphere(api_vec3(in->sphere.center), (float)in->sphere.radius);
        return GLINT_OK;
    case GLINT_SHAPE_PLANE:
        if (!api_finite(in->plane.point, 3) || !api_finite(in->plane.normal, 3) ||
            v3_is_zero(api_vec3(in->plane.normal)))
            return api_bad(err, fn, "plane normal must not be zero and every value finite");
        *out = shape_plane(api_vec3(in->plane.point), api_vec3(in->plane.normal));
        return GLINT_OK;
    case GLINT_SHAPE_QUAD: {
        vec3 u = api_vec3(in->quad.edge_u), v = api_vec3(in->quad.edge_v);
        if (!api_finite(in->quad.origin, 3) || !api_finite(in->quad.edge_u, 3) ||
            !api_finite(in->quad.edge_v, 3) || v3_is_zero(v3_cross(u, v)))
            return api_bad(err, fn, "quad edge_v must not be parallel to edge_u (nor either be "
                                    "zero) and every value finite");
        *out = shape_quad(api_vec3(in->quad.origin), u, v);
        return GLINT_OK;
    }
    case GLINT_SHAPE_BOX: {
        vec3 lo = api_vec3(in->box.min), hi = api_vec3(in->box.max);
        if (!api_finite(in->box.min, 3) || !api_finite(in->box.max, 3) ||
            !(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
            return api_bad(err, fn, "box max must be greater than min on every axis and every "
                                    "value finite");
        *out = shape_box(lo, hi);
        return GLINT_OK;
    }
    case GLINT_SHAPE_CYLINDER: {
        const glint_cylinder *c = &in->cylinder;
        if (!api_finite(c->base, 3) || !api_finite(&c->radius, 1) ||
            !api_finite(&c->height, 1) || !((float)c->radius > 0.0f) ||
            !((float)c->height > 0.0f))
            return api_bad(err, fn, "cylinder radius and height must be > 0 and every value "
                                    "finite");
        *out = shape_cylinder(api_vec3(c->base), (float)c->radius, (float)c->height,
                              c->capped != 0);
        return GLINT_OK;
    }
    case GLINT_SHAPE_TRIANGLE: {
        vec3 p0 = api_vec3(in->triangle.p0), p1 = api_vec3(in->triangle.p1),
             p2 = api_vec3(in->triangle.p2);
        if (!api_finite(in->triangle.p0, 3) || !api_finite(in->triangle.p1, 3) ||
            !api_finite(in->triangle.p2, 3) || triangle_check(p0, p1, p2) == TRIANGLE_DEGENERATE)
            return api_bad(err, fn, "triangle is degenerate (p0, p1 and p2 lie on one line) or "
                                    "not finite");
        if (triangle_check(p0, p1, p2) == TRIANGLE_TOO_LARGE)
            return api_bad(err, fn, "triangle is too large for single precision (its normal "
                                    "overflows)");
        *out = shape_triangle(p0, p1, p2);
        return GLINT_OK;
    }
    case GLINT_SHAPE_MESH:
        if (in->mesh.index < 0 || in->mesh.index >= scene_mesh_count(s))
            return api_bad(err, fn, "mesh %d was not added (the scene has %d)", in->mesh.index,
                           scene_mesh_count(s));
        *out = shape_mesh(scene_mesh(s, in->mesh.index));
        return GLINT_OK;
    }
    return api_bad(err, fn, "shape kind %d is not one of glint_shape_kind", (int)in->kind);
}

static bool xform_finite(const xform *x)
{
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            if (!isfinite(x->fwd.m[i][j]) || !isfinite(x->inv.m[i][j]))
                return false;
    return true;
}

/* One transform step, made with the same functions the scene format's
 * steps use. */
static glint_rc make_step(const glint_step *st, int i, xform *out, glint_error *err)
{
    static const char fn[] = "glint_scene_add_object";
    if ((unsigned)st->kind > GLINT_STEP_MATRIX)
        return api_bad(err, fn, "steps[%d]: kind %d is not one of glint_step_kind", i,
                       (int)st->kind);
    if (!api_finite(st->v, 12))
        return api_bad(err, fn, "steps[%d] has a value that is not finite", i);
    vec3 a = api_vec3(st->v);
    mat4 m = mat4_identity();
    switch (st->kind) {
    case GLINT_STEP_TRANSLATE:
        *out = xform_translate(a);
        break;
    case GLINT_STEP_ROTATE:
        if (v3_is_zero(a))
            return api_bad(err, fn, "steps[%d]: rotation axis must not be zero", i);
        *out = xform_rotate(a, (float)st->v[3]);
        break;
    case GLINT_STEP_SCALE:
        if (a.x == 0.0f || a.y == 0.0f || a.z == 0.0f)
            return api_bad(err, fn, "steps[%d]: scale factors must not be 0", i);
        *out = xform_scale(a);
        break;
    case GLINT_STEP_SHEAR: {
        static const int at[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
        for (int k = 0; k < 6; k++)
            m.m[at[k][0]][at[k][1]] = (float)st->v[k];
        if (!xform_from_matrix(&m, out))
            return api_bad(err, fn, "steps[%d]: shear is not invertible (it flattens space)", i);
        break;
    }
    case GLINT_STEP_MATRIX:
        for (int k = 0; k < 12; k++)
            m.m[k / 4][k % 4] = (float)st->v[k];
        if (!xform_from_matrix(&m, out))
            return api_bad(err, fn, "steps[%d]: matrix is not invertible", i);
        break;
    }
    if (!xform_finite(out))
        return api_bad(err, fn, "steps[%d] makes the transform degenerate", i);
    return GLINT_OK;
}

/* The object's transform as a scene xform index, or -1 for none. */
static glint_rc make_xform(glint_scene *s, const glint_object *in, int *index, glint_error *err)
{
    *index = -1;
    xform acc = xform_identity();
    for (int i = 0; i < in->nsteps; i++) {
        xform step;
        glint_rc rc = make_step(&in->steps[i], i, &step, err);
        if (rc != GLINT_OK)
            return rc;
        acc = i > 0 ? xform_then(&acc, &step) : step;
        if (!xform_finite(&acc))
            return api_bad(err, "glint_scene_add_object",
                           "steps[%d] makes the transform degenerate", i);
    }
    if (in->nsteps == 0)
        return GLINT_OK;
    return added(scene_add_xform(s, &acc), index, err);
}

glint_rc glint_scene_add_object(glint_scene *s, const glint_object *in, int *index,
                                glint_error *err)
{
    static const char fn[] = "glint_scene_add_object";
    if (!s || !in || (!in->steps && in->nsteps > 0))
        return api_null(err, fn, !s ? "scene" : !in ? "object" : "object->steps");
    if (in->nsteps < 0)
        return api_bad(err, fn, "nsteps must be >= 0 (got %d)", in->nsteps);
    int nmaterials = scene_material_count(s);
    bool own = in->material == -1 && in->shape.kind == GLINT_SHAPE_MESH;
    if (!own && (in->material < 0 || in->material >= nmaterials))
        return api_bad(err, fn, "material %d was not added (the scene has %d)", in->material,
                       nmaterials);
    shape sh;
    glint_rc rc = make_shape(s, &in->shape, &sh, err);
    int xf;
    if (rc == GLINT_OK)
        rc = make_xform(s, in, &xf, err);
    if (rc != GLINT_OK)
        return rc;
    return added(scene_add_object(s, &sh, in->material, xf), index, err);
}

glint_rc glint_scene_add_mesh(glint_scene *s, const char *path, int *index, glint_error *err)
{
    if (!s || !path)
        return api_null(err, __func__, !s ? "scene" : "path");
    mesh_file mf = {0};
    glint_rc rc = mesh_import(path, &mf, err);
    int i = -1;
    if (rc == GLINT_OK)
        rc = mesh_file_add(s, &mf, &i, err);
    mesh_file_free(&mf);
    if (rc == GLINT_OK && index)
        *index = i;
    return rc;
}

glint_rc glint_scene_build(glint_scene *s, glint_error *err)
{
    if (!s)
        return api_null(err, __func__, "scene");
    return scene_build(s, err);
}
