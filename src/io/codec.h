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
 * Encoders append to a byte buffer (the PNG writer fills a bytelist) and
 * return GLINT_OK or GLINT_ERR_NOMEM (or GLINT_ERR_INPUT for a raster the
 * format cannot hold, GLINT_ERR_IO naming the file when the library that
 * writes the format cannot be opened).
 *
 * The libraries behind JPEG (jpeg.c), OpenEXR (exr.c), BMP/TGA/GIF
 * (legacy.c), the PNGs glint's own reader leaves to libspng (png.c) and
 * ISA-L (png_write.c) are opened at their first use (core/dynlib.h), not
 * linked: a decoder that cannot open its library says so as it says a
 * file is broken ("name: cannot read JPEG files (why)", GLINT_ERR_INPUT). */
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

/* An encoded file as pieces written in order (file_write_pieces): a
 * PNG's compressed strips stay in the blocks their threads wrote them in,
 * instead of being copied into one new block (on a virtual machine whose
 * host maps fresh memory slowly, 1-2 ms a MiB, the block cost more than
 * the copy). A piece is the list's own bytes (headers, checksums: from
 * NULL, at an offset into own) or bytes that lie elsewhere, in blocks
 * the list holds and frees or that outlive it. (io/bytelist.c) */
typedef struct bytepiece {
    const uint8_t *from; /* NULL: own.data + at */
    size_t at, n;
} bytepiece;

typedef struct bytelist {
    bytebuf own;
    bytepiece *pieces;
    int n, cap;
    void **held; /* freed with the list */
    int nheld, cap_held;
} bytelist;

/* n bytes copied into the list's own; false when memory runs out. */
bool bytelist_own(bytelist *l, const void *data, size_t n);
/* n bytes at p, which must stay there until the list is written. */
bool bytelist_ref(bytelist *l, const void *p, size_t n);
/* block freed with the list; when memory runs out, freed now (false). */
bool bytelist_hold(bytelist *l, void *block);
/* A bytebuf's bytes as the list's own, the only piece, in place of what
 * the list held: b is taken (and freed with the list even when memory
 * runs out: false). */
bool bytelist_of(bytelist *l, bytebuf *b);
size_t bytelist_len(const bytelist *l);
/* Where piece i's bytes are. */
const uint8_t *bytelist_at(const bytelist *l, int i);
/* All the pieces in one block, appended to out; false when memory runs out. */
bool bytelist_flatten(const bytelist *l, bytebuf *out);
void bytelist_free(bytelist *l);

/* A film to encode: linear float RGB, optional coverage in [0, 1]. */
typedef struct raster {
    int width, height;
    const float *rgb;   /* width*height*3, row 0 at the top */
    const float *alpha; /* width*height or NULL: no alpha channel */
    glint_transfer transfer; /* for 8- and 16-bit formats */
    int bits;                /* per channel; already checked for the format */
    int quality;             /* JPEG, 1..100 */
    int threads;             /* PNG: threads compressing it; 0: one per core */
    const char *name;        /* the file, for messages (NULL: the format's name) */
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
/* png_decode's own reader of the common PNG forms alone (png.c): the
 * pixels into *out, or false, *out untouched, for a file it leaves to
 * libspng (another form, a damaged or an unusual file). */
bool png_decode_common(const uint8_t *data, size_t size, image *out);
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

glint_rc png_encode(const raster *r, bytelist *out, glint_error *err);
glint_rc pnm_encode(const raster *r, bytebuf *out, glint_error *err);
glint_rc jpeg_encode(const raster *r, bytebuf *out, glint_error *err);
glint_rc rgbe_encode(const raster *r, bytebuf *out, glint_error *err);
glint_rc pfm_encode(const raster *r, bytebuf *out, glint_error *err);
glint_rc exr_encode(const raster *r, bytebuf *out, glint_error *err);
/* Whether jpeg_encode and exr_encode can run: their library opens (it is
 * opened at first use, core/dynlib.h); else GLINT_ERR_IO naming the file
 * (name) and the library. Checked before a render too (image_write_check),
 * so that a render is not made for nothing. */
glint_rc jpeg_writer_ready(const char *name, glint_error *err);
glint_rc exr_writer_ready(const char *name, glint_error *err);

/* The fast PNG writer's core, also used by the benchmark and the tests:
 * 8- or 16-bit samples (16-bit ones in native order, written big-endian),
 * 1 to 4 channels, rows packed; threads as in raster. */
glint_rc png_encode_pixels(int width, int height, int channels, int bits, const void *pixels,
                           int threads, bytebuf *out, glint_error *err);
/* The same with IDAT chunks of at most chunk_max bytes (1 GiB in every
 * file glint writes), as pieces: for the tests of the chunks' seams. */
glint_rc png_encode_chunked(int width, int height, int channels, int bits, const void *pixels,
                            int threads, size_t chunk_max, bytelist *out, glint_error *err);

/* The rows of each strip the PNG writer compresses apart (png_write.c): a
 * function of the image's size alone, so the file's bytes do not depend on
 * the number of threads. */
int png_strip_rows(int width, int height, int channels, int bits);

#endif
