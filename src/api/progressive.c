/* The public progressive-rendering functions (include/glint.h): argument
 * checks, then render/progressive.c and the tile renderer. */
#include "glint.h"

#include <string.h>

#include "api/check.h"
#include "io/image.h"
#include "render/progressive.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/settings.h"

glint_rc glint_accum_alloc(glint_accum *a, int width, int height, glint_error *err)
{
    if (!a)
        return api_null(err, __func__, "a");
    if (width < 1 || height < 1 || width > SETTINGS_MAX_SIDE || height > SETTINGS_MAX_SIDE ||
        (uint64_t)width * (uint64_t)height > SETTINGS_MAX_PIXELS)
        return api_bad(err, __func__, "size %dx%d is out of range (1 to %d per side)", width,
                       height, SETTINGS_MAX_SIDE);
    return progressive_alloc(a, width, height, err);
}

void glint_accum_free(glint_accum *a) { progressive_free(a); }

static bool accum_whole(const glint_accum *a)
{
    return a->sum && a->tile_samples && a->cover && a->tile_div &&
           a->ntiles == render_tile_count(a->width, a->height);
}

void glint_accum_clear(glint_accum *a)
{
    if (!a || !accum_whole(a))
        return;
    memset(a->tile_samples, 0, (size_t)a->ntiles * sizeof *a->tile_samples);
    memset(a->tile_div, 0, (size_t)a->ntiles * sizeof *a->tile_div);
    memset(a->sum, 0, (size_t)a->width * (size_t)a->height * 3 * sizeof *a->sum);
}

glint_rc glint_render_pass(const glint_scene *sc, const glint_settings *settings, int upto,
                           const glint_callbacks *cb, glint_accum *a, glint_stats *stats,
                           glint_error *err)
{
    static const char fn[] = "glint_render_pass";
    if (!sc || !a)
        return api_null(err, fn, !sc ? "scene" : "a");
    glint_settings own;
    if (!settings) {
        own = scene_settings(sc);
        settings = &own;
    }
    glint_rc rc = settings_check(settings, err);
    if (rc != GLINT_OK)
        return rc;
    if (!accum_whole(a))
        return api_bad(err, fn, "accumulating film was not made by glint_accum_alloc");
    if (a->width != settings->width || a->height != settings->height)
        return api_bad(err, fn, "accumulating film is %dx%d; the image is %dx%d", a->width,
                       a->height, settings->width, settings->height);
    if (upto < 1 || upto > settings->samples)
        return api_bad(err, fn, "upto must be 1 to %d (the samples per pixel), got %d",
                       settings->samples, upto);
    render_work w = {.region = {0, 0, settings->width, settings->height}, .accum = a, .upto = upto};
    glint_film none = {.width = settings->width, .height = settings->height};
    return render_run(sc, settings, cb, &w, &none, stats, err);
}

/* rect, or the whole image for NULL; GLINT_ERR_INPUT when not inside it. */
static glint_rc whole_or(const glint_rect *rect, int w, int h, glint_rect *out, const char *fn,
                         glint_error *err)
{
    *out = rect ? *rect : (glint_rect){0, 0, w, h};
    if (out->x0 < 0 || out->y0 < 0 || out->x1 > w || out->y1 > h || out->x0 >= out->x1 ||
        out->y0 >= out->y1)
        return api_bad(err, fn, "rect [%d, %d) x [%d, %d) is empty or not inside the %dx%d image",
                       out->x0, out->x1, out->y0, out->y1, w, h);
    return GLINT_OK;
}

glint_rc glint_accum_resolve(const glint_accum *a, const glint_rect *rect, glint_film *film,
                             int *min_samples, glint_error *err)
{
    if (!a || !film || !film->rgb)
        return api_null(err, __func__, !a ? "a" : !film ? "film" : "film->rgb");
    if (!accum_whole(a))
        return api_bad(err, __func__, "accumulating film was not made by glint_accum_alloc");
    if (film->width != a->width || film->height != a->height)
        return api_bad(err, __func__, "film is %dx%d; it must be %dx%d", film->width,
                       film->height, a->width, a->height);
    glint_rect g;
    glint_rc rc = whole_or(rect, a->width, a->height, &g, __func__, err);
    if (rc != GLINT_OK)
        return rc;
    progressive_resolve(a, g, film);
    if (min_samples)
        *min_samples = progressive_min_samples(a);
    return GLINT_OK;
}

glint_rc glint_film_quantize(const glint_film *film, const glint_rect *rect,
                             glint_transfer transfer, uint8_t *dst, glint_error *err)
{
    if (!film || !film->rgb || !dst)
        return api_null(err, __func__, !film ? "film" : !dst ? "dst" : "film->rgb");
    if ((unsigned)transfer > GLINT_TRANSFER_SRGB)
        return api_bad(err, __func__, "transfer must be none or srgb (got %d)", (int)transfer);
    glint_rect g;
    glint_rc rc = whole_or(rect, film->width, film->height, &g, __func__, err);
    if (rc != GLINT_OK)
        return rc;
    size_t n = (size_t)(g.x1 - g.x0) * 3;
    for (int y = g.y0; y < g.y1; y++) {
        size_t at = ((size_t)y * (size_t)film->width + (size_t)g.x0) * 3;
        image_quantize(film->rgb + at, n, transfer, dst + at);
    }
    return GLINT_OK;
}
