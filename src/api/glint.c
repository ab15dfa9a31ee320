/* The public library API (include/glint.h): every glint_* function but the
 * scene-building ones (build.c), each a thin layer that checks its
 * arguments and hands over to the module that owns the work. Nothing below
 * this folder knows the public names. */
#include "glint.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "api/check.h"
#include "core/error.h"
#include "io/image_write.h"
#include "load/load.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/settings.h"

const char *glint_version(void) { return GLINT_VERSION; }

int glint_exit_code(glint_rc rc)
{
    switch (rc) {
    case GLINT_OK:
        return 0;
    case GLINT_ERR_INPUT:
        return 2;
    case GLINT_ERR_NOMEM:
    case GLINT_ERR_IO:
    case GLINT_ERR_CANCELLED:
        return 1;
    }
    return 1;
}

glint_rc glint_scene_builtin(glint_scene **out, glint_error *err)
{
    if (!out)
        return api_null(err, __func__, "out");
    return scene_load_builtin(out, err);
}

glint_rc glint_scene_load(const char *path, glint_scene **out, glint_error *err)
{
    if (!path || !out)
        return api_null(err, __func__, !path ? "path" : "out");
    return scene_load_file(path, out, err);
}

void glint_scene_free(glint_scene *s) { scene_free(s); }

glint_rc glint_scene_settings(const glint_scene *s, glint_settings *out, glint_error *err)
{
    if (!s || !out)
        return api_null(err, __func__, !s ? "scene" : "out");
    *out = scene_settings(s);
    return GLINT_OK;
}

glint_rc glint_scene_count(const glint_scene *s, glint_scene_counts *out, glint_error *err)
{
    if (!s || !out)
        return api_null(err, __func__, !s ? "scene" : "out");
    *out = (glint_scene_counts){s->nobjects, s->nlights, scene_material_count(s), s->ntextures,
                                scene_mesh_count(s)};
    return GLINT_OK;
}

glint_rc glint_scene_set_settings(glint_scene *s, const glint_settings *st, glint_error *err)
{
    if (!s || !st)
        return api_null(err, __func__, !s ? "scene" : "settings");
    glint_rc rc = settings_check(st, err);
    if (rc == GLINT_OK)
        scene_set_settings(s, st);
    return rc;
}

glint_rc glint_settings_check(const glint_settings *s, glint_error *err)
{
    if (!s)
        return api_null(err, __func__, "settings");
    return settings_check(s, err);
}

int glint_default_threads(void) { return settings_default_threads(); }

/* ---- camera ---------------------------------------------------------------- */

glint_rc glint_scene_camera(const glint_scene *s, glint_camera *out, glint_error *err)
{
    if (!s || !out)
        return api_null(err, __func__, !s ? "scene" : "out");
    camera cam = scene_camera(s);
    const camera *c = &cam;
    memset(out, 0, sizeof *out);
    const vec3 *from[3] = {&c->eye, &c->target, &c->up};
    double *to[3] = {out->eye, out->look_at, out->up};
    for (int i = 0; i < 3; i++)
        for (int a = 0; a < 3; a++)
            to[i][a] = (double)v3_at(*from[i], a);
    out->fov = (double)c->hfov;
    out->aperture = 0.0;
    out->focus_distance = (double)v3_len(v3_sub(c->target, c->eye));
    out->projection = GLINT_PROJECTION_PERSPECTIVE;
    return GLINT_OK;
}

glint_rc glint_scene_set_camera(glint_scene *s, const glint_camera *in, glint_error *err)
{
    static const char fn[] = "glint_scene_set_camera";
    if (!s || !in)
        return api_null(err, fn, !s ? "scene" : "camera");
    if (!api_finite(in->eye, 3) || !api_finite(in->look_at, 3) || !api_finite(in->up, 3) ||
        !api_finite(&in->fov, 1) || !api_finite(&in->aperture, 1) ||
        !api_finite(&in->focus_distance, 1))
        return api_bad(err, fn, "every camera value must be a finite number");
    if ((unsigned)in->projection > GLINT_PROJECTION_PERSPECTIVE)
        return api_bad(err, fn, "projection must be perspective (%d) (got %d)",
                       GLINT_PROJECTION_PERSPECTIVE, (int)in->projection);
    if (!((float)in->fov > 0.0f && (float)in->fov < 180.0f))
        return api_bad(err, fn, "fov must be > 0 and < 180 degrees (got %g)", in->fov);
    if (in->aperture != 0.0)
        return api_bad(err, fn, "aperture must be 0 (a pinhole camera) (got %g)", in->aperture);
    if (in->focus_distance < 0.0)
        return api_bad(err, fn, "focus_distance must be >= 0 (got %g)", in->focus_distance);
    camera c = {api_vec3(in->eye), api_vec3(in->look_at), api_vec3(in->up), (float)in->fov};
    vec3 view = v3_sub(c.target, c.eye);
    if (v3_is_zero(view))
        return api_bad(err, fn, "camera look_at must differ from eye");
    if (v3_is_zero(v3_cross(view, c.up)))
        return api_bad(err, fn, "camera up must not be zero nor parallel to the view direction");
    scene_set_camera(s, &c);
    return GLINT_OK;
}

/* ---- films and rendering ---------------------------------------------------- */

glint_rc glint_film_alloc(glint_film *film, int width, int height, glint_error *err)
{
    if (!film)
        return api_null(err, __func__, "film");
    if (width < 1 || height < 1 || width > SETTINGS_MAX_SIDE || height > SETTINGS_MAX_SIDE ||
        (uint64_t)width * (uint64_t)height > SETTINGS_MAX_PIXELS)
        return api_bad(err, __func__, "film size %dx%d is out of range (1 to %d per side)", width,
                       height, SETTINGS_MAX_SIDE);
    float *rgb = calloc((size_t)width * (size_t)height * 3, sizeof *rgb);
    if (!rgb)
        return err_nomem(err);
    *film = (glint_film){width, height, rgb};
    return GLINT_OK;
}

void glint_film_free(glint_film *film) { render_film_free(film); }

/* The settings a render uses, checked: the given ones or the scene's. */
static glint_rc render_settings(const glint_scene *sc, const glint_settings **settings,
                                glint_settings *own, glint_error *err)
{
    if (!*settings) {
        *own = scene_settings(sc);
        *settings = own;
    }
    return settings_check(*settings, err);
}

glint_rc glint_render(const glint_scene *sc, const glint_settings *settings,
                      const glint_callbacks *callbacks, glint_film *film, glint_stats *stats,
                      glint_error *err)
{
    if (!sc || !film)
        return api_null(err, __func__, !sc ? "scene" : "film");
    glint_settings own;
    glint_rc rc = render_settings(sc, &settings, &own, err);
    if (rc != GLINT_OK)
        return rc;
    rc = glint_film_alloc(film, settings->width, settings->height, err);
    if (rc != GLINT_OK)
        return rc;
    render_work w = {.region = {0, 0, settings->width, settings->height}};
    rc = render_run(sc, settings, callbacks, &w, film, stats, err);
    if (rc != GLINT_OK)
        render_film_free(film);
    return rc;
}

glint_rc glint_render_region(const glint_scene *sc, const glint_settings *settings,
                             const glint_rect *g, const glint_callbacks *callbacks,
                             glint_film *film, glint_stats *stats, glint_error *err)
{
    static const char fn[] = "glint_render_region";
    if (!sc || !g || !film || !film->rgb)
        return api_null(err, fn, !sc ? "scene" : !g ? "region" : !film ? "film" : "film->rgb");
    glint_settings own;
    glint_rc rc = render_settings(sc, &settings, &own, err);
    if (rc != GLINT_OK)
        return rc;
    int w = settings->width, h = settings->height;
    if (g->x0 < 0 || g->y0 < 0 || g->x1 > w || g->y1 > h || g->x0 >= g->x1 || g->y0 >= g->y1)
        return api_bad(err, fn, "region [%d, %d) x [%d, %d) is empty or not inside the %dx%d image",
                       g->x0, g->x1, g->y0, g->y1, w, h);
    render_work work = {.region = *g};
    if (film->width == g->x1 - g->x0 && film->height == g->y1 - g->y0) {
        work.film_x0 = g->x0;
        work.film_y0 = g->y0;
    } else if (film->width != w || film->height != h) {
        return api_bad(err, fn, "film is %dx%d; it must be the image's size (%dx%d) or the region's (%dx%d)",
                       film->width, film->height, w, h, g->x1 - g->x0, g->y1 - g->y0);
    }
    return render_run(sc, settings, callbacks, &work, film, stats, err);
}

glint_rc glint_tile_count(const glint_settings *settings, int *count, glint_error *err)
{
    if (!settings || !count)
        return api_null(err, __func__, !settings ? "settings" : "count");
    glint_rc rc = settings_check(settings, err);
    if (rc == GLINT_OK)
        *count = render_tile_count(settings->width, settings->height);
    return rc;
}

glint_rc glint_tile_rect(const glint_settings *settings, int tile, glint_rect *out,
                         glint_error *err)
{
    if (!settings || !out)
        return api_null(err, __func__, !settings ? "settings" : "out");
    glint_rc rc = settings_check(settings, err);
    if (rc != GLINT_OK)
        return rc;
    int n = render_tile_count(settings->width, settings->height);
    if (tile < 0 || tile >= n)
        return api_bad(err, __func__, "tile %d is out of range (0 to %d)", tile, n - 1);
    *out = render_tile_rect(settings->width, settings->height, tile);
    return GLINT_OK;
}

/* Each listed tile in range, and listed once. */
static glint_rc check_tiles(const int *tiles, int ntiles, int count, glint_error *err)
{
    static const char fn[] = "glint_render_tiles";
    unsigned char *seen = calloc((size_t)count / 8 + 1, 1);
    if (!seen)
        return err_nomem(err);
    glint_rc rc = GLINT_OK;
    for (int i = 0; i < ntiles && rc == GLINT_OK; i++) {
        int t = tiles[i];
        if (t < 0 || t >= count)
            rc = api_bad(err, fn, "tiles[%d] is %d, out of range (0 to %d)", i, t, count - 1);
        else if (seen[t / 8] & (1u << (t % 8)))
            rc = api_bad(err, fn, "tile %d is listed twice (tiles[%d])", t, i);
        else
            seen[t / 8] |= (unsigned char)(1u << (t % 8));
    }
    free(seen);
    return rc;
}

glint_rc glint_render_tiles(const glint_scene *sc, const glint_settings *settings,
                            const int *tiles, int ntiles, const glint_callbacks *callbacks,
                            glint_film *film, glint_stats *stats, glint_error *err)
{
    static const char fn[] = "glint_render_tiles";
    if (!sc || (!tiles && ntiles > 0) || !film || !film->rgb)
        return api_null(err, fn, !sc ? "scene" : !film ? "film" : !film->rgb ? "film->rgb" : "tiles");
    if (ntiles < 0)
        return api_bad(err, fn, "ntiles must be >= 0 (got %d)", ntiles);
    glint_settings own;
    glint_rc rc = render_settings(sc, &settings, &own, err);
    if (rc != GLINT_OK)
        return rc;
    if (film->width != settings->width || film->height != settings->height)
        return api_bad(err, fn, "film is %dx%d; it must be the image's size (%dx%d)", film->width,
                       film->height, settings->width, settings->height);
    rc = check_tiles(tiles, ntiles, render_tile_count(settings->width, settings->height), err);
    if (rc != GLINT_OK)
        return rc;
    render_work work = {.tiles = tiles, .ntiles = ntiles};
    if (ntiles == 0) {
        if (stats)
            *stats = (glint_stats){0};
        return GLINT_OK;
    }
    return render_run(sc, settings, callbacks, &work, film, stats, err);
}

glint_rc glint_film_write(const glint_film *film, const char *path,
                          const glint_write_options *opts, glint_error *err)
{
    if (!film || !film->rgb || !path)
        return api_null(err, __func__, !film ? "film" : !path ? "path" : "film->rgb");
    if (film->width <= 0 || film->height <= 0)
        return api_bad(err, __func__, "film is %dx%d", film->width, film->height);
    return image_write_film(path, film->width, film->height, film->rgb, opts, err);
}

glint_rc glint_output_check(const char *path, const glint_write_options *opts, glint_error *err)
{
    if (!path)
        return api_null(err, __func__, "path");
    return image_write_check(path, opts, err);
}

glint_rc glint_format_parse(const char *name, glint_format *out, glint_error *err)
{
    if (!name || !out)
        return api_null(err, __func__, !name ? "name" : "out");
    return image_format_parse(name, out, err);
}
