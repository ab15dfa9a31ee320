/* png: PNG read through libspng, written by a small streaming encoder.
 *
 * The writer filters every row with one fixed filter and compresses with
 * ISA-L's igzip at level 1, which is several times faster than zlib at a
 * size close to libpng's defaults on rendered images (bench/pngbench.c
 * measures the candidates: libpng, libspng, libdeflate, ISA-L, each filter).
 * PNG: ISO/IEC 15948:2004 (chunks, filters section 9, CRC annex D). */
#include <stdlib.h>
#include <string.h>

#include <isa-l/crc.h>
#include <isa-l/igzip_lib.h>
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
    put_be32(dst, crc32_gzip_refl(0, type_and_data, n));
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

/* Feeds n bytes to the compressor, appending what comes out to out; with
 * last set, runs until the stream is closed. */
static bool deflate_feed(struct isal_zstream *z, bytebuf *out, const uint8_t *in, size_t n,
                         bool last)
{
    z->next_in = (uint8_t *)in;
    z->avail_in = (uint32_t)n;
    z->end_of_stream = last;
    z->flush = NO_FLUSH;
    for (;;) {
        if (out->cap - out->len < (1u << 16) &&
            !bytes_reserve(out, out->cap > (1u << 20) ? out->cap : (1u << 20)))
            return false;
        size_t room = out->cap - out->len;
        z->next_out = out->data + out->len;
        z->avail_out = room > UINT32_MAX ? UINT32_MAX : (uint32_t)room;
        uint32_t before = z->avail_out;
        if (isal_deflate(z) != COMP_OK)
            return false;
        out->len += before - z->avail_out;
        if (last ? z->internal_state.state == ZSTATE_END : z->avail_in == 0)
            return true;
    }
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

/* Up filter (section 9.2, type 2): each byte minus the one above it. It
 * compresses flat and vertically smooth areas to almost nothing and costs
 * one vector subtraction per 16 bytes. Row 0 is written unfiltered. */
static void filter_row(uint8_t *dst, const uint8_t *row, const uint8_t *above, size_t n)
{
    if (!above) {
        dst[0] = 0;
        memcpy(dst + 1, row, n);
        return;
    }
    dst[0] = 2;
    for (size_t i = 0; i < n; i++)
        dst[i + 1] = (uint8_t)(row[i] - above[i]);
}

/* 16-bit samples go big-endian. */
static void to_big_endian(uint8_t *dst, const uint16_t *src, size_t count)
{
    for (size_t i = 0; i < count; i++) {
        dst[2 * i] = (uint8_t)(src[i] >> 8);
        dst[2 * i + 1] = (uint8_t)src[i];
    }
}

typedef struct png_rows {
    struct isal_zstream z;
    uint8_t *level_buf, *batch, *be[2];
} png_rows;

static bool compress_rows(png_rows *s, bytebuf *out, int width, int height, int channels, int bits,
                          const void *pixels)
{
    size_t samples = (size_t)width * (size_t)channels;
    size_t rb = samples * (size_t)(bits / 8);
    size_t batch_cap = rb + 1 > (1u << 18) ? rb + 1 : (1u << 18);
    s->batch = malloc(batch_cap);
    s->level_buf = malloc(ISAL_DEF_LVL1_DEFAULT);
    if (bits == 16) {
        s->be[0] = malloc(rb);
        s->be[1] = malloc(rb);
    }
    if (!s->batch || !s->level_buf || (bits == 16 && (!s->be[0] || !s->be[1])))
        return false;
    isal_deflate_init(&s->z);
    s->z.level = 1;
    s->z.level_buf = s->level_buf;
    s->z.level_buf_size = ISAL_DEF_LVL1_DEFAULT;
    s->z.gzip_flag = IGZIP_ZLIB;
    size_t fill = 0;
    const uint8_t *above = NULL;
    for (int y = 0; y < height; y++) {
        const uint8_t *row;
        if (bits == 16) {
            uint8_t *be = s->be[y & 1];
            to_big_endian(be, (const uint16_t *)pixels + (size_t)y * samples, samples);
            row = be;
        } else {
            row = (const uint8_t *)pixels + (size_t)y * rb;
        }
        if (fill + rb + 1 > batch_cap) {
            if (!deflate_feed(&s->z, out, s->batch, fill, false))
                return false;
            fill = 0;
        }
        filter_row(s->batch + fill, row, above, rb);
        fill += rb + 1;
        above = row;
    }
    return deflate_feed(&s->z, out, s->batch, fill, true);
}

glint_rc png_encode_pixels(int width, int height, int channels, int bits, const void *pixels,
                           bytebuf *out, glint_error *err)
{
    static const uint8_t color_type[5] = {0, 0, 4, 2, 6}; /* grey, grey+alpha, RGB, RGBA */
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || (bits != 8 && bits != 16))
        return err_set(err, GLINT_ERR_INPUT, "PNG: cannot write %dx%d, %d channels, %d bits",
                       width, height, channels, bits);
    uint8_t ihdr[13];
    put_be32(ihdr, (uint32_t)width);
    put_be32(ihdr + 4, (uint32_t)height);
    ihdr[8] = (uint8_t)bits;
    ihdr[9] = color_type[channels];
    ihdr[10] = ihdr[11] = ihdr[12] = 0; /* deflate, adaptive filtering, no interlace */
    png_rows s = {0};
    bool ok = bytes_append(out, "\x89PNG\r\n\x1a\n", 8) && put_chunk(out, "IHDR", ihdr, 13);
    size_t start = out->len;
    ok = ok && compress_rows(&s, out, width, height, channels, bits, pixels) &&
         wrap_idat(out, start) && put_chunk(out, "IEND", NULL, 0);
    free(s.batch);
    free(s.level_buf);
    free(s.be[0]);
    free(s.be[1]);
    return ok ? GLINT_OK : err_nomem(err);
}

glint_rc png_encode(const raster *r, bytebuf *out, glint_error *err)
{
    int ch = r->alpha ? 4 : 3;
    size_t n = (size_t)r->width * (size_t)r->height;
    size_t bps = (size_t)r->bits / 8;
    void *px = malloc(n * (size_t)ch * bps);
    if (!px)
        return err_nomem(err);
    if (r->bits == 16)
        image_quantize16(r->rgb, n * 3, r->transfer, px);
    else
        image_quantize(r->rgb, n * 3, r->transfer, px);
    if (r->alpha) {
        /* spread RGB to RGBA from the end backwards, then fill in alpha
         * (linear coverage: no transfer function) */
        for (size_t i = n; i-- > 0;)
            for (int c = 2; c >= 0; c--) {
                if (bps == 2)
                    ((uint16_t *)px)[i * 4 + (size_t)c] = ((uint16_t *)px)[i * 3 + (size_t)c];
                else
                    ((uint8_t *)px)[i * 4 + (size_t)c] = ((uint8_t *)px)[i * 3 + (size_t)c];
            }
        for (size_t i = 0; i < n; i++) {
            if (bps == 2)
                image_quantize16(r->alpha + i, 1, GLINT_TRANSFER_NONE, (uint16_t *)px + i * 4 + 3);
            else
                image_quantize(r->alpha + i, 1, GLINT_TRANSFER_NONE, (uint8_t *)px + i * 4 + 3);
        }
    }
    glint_rc rc = png_encode_pixels(r->width, r->height, ch, r->bits, px, out, err);
    free(px);
    return rc;
}
