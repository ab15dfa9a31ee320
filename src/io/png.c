/* png: PNG read through libspng, written by a small encoder.
 *
 * The writer filters every row with one fixed filter (Up) and compresses
 * the whole image in one call to libdeflate at level 3: on rendered images
 * that is about 5 times faster than libpng's defaults (zlib level 6,
 * adaptive filters) for files about 1.1 times their size. ISA-L's igzip is
 * faster still but its files come out 1.35-1.5 times libpng's whatever the
 * filter; bench/README.md (row 5) has the measurements.
 * PNG: ISO/IEC 15948:2004 (chunks, filters section 9, CRC annex D). */
#include <stdlib.h>
#include <string.h>

#include <libdeflate.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <spng.h>

#include "codec.h"
#include "core/error.h"
#include "image.h"

/* ---- reading ------------------------------------------------------------ */

static glint_rc spng_failure(int e, const char *name, glint_error *err)
{
    switch (e) {
    case SPNG_IO_EOF:
    case SPNG_EOF:
    case SPNG_EIDAT_TOO_SHORT:
        return codec_truncated(name, err);
    case SPNG_EMEM:
        return err_nomem(err);
    default:
        return err_set(err, GLINT_ERR_INPUT, "%s: broken PNG file (%s)", name, spng_strerror(e));
    }
}

glint_rc png_decode(const uint8_t *data, size_t size, const char *name, image *out,
                    glint_error *err)
{
    spng_ctx *ctx = spng_ctx_new(0);
    if (!ctx)
        return err_nomem(err);
    glint_rc rc = GLINT_OK;
    uint8_t *px = NULL;
    struct spng_ihdr ihdr;
    /* metadata chunks are skipped, but bounded all the same */
    int e = spng_set_chunk_limits(ctx, 1u << 24, 1u << 26);
    if (!e)
        e = spng_set_png_buffer(ctx, data, size);
    if (!e)
        e = spng_get_ihdr(ctx, &ihdr);
    if (e) {
        rc = spng_failure(e, name, err);
        goto out;
    }
    rc = codec_check_size(ihdr.width, ihdr.height, name, err);
    /* deflate expands a byte at most about 1032 times (a 258-byte match
     * fits in 2 bits), and a byte of 1-bit pixels holds 8 of them */
    if (rc == GLINT_OK)
        rc = codec_check_data(ihdr.width, ihdr.height, size, 1032 * 8, name, err);
    if (rc != GLINT_OK)
        goto out;
    size_t len;
    e = spng_decoded_image_size(ctx, SPNG_FMT_RGB8, &len);
    if (e) {
        rc = spng_failure(e, name, err);
        goto out;
    }
    px = malloc(len);
    if (!px) {
        rc = err_nomem(err);
        goto out;
    }
    e = spng_decode_image(ctx, px, len, SPNG_FMT_RGB8, 0);
    if (e) {
        rc = spng_failure(e, name, err);
        goto out;
    }
    *out = (image){.width = (int)ihdr.width, .height = (int)ihdr.height, .rgb = px};
    px = NULL;
out:
    free(px);
    spng_ctx_free(ctx);
    return rc;
}

/* ---- writing ------------------------------------------------------------ */

/* Chunks hold at most 2^31 - 1 bytes; pixel data is split at 1 GiB. */
#define PNG_CHUNK_MAX (1u << 30)

static void put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* The chunk's CRC covers its type and data (annex D: the reflected
 * CRC-32 of ISO 3309, the one gzip uses). */
static void put_crc(uint8_t *type_and_data, size_t n, uint8_t *dst)
{
    put_be32(dst, libdeflate_crc32(0, type_and_data, n));
}

static bool put_chunk(bytebuf *out, const char type[4], const uint8_t *data, uint32_t n)
{
    uint8_t *p = bytes_grow(out, 12 + (size_t)n);
    if (!p)
        return false;
    put_be32(p, n);
    memcpy(p + 4, type, 4);
    if (n)
        memcpy(p + 8, data, n);
    put_crc(p + 4, 4 + (size_t)n, p + 8 + n);
    return true;
}

/* Turns the compressed stream at out[start..] into IDAT chunks in place. */
static bool wrap_idat(bytebuf *out, size_t start)
{
    size_t zlen = out->len - start;
    size_t k = zlen ? (zlen + PNG_CHUNK_MAX - 1) / PNG_CHUNK_MAX : 1;
    if (!bytes_grow(out, 12 * k))
        return false;
    /* move pieces to their places, last first (they only move right) */
    for (size_t i = k; i-- > 0;) {
        size_t off = i * PNG_CHUNK_MAX;
        size_t n = zlen - off < PNG_CHUNK_MAX ? zlen - off : PNG_CHUNK_MAX;
        uint8_t *chunk = out->data + start + i * ((size_t)PNG_CHUNK_MAX + 12);
        memmove(chunk + 8, out->data + start + off, n);
        put_be32(chunk, (uint32_t)n);
        memcpy(chunk + 4, "IDAT", 4);
        put_crc(chunk + 4, 4 + n, chunk + 8 + n);
    }
    return true;
}

/* The image as PNG wants it before compression: each row a filter-type
 * byte and then its samples (16-bit ones big-endian). */
typedef struct png_rows {
    uint8_t *data;
    size_t stride; /* 1 + bytes of a row */
    int height;
} png_rows;

static bool rows_alloc(png_rows *p, int width, int height, int channels, int bits)
{
    size_t rb = (size_t)width * (size_t)channels * (size_t)(bits / 8);
    p->stride = rb + 1;
    p->height = height;
    p->data = (size_t)height > SIZE_MAX / p->stride ? NULL : malloc(p->stride * (size_t)height);
    return p->data != NULL;
}

static uint8_t *row_at(const png_rows *p, int y) { return p->data + (size_t)y * p->stride + 1; }

/* Up filter (section 9.2, type 2) in place: each byte minus the one above
 * it, from the last row up so that every row above is still unfiltered.
 * It compresses flat and vertically smooth areas to almost nothing; row 0
 * is left unfiltered (type 0). */
static void filter_up(png_rows *p)
{
    size_t n = p->stride - 1;
    for (int y = p->height - 1; y > 0; y--) {
        uint8_t *row = row_at(p, y);
        const uint8_t *above = row_at(p, y - 1);
        row[-1] = 2;
        size_t i = 0;
#if defined(__SSE2__)
        for (; i + 16 <= n; i += 16) {
            __m128i a = _mm_loadu_si128((const __m128i *)(row + i));
            __m128i b = _mm_loadu_si128((const __m128i *)(above + i));
            _mm_storeu_si128((__m128i *)(row + i), _mm_sub_epi8(a, b));
        }
#endif
        for (; i < n; i++)
            row[i] = (uint8_t)(row[i] - above[i]);
    }
    p->data[0] = 0;
}

/* The deflate level, 1 to 12 in libdeflate: on rendered images 2 is as
 * fast as 1 with files a few percent smaller; higher levels cost more
 * time than they save bytes. */
#define PNG_DEFLATE_LEVEL 2

/* Filters the rows and appends them to out as one zlib stream. */
static bool compress_rows(png_rows *p, bytebuf *out)
{
    filter_up(p);
    size_t n = p->stride * (size_t)p->height;
    struct libdeflate_compressor *c = libdeflate_alloc_compressor(PNG_DEFLATE_LEVEL);
    size_t bound = c ? libdeflate_zlib_compress_bound(c, n) : 0;
    size_t z = c && bytes_reserve(out, bound)
                   ? libdeflate_zlib_compress(c, p->data, n, out->data + out->len, bound)
                   : 0;
    libdeflate_free_compressor(c);
    out->len += z;
    return z > 0;
}

/* Signature, IHDR, the rows as IDAT chunks, IEND. */
static bool encode_rows(png_rows *p, int width, int channels, int bits, bytebuf *out)
{
    static const uint8_t color_type[5] = {0, 0, 4, 2, 6}; /* grey, grey+alpha, RGB, RGBA */
    uint8_t ihdr[13];
    put_be32(ihdr, (uint32_t)width);
    put_be32(ihdr + 4, (uint32_t)p->height);
    ihdr[8] = (uint8_t)bits;
    ihdr[9] = color_type[channels];
    ihdr[10] = ihdr[11] = ihdr[12] = 0; /* deflate, adaptive filtering, no interlace */
    bool ok = bytes_append(out, "\x89PNG\r\n\x1a\n", 8) && put_chunk(out, "IHDR", ihdr, 13);
    size_t start = out->len;
    return ok && compress_rows(p, out) && wrap_idat(out, start) && put_chunk(out, "IEND", NULL, 0);
}

/* 16-bit samples go big-endian. */
static void put_be16(uint8_t *dst, const uint16_t *src, size_t count)
{
    for (size_t i = 0; i < count; i++) {
        dst[2 * i] = (uint8_t)(src[i] >> 8);
        dst[2 * i + 1] = (uint8_t)src[i];
    }
}

glint_rc png_encode_pixels(int width, int height, int channels, int bits, const void *pixels,
                           bytebuf *out, glint_error *err)
{
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || (bits != 8 && bits != 16))
        return err_set(err, GLINT_ERR_INPUT, "PNG: cannot write %dx%d, %d channels, %d bits",
                       width, height, channels, bits);
    png_rows p;
    if (!rows_alloc(&p, width, height, channels, bits))
        return err_nomem(err);
    size_t samples = (size_t)width * (size_t)channels;
    for (int y = 0; y < height; y++) {
        if (bits == 16)
            put_be16(row_at(&p, y), (const uint16_t *)pixels + (size_t)y * samples, samples);
        else
            memcpy(row_at(&p, y), (const uint8_t *)pixels + (size_t)y * samples, samples);
    }
    bool ok = encode_rows(&p, width, channels, bits, out);
    free(p.data);
    return ok ? GLINT_OK : err_nomem(err);
}

/* One row of the film into PNG samples: RGB, or RGBA with the coverage as
 * alpha (linear: no transfer function); 16-bit ones big-endian, through
 * tmp (width x 4 samples). */
static void quantize_row(const raster *r, int y, uint8_t *dst, uint16_t *tmp)
{
    size_t w = (size_t)r->width, at = (size_t)y * w;
    const float *rgb = r->rgb + at * 3;
    if (!r->alpha) {
        if (r->bits == 8) {
            image_quantize(rgb, w * 3, r->transfer, dst);
            return;
        }
        image_quantize16(rgb, w * 3, r->transfer, tmp);
        put_be16(dst, tmp, w * 3);
        return;
    }
    if (r->bits == 16) {
        for (size_t x = 0; x < w; x++) {
            image_quantize16(rgb + x * 3, 3, r->transfer, tmp + x * 4);
            image_quantize16(r->alpha + at + x, 1, GLINT_TRANSFER_NONE, tmp + x * 4 + 3);
        }
        put_be16(dst, tmp, w * 4);
        return;
    }
    uint8_t px[4];
    for (size_t x = 0; x < w; x++) {
        image_quantize(rgb + x * 3, 3, r->transfer, px);
        image_quantize(r->alpha + at + x, 1, GLINT_TRANSFER_NONE, px + 3);
        memcpy(dst + x * 4, px, 4);
    }
}

glint_rc png_encode(const raster *r, bytebuf *out, glint_error *err)
{
    int ch = r->alpha ? 4 : 3;
    png_rows p;
    uint16_t *tmp = malloc((size_t)r->width * 4 * sizeof *tmp);
    if (!tmp || !rows_alloc(&p, r->width, r->height, ch, r->bits)) {
        free(tmp);
        return err_nomem(err);
    }
    for (int y = 0; y < r->height; y++)
        quantize_row(r, y, row_at(&p, y), tmp);
    bool ok = encode_rows(&p, r->width, ch, r->bits, out);
    free(p.data);
    free(tmp);
    return ok ? GLINT_OK : err_nomem(err);
}
