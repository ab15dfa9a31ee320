/* codec: the image formats, each a decoder from memory into an image and an
 * encoder from a film raster into memory. Files are only touched by
 * image.c (reading) and file.c (writing), so every codec is a pure function
 * of its bytes: easy to fuzz, and an output file is never created before
 * its bytes exist.
 *
 * Decoders: data/size are the whole file; name is for messages, which all
 * start "name: ". They check the header's size with codec_check_size before
 * allocating pixels, say "file is truncated" when the data stops early, and
 * leave *out untouched on failure.
 *
 * Encoders append to a byte buffer and return GLINT_OK or GLINT_ERR_NOMEM
 * (or GLINT_ERR_INPUT for a raster the format cannot hold). */
#ifndef GLINT_IO_CODEC_H
#define GLINT_IO_CODEC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "glint.h"

typedef struct image image;

/* A growable byte buffer. */
typedef struct bytebuf {
    uint8_t *data;
    size_t len, cap;
} bytebuf;

/* Makes room for n more bytes and returns where they go (len grows by n),
 * or NULL when memory runs out. */
uint8_t *bytes_grow(bytebuf *b, size_t n);
/* Makes room for n more bytes without counting them (cap >= len + n). */
bool bytes_reserve(bytebuf *b, size_t n);
bool bytes_append(bytebuf *b, const void *data, size_t n);
void bytes_free(bytebuf *b);

/* A film to encode: linear float RGB, optional coverage in [0, 1]. */
typedef struct raster {
    int width, height;
    const float *rgb;   /* width*height*3, row 0 at the top */
    const float *alpha; /* width*height or NULL: no alpha channel */
    glint_transfer transfer; /* for 8- and 16-bit formats */
    int bits;                /* per channel; already checked for the format */
    int quality;             /* JPEG, 1..100 */
    int threads;             /* PNG: threads compressing it; 0: one per core */
} raster;

/* "name: image WxH is too large (limit N pixels)" or an empty-size error. */
glint_rc codec_check_size(uint64_t width, uint64_t height, const char *name, glint_error *err);
/* A header may claim far more pixels than its data can encode (a few
 * bytes of run-length codes declaring 100 million pixels): when
 * width * height exceeds size * per_byte, the most any byte of the format
 * can expand to, the file is truncated, said before memory is asked for. */
glint_rc codec_check_data(uint64_t width, uint64_t height, size_t size, uint64_t per_byte,
                          const char *name, glint_error *err);
/* "name: file is truncated" */
glint_rc codec_truncated(const char *name, glint_error *err);

glint_rc png_decode(const uint8_t *data, size_t size, const char *name, image *out,
                    glint_error *err);
glint_rc jpeg_decode(const uint8_t *data, size_t size, const char *name, image *out,
                     glint_error *err);
glint_rc rgbe_decode(const uint8_t *data, size_t size, const char *name, image *out,
                     glint_error *err);
glint_rc pfm_decode(const uint8_t *data, size_t size, const char *name, image *out,
                    glint_error *err);
glint_rc pnm_decode(const uint8_t *data, size_t size, const char *name, image *out,
                    glint_error *err);
glint_rc exr_decode(const uint8_t *data, size_t size, const char *name, image *out,
                    glint_error *err);
/* BMP, TGA and GIF (first frame), through stb_image. */
glint_rc legacy_decode(const uint8_t *data, size_t size, const char *name, image *out,
                       glint_error *err);

glint_rc png_encode(const raster *r, bytebuf *out, glint_error *err);
glint_rc pnm_encode(const raster *r, bytebuf *out, glint_error *err);
glint_rc jpeg_encode(const raster *r, bytebuf *out, glint_error *err);
glint_rc rgbe_encode(const raster *r, bytebuf *out, glint_error *err);
glint_rc pfm_encode(const raster *r, bytebuf *out, glint_error *err);
glint_rc exr_encode(const raster *r, bytebuf *out, glint_error *err);

/* The fast PNG writer's core, also used by the benchmark and the tests:
 * 8- or 16-bit samples (16-bit ones in native order, written big-endian),
 * 1 to 4 channels, rows packed; threads as in raster. */
glint_rc png_encode_pixels(int width, int height, int channels, int bits, const void *pixels,
                           int threads, bytebuf *out, glint_error *err);

/* The rows of each strip the PNG writer compresses apart (png_write.c): a
 * function of the image's size alone, so the file's bytes do not depend on
 * the number of threads. */
int png_strip_rows(int width, int height, int channels, int bits);

#endif
