/* render: turns a built scene into film pixels. The work is a set of tiles
 * of the image's tile grid (RENDER_TILE pixels square, numbered row by row;
 * film.c), clipped to a region or listed one by one, shared among a pool of
 * threads in bands of consecutive tiles (bands.h); each pixel depends only
 * on its own position, so the film is bit-identical for any thread count,
 * tile order or split of the image into regions. Front ends watch and stop
 * it through glint_callbacks. */
#ifndef GLINT_RENDER_RENDER_H
#define GLINT_RENDER_RENDER_H

#include "glint.h"
#include "scene/camera.h"
#include "trace/whitted.h"

#define RENDER_TILE 16

struct glint_scene;

/* What to render: the tiles listed, or (tiles NULL) every tile meeting
 * region, clipped to it. The film is image-sized, or region-sized with
 * (film_x0, film_y0) the image position of its top-left pixel. */
typedef struct render_work {
    glint_rect region;
    const int *tiles;
    int ntiles;
    int film_x0, film_y0;
    glint_accum *accum; /* non-NULL: a progressive pass over the whole image
                           (region, no list) adding samples up to upto into it */
    int upto;
} render_work;

/* The tile grid of a width x height image. */
int render_tile_count(int width, int height);
glint_rect render_tile_rect(int width, int height, int tile);

/* Renders the work into film (allocated by the caller, checked by it to fit
 * the work). Settings are checked here; the scene must be built.
 * callbacks and stats may be NULL. On cancellation the tiles reported done
 * are in the film. */
glint_rc render_run(const struct glint_scene *sc, const glint_settings *settings,
                    const glint_callbacks *callbacks, const render_work *work, glint_film *film,
                    glint_stats *stats, glint_error *err);

/* A film's width x height RGB pixels, zeroed, their pages mapped by up to
 * `threads` threads (a render's count: array_calloc_big_on); NULL when
 * memory runs out. Freed by render_film_free. */
float *render_film_rgb(int width, int height, int threads);

/* Frees a film's pixels and empties it; NULL is fine. */
void render_film_free(glint_film *film);

#endif
