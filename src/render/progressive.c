#include "progressive.h"

#include <stdlib.h>

#include "core/array.h"
#include "core/error.h"
#include "render/render.h"

glint_rc progressive_alloc(glint_accum *a, int width, int height, glint_error *err)
{
    *a = (glint_accum){width, height, render_tile_count(width, height), NULL, NULL,
                        NULL, NULL};
    a->tile_samples = calloc((size_t)a->ntiles, sizeof *a->tile_samples);
    a->tile_div = calloc((size_t)a->ntiles, sizeof *a->tile_div);
    a->sum = array_calloc_big((size_t)width * (size_t)height * 3 * sizeof *a->sum);
    a->cover = calloc((size_t)width * (size_t)height, sizeof *a->cover);
    if (!a->tile_samples || !a->tile_div || !a->sum || !a->cover) {
        progressive_free(a);
        return err_nomem(err);
    }
    return GLINT_OK;
}

void progressive_free(glint_accum *a)
{
    if (!a)
        return;
    free(a->tile_samples);
    free(a->sum);
    free(a->cover);
    free(a->tile_div);
    *a = (glint_accum){0};
}

static uint64_t tile_area(const glint_accum *a, int tile)
{
    glint_rect r = render_tile_rect(a->width, a->height, tile);
    return (uint64_t)(r.x1 - r.x0) * (uint64_t)(r.y1 - r.y0);
}

uint64_t progressive_samples_left(const glint_accum *a, int upto)
{
    uint64_t n = 0;
    for (int t = 0; t < a->ntiles; t++)
        if (a->tile_samples[t] < upto)
            n += tile_area(a, t) * (uint64_t)(upto - a->tile_samples[t]);
    return n;
}

void progressive_resolve(const glint_accum *a, glint_rect g, glint_film *film)
{
    for (int t = 0; t < a->ntiles; t++) {
        int m = a->tile_div[t];
        if (m == 0)
            continue;
        float inv = 1.0f / (float)m;
        glint_rect r = render_tile_rect(a->width, a->height, t);
        if (r.x1 <= g.x0 || r.x0 >= g.x1 || r.y1 <= g.y0 || r.y0 >= g.y1)
            continue;
        int x0 = r.x0 > g.x0 ? r.x0 : g.x0, x1 = r.x1 < g.x1 ? r.x1 : g.x1;
        int y0 = r.y0 > g.y0 ? r.y0 : g.y0, y1 = r.y1 < g.y1 ? r.y1 : g.y1;
        for (int y = y0; y < y1; y++)
            for (int x = x0; x < x1; x++) {
                size_t at = ((size_t)y * (size_t)a->width + (size_t)x) * 3;
                for (int c = 0; c < 3; c++)
                    film->rgb[at + (size_t)c] = a->sum[at + (size_t)c] * inv;
                if (film->alpha)
                    film->alpha[at / 3] = a->cover[at / 3] * inv;
            }
    }
}

int progressive_min_samples(const glint_accum *a)
{
    int m = a->ntiles > 0 ? a->tile_samples[0] : 0;
    for (int t = 1; t < a->ntiles; t++)
        if (a->tile_samples[t] < m)
            m = a->tile_samples[t];
    return m;
}
