/* A film's pixels and the tile grid they are rendered in (render.h). */
#include "render.h"

#include <stdlib.h>

#include "core/spare.h"

int render_tile_count(int width, int height)
{
    return ((width + RENDER_TILE - 1) / RENDER_TILE) * ((height + RENDER_TILE - 1) / RENDER_TILE);
}

glint_rect render_tile_rect(int width, int height, int tile)
{
    int tiles_x = (width + RENDER_TILE - 1) / RENDER_TILE;
    int x0 = (tile % tiles_x) * RENDER_TILE, y0 = (tile / tiles_x) * RENDER_TILE;
    return (glint_rect){x0, y0, x0 + RENDER_TILE < width ? x0 + RENDER_TILE : width,
                        y0 + RENDER_TILE < height ? y0 + RENDER_TILE : height};
}

float *render_film_rgb(int width, int height, int threads)
{
    return spare_calloc((size_t)width * (size_t)height * 3 * sizeof(float), threads);
}

void render_film_free(glint_film *film)
{
    if (!film)
        return;
    spare_free(film->rgb);
    free(film->alpha);
    film->rgb = NULL;
    film->alpha = NULL;
    film->width = film->height = 0;
}
