/* image: 8-bit RGB pictures read from files or memory (PNG, JPEG, BMP, TGA,
 * and the rest stb_image knows), and films written out as PNG or PPM.
 * Images keep their stored byte values; turning them into linear light is
 * the texture's business (a lookup table per transfer function). */
#ifndef GLINT_IO_IMAGE_H
#define GLINT_IO_IMAGE_H

#include <stddef.h>
#include <stdint.h>
#include "glint.h"

typedef struct image {
    int width, height;
    uint8_t *rgb; /* width*height*3 bytes, row 0 at the top */
} image;

/* Largest image accepted on input, in pixels (protects against absurd headers). */
#define IMAGE_MAX_PIXELS (1u << 28)

glint_rc image_load(const char *path, image *out, glint_error *err);
/* name is used in messages only. */
glint_rc image_load_memory(const void *data, size_t size, const char *name, image *out,
                           glint_error *err);
void image_free(image *img);

/* Writes width*height RGB bytes to path as PNG or PPM by extension, through
 * a temporary file renamed into place, so a failed write leaves no partial
 * file behind. */
glint_rc image_write(const char *path, int width, int height, const uint8_t *rgb,
                     glint_error *err);

/* Film to 8-bit: each value through the transfer function, clamped to
 * [0, 1], rounded to the nearest of 256 levels. */
void image_quantize(const float *src, size_t count, glint_transfer transfer, uint8_t *dst);

/* 256-entry table from stored 8-bit values to linear values for textures. */
void image_decode_table(glint_transfer transfer, float table[256]);

#endif
