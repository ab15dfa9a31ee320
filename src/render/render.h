/* render: turns a built scene into a film. The image is cut into square
 * tiles handed out from a shared counter to a pool of threads; each pixel
 * depends only on its own position, so the film is bit-identical for any
 * thread count or tile order. Front ends watch through glint_callbacks. */
#ifndef GLINT_RENDER_RENDER_H
#define GLINT_RENDER_RENDER_H

#include "glint.h"

#define RENDER_TILE 16

/* Limits that glint_settings_check enforces before anything is allocated. */
#define RENDER_MAX_SIDE 32768
#define RENDER_MAX_PIXELS (1u << 27) /* 134M pixels: a 1.5 GiB float film */
#define RENDER_MAX_SAMPLES 1024      /* 32 x 32 */
#define RENDER_MAX_DEPTH 64
#define RENDER_MAX_THREADS 1024

/* Threads a render with settings.threads == 0 uses. */
int render_default_threads(void);

#endif
