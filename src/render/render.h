/* render: turns a built scene into a film. The image is cut into square
 * tiles handed out from a shared counter to a pool of threads; each pixel
 * depends only on its own position, so the film is bit-identical for any
 * thread count or tile order. Front ends watch through glint_callbacks. */
#ifndef GLINT_RENDER_RENDER_H
#define GLINT_RENDER_RENDER_H

#include "glint.h"

#define RENDER_TILE 16

struct glint_scene;

/* Renders a built scene into *film (allocated here). callbacks and stats may
 * be NULL. On any error the film is left empty. */
glint_rc render_run(const struct glint_scene *sc, const glint_settings *settings,
                    const glint_callbacks *callbacks, glint_film *film, glint_stats *stats,
                    glint_error *err);

/* Frees a film's pixels and empties it; NULL is fine. */
void render_film_free(glint_film *film);

#endif
