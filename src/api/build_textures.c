/* Textures built in code: images with their wrap modes and mappings, and
 * the procedural patterns with their colour maps, spaces, fractal
 * parameters and transforms, with the scene format's rules and words
 * (docs/scene-format.md, src/load/textures.c). The defaults are the
 * world's own (texture_image, texture_checker, texture_pattern). */
#include "api/build.h"

#include "api/check.h"
#include "core/error.h"
#include "io/image.h"

static const char fn[] = "glint_scene_add_texture";

/* The world's texture of a kind with its defaults (an image for a kind
 * out of range). */
static texture world_default(glint_texture_kind kind)
{
    if (kind == GLINT_TEXTURE_CHECKER)
        return texture_checker(v3s(1.0f), v3s(0.0f), 1.0f, 1.0f);
    if ((unsigned)kind > GLINT_TEXTURE_WOOD || kind == GLINT_TEXTURE_IMAGE)
        return texture_image(-1);
    return texture_pattern((texture_kind)kind);
}

glint_texture glint_texture_default(glint_texture_kind kind)
{
    texture w = world_default(kind);
    const pattern_noise *pn = &w.pattern.noise;
    bool pattern = w.kind != TEXTURE_IMAGE;
    return (glint_texture){.kind = kind, .file = NULL,
                           .wrap = {GLINT_WRAP_REPEAT, GLINT_WRAP_REPEAT},
                           .even = {1, 1, 1}, .odd = {0, 0, 0}, .scale = {1, 1}, .offset = {0, 0},
                           .space = (glint_texture_space)w.space, .mapping = GLINT_MAPPING_UV,
                           .axis = 2, .scale_z = 1, .offset_z = 0, .ncolors = 0,
                           .octaves = pattern ? pn->octaves : 6,
                           .lacunarity = pattern ? pn->lacunarity : 2.0,
                           .gain = pattern ? pn->gain : 0.5,
                           .turbulence = pattern ? pn->amount : 0.0};
}

/* The image's file, wrap, space and mapping, consistent with each other. */
static glint_rc check_image(const glint_texture *in, glint_error *err)
{
    static const char *const mappings[] = {"uv", "planar", "spherical", "cylindrical", "box"};
    if (!in->file)
        return api_null(err, fn, "texture->file");
    if ((unsigned)in->wrap[0] > GLINT_WRAP_CLAMP || (unsigned)in->wrap[1] > GLINT_WRAP_CLAMP)
        return api_bad(err, fn, "wrap must be GLINT_WRAP_REPEAT or GLINT_WRAP_CLAMP");
    if ((unsigned)in->mapping > GLINT_MAPPING_BOX)
        return api_bad(err, fn, "mapping %d is not one of glint_mapping", (int)in->mapping);
    if (in->mapping == GLINT_MAPPING_UV && in->space != GLINT_SPACE_UV)
        return api_bad(err, fn, "an image with mapping uv is on (u, v); space object or world "
                                "needs mapping planar, spherical, cylindrical or box");
    if (in->mapping != GLINT_MAPPING_UV && in->space == GLINT_SPACE_UV)
        return api_bad(err, fn, "mapping %s projects a point in space: space must be object or "
                                "world", mappings[in->mapping]);
    if (in->mapping == GLINT_MAPPING_PLANAR && (in->axis < 0 || in->axis > 2))
        return api_bad(err, fn, "axis must be 0 (x), 1 (y) or 2 (z) (got %d)", in->axis);
    return GLINT_OK;
}

/* colors: 1 to GLINT_COLOR_MAP_MAX stops, at ascending, into m. */
static glint_rc read_color_map(const glint_texture *in, color_map *m, glint_error *err)
{
    if (in->ncolors < 1 || in->ncolors > GLINT_COLOR_MAP_MAX)
        return api_bad(err, fn, "colors must have 1 to %d stops (got %d)", GLINT_COLOR_MAP_MAX,
                       in->ncolors);
    for (int i = 0; i < in->ncolors; i++) {
        const glint_color_stop *st = &in->colors[i];
        if (!api_finite(&st->at, 1) || !api_color_ok(st->color))
            return api_bad(err, fn, "colors[%d]: at must be finite and colour components "
                                    "finite and >= 0", i);
        m->at[i] = (float)st->at;
        m->color[i] = api_vec3(st->color);
        if (i > 0 && m->at[i] < m->at[i - 1])
            return api_bad(err, fn, "colors must be in ascending order of value (%g after %g)",
                           (double)m->at[i], (double)m->at[i - 1]);
    }
    m->n = in->ncolors;
    return GLINT_OK;
}

/* A pattern's colours, fractal parameters and third dimension into t. */
static glint_rc read_pattern(const glint_texture *in, texture *t, glint_error *err)
{
    if (in->ncolors != 0) {
        glint_rc rc = read_color_map(in, &t->pattern.map, err);
        if (rc != GLINT_OK)
            return rc;
    } else if (in->kind == GLINT_TEXTURE_CHECKER) {
        if (!api_color_ok(in->even) || !api_color_ok(in->odd))
            return api_bad(err, fn, "colour components must be finite and >= 0");
        t->pattern.map.color[0] = api_vec3(in->even);
        t->pattern.map.color[1] = api_vec3(in->odd);
    }
    bool fractal = in->kind == GLINT_TEXTURE_TURBULENCE || in->kind == GLINT_TEXTURE_MARBLE ||
                   in->kind == GLINT_TEXTURE_WOOD;
    const double f[] = {in->lacunarity, in->gain, in->turbulence};
    if (fractal && (in->octaves < 1 || in->octaves > 16))
        return api_bad(err, fn, "octaves must be 1 to 16 (got %d)", in->octaves);
    if (fractal && (!api_finite(f, 3) || !((float)f[0] > 0.0f) || !((float)f[1] > 0.0f)))
        return api_bad(err, fn, "lacunarity and gain must be > 0 and finite");
    if (fractal && in->kind != GLINT_TEXTURE_TURBULENCE && !(f[2] >= 0.0))
        return api_bad(err, fn, "turbulence must be >= 0 (got %g)", f[2]);
    if (fractal) {
        t->pattern.noise = (pattern_noise){in->octaves, (float)f[0], (float)f[1],
                                           in->kind == GLINT_TEXTURE_TURBULENCE
                                               ? t->pattern.noise.amount
                                               : (float)f[2]};
    }
    if (in->space == GLINT_SPACE_UV)
        return GLINT_OK;
    if (!api_finite(&in->scale_z, 1) || !api_finite(&in->offset_z, 1) ||
        (float)in->scale_z == 0.0f)
        return api_bad(err, fn, "scale_z must not be 0 and scale_z and offset_z must be finite "
                                "(a pattern in space)");
    t->scale.z = (float)in->scale_z;
    t->offset.z = (float)in->offset_z;
    return GLINT_OK;
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
    if (!s || !in)
        return api_null(err, fn, !s ? "scene" : "texture");
    if ((unsigned)in->kind > GLINT_TEXTURE_WOOD)
        return api_bad(err, fn, "texture kind %d is not one of glint_texture_kind",
                       (int)in->kind);
    if (!api_finite(in->scale, 2) || !api_finite(in->offset, 2) ||
        (float)in->scale[0] == 0.0f || (float)in->scale[1] == 0.0f)
        return api_bad(err, fn, "scale must not be 0 and scale and offset must be finite");
    if ((unsigned)in->space > GLINT_SPACE_WORLD)
        return api_bad(err, fn, "space %d is not one of glint_texture_space", (int)in->space);
    texture t = world_default(in->kind);
    t.space = (texture_space)in->space;
    t.scale = v3((float)in->scale[0], (float)in->scale[1], 1.0f);
    t.offset = v3((float)in->offset[0], (float)in->offset[1], 0.0f);
    glint_rc rc = api_xform(fn, "", in->steps, in->nsteps, &t.xf, err);
    t.has_xform = in->nsteps > 0;
    if (rc == GLINT_OK && in->kind == GLINT_TEXTURE_IMAGE)
        rc = check_image(in, err);
    else if (rc == GLINT_OK)
        rc = read_pattern(in, &t, err);
    if (rc == GLINT_OK && in->kind == GLINT_TEXTURE_IMAGE) {
        t.image.wrap_u = in->wrap[0] == GLINT_WRAP_CLAMP ? WRAP_CLAMP : WRAP_REPEAT;
        t.image.wrap_v = in->wrap[1] == GLINT_WRAP_CLAMP ? WRAP_CLAMP : WRAP_REPEAT;
        t.image.mapping = (texture_mapping)in->mapping;
        t.image.axis = in->mapping == GLINT_MAPPING_PLANAR ? in->axis : 2;
        rc = add_image(s, in->file, &t.image.image, err); /* last: the others cost less */
    }
    if (rc != GLINT_OK)
        return rc;
    return api_added(scene_add_texture(s, &t), index, err);
}
