/* settings: the limits every render is held to and the check that enforces
 * them before anything is allocated. The world owns them so that every front
 * end (scene files, the C API, the command line) refuses the same values with
 * the same words. */
#ifndef GLINT_SCENE_SETTINGS_H
#define GLINT_SCENE_SETTINGS_H

#include "glint.h"

#define SETTINGS_MAX_SIDE 32768
#define SETTINGS_MAX_PIXELS (1u << 27) /* 134M pixels: a 1.5 GiB float film */
#define SETTINGS_MAX_SAMPLES 1024      /* 32 x 32 */
#define SETTINGS_MAX_DEPTH 64
#define SETTINGS_MAX_THREADS 1024
#define SETTINGS_MAX_ADAPTIVE_DEPTH 5 /* 32 x 32 cells, as many as SETTINGS_MAX_SAMPLES */
/* A scene's adaptive depth control threshold unless it says otherwise:
 * one step of an 8-bit pixel, POV-Ray's adc_bailout default. */
#define SETTINGS_ADC_BAILOUT (1.0 / 255.0)

/* GLINT_OK when every field is in range; otherwise GLINT_ERR_INPUT and a
 * message naming the field, its range and the value given. */
glint_rc settings_check(const glint_settings *s, glint_error *err);

/* The side of the N x N sample grid for n samples per pixel, or -1 when n
 * is not a perfect square. */
int settings_grid_side(int samples);

/* Threads a render with settings.threads == 0 uses: one per online core. */
int settings_default_threads(void);

#endif
