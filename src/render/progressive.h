/* progressive: rendering an image in passes that converge to exactly the
 * batch image. An accumulating film (glint_accum) keeps, per pixel, the sum
 * of its first m primary samples, with m counted per tile; a pass brings
 * every tile up to a target m, tracing only the samples it lacks, in the
 * batch order (render_samples), so the sum is the same float the batch
 * render builds. Resolving multiplies by 1/m as the batch render does: with
 * m equal to the settings' samples the film is byte-identical to
 * glint_render's. A cancelled pass leaves each tile either before or after
 * the pass, never in between, so the next pass picks up from there. */
#ifndef GLINT_RENDER_PROGRESSIVE_H
#define GLINT_RENDER_PROGRESSIVE_H

#include <stdint.h>
#include "glint.h"
#include "scene/camera.h"
#include "trace/whitted.h"

glint_rc progressive_alloc(glint_accum *a, int width, int height, glint_error *err);
void progressive_free(glint_accum *a);
/* Samples a pass up to upto per pixel would trace. */
uint64_t progressive_samples_left(const glint_accum *a, int upto);
/* film = sum / samples over rect, per tile; tiles with no sample yet are
 * left as they are. */
void progressive_resolve(const glint_accum *a, glint_rect rect, glint_film *film);
/* The fewest samples per pixel of any tile. */
int progressive_min_samples(const glint_accum *a);

#endif
