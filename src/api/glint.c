/* The public library API (include/glint.h): every glint_* function but the
 * scene-building ones (build.c), each a thin layer that checks its
 * arguments and hands over to the module that owns the work. Nothing below
 * this folder knows the public names. */
#include "glint.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "api/check.h"
#include "core/error.h"
#include "core/spare.h"
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
    return glint_scene_builtin_with(NULL, out, err);
}

glint_rc glint_scene_load(const char *path, glint_scene **out, glint_error *err)
{
    return glint_scene_load_with(path, NULL, out, err);
}

/* The thread count of options (NULL: 0) into *threads, checked. */
static glint_rc load_threads(const glint_load_options *o, const char *fn, int *threads,
                             glint_error *err)
{
    *threads = o ? o->threads : 0;
    if (*threads < 0 || *threads > SETTINGS_MAX_THREADS)
        return api_bad(err, fn, "threads must be 0 to %d (got %d)", SETTINGS_MAX_THREADS,
                       *threads);
    return GLINT_OK;
}

glint_rc glint_scene_builtin_with(const glint_load_options *o, glint_scene **out,
                                  glint_error *err)
{
    int threads;
    if (!out)
        return api_null(err, __func__, "out");
    glint_rc rc = load_threads(o, __func__, &threads, err);
    return rc != GLINT_OK ? rc : scene_load_builtin(threads, out, err);
}

glint_rc glint_scene_load_with(const char *path, const glint_load_options *o,
                               glint_scene **out, glint_error *err)
{
    int threads;
    if (!path || !out)
        return api_null(err, __func__, !path ? "path" : "out");
    glint_rc rc = load_threads(o, __func__, &threads, err);
    return rc != GLINT_OK ? rc : scene_load_file_threads(path, threads, out, err);
}

glint_rc glint_scene_set_threads(glint_scene *s, int threads, glint_error *err)
{
    if (!s)
        return api_null(err, __func__, "scene");
    glint_rc rc = load_threads(&(glint_load_options){threads}, __func__, &threads, err);
    if (rc == GLINT_OK)
        s->threads = threads;
    return rc;
}

void glint_scene_free(glint_scene *s) { scene_free(s); }

const char *glint_scene_warnings(const glint_scene *s) { return s ? scene_warnings(s) : ""; }

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

void *glint_memory_spare(size_t bytes) { return spare_make(bytes); }

/* ---- camera ---------------------------------------------------------------- */

/* In glint_projection order. */
static const camera_projection projections[] = {CAMERA_PERSPECTIVE, CAMERA_ORTHOGRAPHIC,
                                                CAMERA_EQUIRECTANGULAR, CAMERA_FISHEYE};

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
    out->aperture = (double)c->aperture;
    out->focus_distance = c->focus_distance > 0.0f ? (double)c->focus_distance
                                                   : (double)v3_len(v3_sub(c->target, c->eye));
    for (int i = 0; i < 4; i++)
        if (projections[i] == c->projection)
            out->projection = (glint_projection)i;
    out->width = (double)c->width;
    out->shutter = (double)c->shutter;
    return GLINT_OK;
}

/* The ranges of glint_camera's fields (include/glint.h). */
static glint_rc camera_ranges(const glint_camera *in, glint_error *err)
{
    static const char fn[] = "glint_scene_set_camera";
    if (!api_finite(in->eye, 3) || !api_finite(in->look_at, 3) || !api_finite(in->up, 3) ||
        !api_finite(&in->fov, 1) || !api_finite(&in->aperture, 1) ||
        !api_finite(&in->focus_distance, 1) || !api_finite(&in->width, 1) ||
        !api_finite(&in->shutter, 1))
        return api_bad(err, fn, "every camera value must be a finite number");
    if ((unsigned)in->projection > GLINT_PROJECTION_FISHEYE)
        return api_bad(err, fn, "projection must be %d to %d (got %d)",
                       GLINT_PROJECTION_PERSPECTIVE, GLINT_PROJECTION_FISHEYE,
                       (int)in->projection);
    if (in->projection == GLINT_PROJECTION_PERSPECTIVE &&
        !((float)in->fov > 0.0f && (float)in->fov < 180.0f))
        return api_bad(err, fn, "fov must be > 0 and < 180 degrees (got %g)", in->fov);
    if (in->projection == GLINT_PROJECTION_FISHEYE &&
        !((float)in->fov > 0.0f && (float)in->fov <= 360.0f))
        return api_bad(err, fn, "a fisheye's fov must be > 0 and <= 360 degrees (got %g)",
                       in->fov);
    if (in->projection == GLINT_PROJECTION_ORTHOGRAPHIC && !((float)in->width > 0.0f))
        return api_bad(err, fn, "an orthographic camera's width must be > 0 (got %g)",
                       in->width);
    if (in->aperture < 0.0)
        return api_bad(err, fn, "aperture must be >= 0 (got %g)", in->aperture);
    if (in->focus_distance < 0.0)
        return api_bad(err, fn, "focus_distance must be >= 0 (got %g)", in->focus_distance);
    if (!(in->shutter >= 0.0 && in->shutter <= 1.0))
        return api_bad(err, fn, "shutter must be 0 to 1 (got %g)", in->shutter);
    return GLINT_OK;
}

glint_rc glint_scene_set_camera(glint_scene *s, const glint_camera *in, glint_error *err)
{
    static const char fn[] = "glint_scene_set_camera";
    if (!s || !in)
        return api_null(err, fn, !s ? "scene" : "camera");
    glint_rc rc = camera_ranges(in, err);
    if (rc != GLINT_OK)
        return rc;
    bool fisheye = in->projection == GLINT_PROJECTION_FISHEYE;
    camera c = {.eye = api_vec3(in->eye), .target = api_vec3(in->look_at),
                .up = api_vec3(in->up),
                .hfov = in->projection == GLINT_PROJECTION_PERSPECTIVE || fisheye
                            ? (float)in->fov : 90.0f,
                .aperture = (float)in->aperture, .focus_distance = (float)in->focus_distance,
                .width = (float)in->width, .shutter = (float)in->shutter,
                .projection = projections[in->projection]};
    vec3 view = v3_sub(c.target, c.eye);
    if (v3_is_zero(view))
        return api_bad(err, fn, "camera look_at must differ from eye");
    if (v3_is_zero(v3_cross(view, c.up)))
        return api_bad(err, fn, "camera up must not be zero nor parallel to the view direction");
    scene_set_camera(s, &c);
    return scene_camera_changed(s, err);
}

/* ---- animation -------------------------------------------------------------- */

glint_rc glint_scene_animation(const glint_scene *s, glint_animation *out, glint_error *err)
{
    if (!s || !out)
        return api_null(err, __func__, !s ? "scene" : "out");
    *out = (glint_animation){s->anim.frames, (double)s->anim.fps, (double)s->anim.start};
    return GLINT_OK;
}

glint_rc glint_scene_set_time(glint_scene *s, double seconds, glint_error *err)
{
    if (!s)
        return api_null(err, __func__, "scene");
    if (!isfinite((float)seconds))
        return api_bad(err, __func__, "time must be a finite number (got %g)", seconds);
    return scene_set_time(s, (float)seconds, err);
}

glint_rc glint_scene_set_frame(glint_scene *s, int frame, glint_error *err)
{
    if (!s)
        return api_null(err, __func__, "scene");
    if (frame < 1 || frame > s->anim.frames)
        return api_bad(err, __func__, "frame %d is out of range (1 to %d)", frame,
                       s->anim.frames);
    return scene_set_time(s, s->anim.start + (float)(frame - 1) / s->anim.fps, err);
}

/* ---- films and rendering ---------------------------------------------------- */

/* glint_film_alloc, its pages mapped by up to `threads` threads
 * (render_film_rgb). */
static glint_rc film_alloc(glint_film *film, int width, int height, int threads,
                           glint_error *err)
{
    if (!film)
        return api_null(err, "glint_film_alloc", "film");
    if (width < 1 || height < 1 || width > SETTINGS_MAX_SIDE || height > SETTINGS_MAX_SIDE ||
        (uint64_t)width * (uint64_t)height > SETTINGS_MAX_PIXELS)
        return api_bad(err, "glint_film_alloc",
                       "film size %dx%d is out of range (1 to %d per side)", width, height,
                       SETTINGS_MAX_SIDE);
    float *rgb = render_film_rgb(width, height, threads);
    if (!rgb)
        return err_nomem(err);
    *film = (glint_film){width, height, rgb, NULL};
    return GLINT_OK;
}

glint_rc glint_film_alloc(glint_film *film, int width, int height, glint_error *err)
{
    return film_alloc(film, width, height, 1, err);
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
    rc = film_alloc(film, settings->width, settings->height, settings->threads, err);
    if (rc != GLINT_OK)
        return rc;
    if (settings->alpha) {
        film->alpha = calloc((size_t)settings->width * (size_t)settings->height,
                             sizeof *film->alpha);
        if (!film->alpha) {
            render_film_free(film);
            return err_nomem(err);
        }
    }
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

/* The smallest rectangle holding every listed tile (empty for none). */
static glint_rect tiles_bounds(int w, int h, const int *tiles, int ntiles)
{
    glint_rect box = {0, 0, 0, 0};
    for (int i = 0; i < ntiles; i++) {
        glint_rect r = render_tile_rect(w, h, tiles[i]);
        if (i == 0 || r.x0 < box.x0)
            box.x0 = r.x0;
        if (i == 0 || r.y0 < box.y0)
            box.y0 = r.y0;
        if (i == 0 || r.x1 > box.x1)
            box.x1 = r.x1;
        if (i == 0 || r.y1 > box.y1)
            box.y1 = r.y1;
    }
    return box;
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
    int w = settings->width, h = settings->height;
    rc = check_tiles(tiles, ntiles, render_tile_count(w, h), err);
    if (rc != GLINT_OK)
        return rc;
    render_work work = {.tiles = tiles, .ntiles = ntiles};
    glint_rect box = tiles_bounds(w, h, tiles, ntiles);
    if (ntiles > 0 && film->width == box.x1 - box.x0 && film->height == box.y1 - box.y0) {
        work.film_x0 = box.x0;
        work.film_y0 = box.y0;
    } else if (film->width != w || film->height != h) {
        return api_bad(err, fn, "film is %dx%d; it must be the image's size (%dx%d) or the tiles' bounds (%dx%d)",
                       film->width, film->height, w, h, box.x1 - box.x0, box.y1 - box.y0);
    }
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
    glint_write_options o = opts ? *opts : (glint_write_options){0};
    if (!o.alpha)
        o.alpha = film->alpha;
    return image_write_film(path, film->width, film->height, film->rgb, &o, err);
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
