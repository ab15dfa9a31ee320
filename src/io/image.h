/* image: pictures read from untrusted files or memory, and films written out.
 *
 * Reading. The format is told by the file's first bytes, never its name:
 * PNG through libspng and JPEG through libjpeg-turbo (the reference
 * decoders, fuzzed upstream); Radiance HDR, PFM and binary PPM/PGM through
 * the small parsers in this folder; BMP, TGA and GIF through stb_image, the
 * only formats left to it (no hardened Debian library reads them). The
 * libraries are opened at their first use, not linked (codec.h). Every
 * reader checks the size in the header against IMAGE_MAX_PIXELS before it
 * allocates or decodes a pixel, and every message starts with the name.
 *
 * An image holds either 8-bit stored values (`rgb`; turning them into linear
 * light is the texture's business, through a table per transfer function)
 * or linear floats (`linear`, from HDR and PFM files, used as they are).
 * Exactly one of the two is non-null in a loaded image.
 *
 * Writing: image_write.h. */
#ifndef GLINT_IO_IMAGE_H
#define GLINT_IO_IMAGE_H

#include <stddef.h>
#include <stdint.h>
#include "glint.h"

typedef struct image {
    int width, height;
    uint8_t *rgb;  /* width*height*3 stored bytes, row 0 at the top; or NULL */
    float *linear; /* width*height*3 linear floats, row 0 at the top; or NULL */
} image;

/* Largest image accepted on input, in pixels (a decompression bomb's header
 * claims far more; 2^28 is a 16384x16384 texture). */
#define IMAGE_MAX_PIXELS (1u << 28)

/* Largest image file read, in bytes. */
#define IMAGE_MAX_FILE_BYTES (1L << 30)

/* Reads the image at path (a regular file; anything else is refused at once,
 * without blocking). Errors are GLINT_ERR_INPUT (bad or unreadable file) or
 * GLINT_ERR_NOMEM. */
glint_rc image_load(const char *path, image *out, glint_error *err);
/* The same from memory; name is used in messages only. */
glint_rc image_load_memory(const void *data, size_t size, const char *name, image *out,
                           glint_error *err);
void image_free(image *img);

/* A film value as shown: clamped to [0, 1] (NaN to 0), then through the
 * transfer function. */
float image_display_value(float x, glint_transfer transfer);
/* Film to 8-bit: each value through the transfer function, clamped to
 * [0, 1], rounded to the nearest of 256 levels. */
void image_quantize(const float *src, size_t count, glint_transfer transfer, uint8_t *dst);
/* The same to 16 bits (65536 levels). */
void image_quantize16(const float *src, size_t count, glint_transfer transfer, uint16_t *dst);

/* 256-entry table from stored 8-bit values to linear values for textures. */
void image_decode_table(glint_transfer transfer, float table[256]);

#endif
