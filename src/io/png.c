/* png: PNG read, the common forms by a reader of its own with libdeflate
 * and the rest through libspng (the writer is png_write.c), which is
 * opened at the first such file (core/dynlib.h), not linked. */
#include <stdlib.h>
#include <string.h>

#include <libdeflate.h>
#include <spng.h>

#include "codec.h"
#include "core/array.h"
#include "core/dynlib.h"
#include "core/error.h"
#include "image.h"

#define SPNG_FUNCTIONS(X, t)                                                                   \
    X(t, spng_ctx_new) X(t, spng_ctx_free) X(t, spng_set_chunk_limits)                         \
    X(t, spng_set_png_buffer) X(t, spng_get_ihdr) X(t, spng_decoded_image_size)                \
    X(t, spng_decode_image) X(t, spng_strerror)

static DYNLIB_STRUCT(SPNG_FUNCTIONS) spng_fn;
static dynlib spng_lib = DYNLIB(GLINT_SONAME_SPNG, SPNG_FUNCTIONS, spng_fn);

#define spng_ctx_new (spng_fn.spng_ctx_new)
#define spng_ctx_free (spng_fn.spng_ctx_free)
#define spng_set_chunk_limits (spng_fn.spng_set_chunk_limits)
#define spng_set_png_buffer (spng_fn.spng_set_png_buffer)
#define spng_get_ihdr (spng_fn.spng_get_ihdr)
#define spng_decoded_image_size (spng_fn.spng_decoded_image_size)
#define spng_decode_image (spng_fn.spng_decode_image)
#define spng_strerror (spng_fn.spng_strerror)

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

/* ---- the common PNGs, read without libspng ---------------------------------
 * 8-bit grey, grey and alpha, RGB or RGBA, not interlaced: the forms
 * image editors and glint itself write. The chunks are walked here, each
 * critical one's CRC checked, the IDAT ones' zlib stream inflated by
 * libdeflate (which checks its Adler-32) to exactly the bytes the header
 * implies, and the rows unfiltered. Anything else, an unusual or a
 * damaged file included, is left to libspng, which reads it or says what
 * is wrong: this reader never reports an error, and gives the pixels
 * libspng gives (tests/test_png_read.c compares them). Ancillary chunks
 * are skipped unread; a file with more of them than QUICK_ANCILLARY_MAX
 * or QUICK_ANCILLARY_BYTES goes to libspng, whose limits on them
 * (spng_set_chunk_limits below) then apply as before. libdeflate also
 * decodes a few damaged streams zlib refuses (a Huffman code left
 * incomplete by a flipped bit, or declaring more codes than zlib allows),
 * where the bytes decoded, their Adler-32 and every CRC are still right.
 * The built-in scene's 1024x512 globe loads in 2.2 ms here against 5.6
 * through libspng, most of which was zlib's inflate. */

#define QUICK_ANCILLARY_MAX 64
#define QUICK_ANCILLARY_BYTES ((size_t)1 << 20)
/* deflate expands a byte at most about 1032 times (a 258-byte match in 2
 * bits) */
#define DEFLATE_MAX_RATIO 1032

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* The chunk at p holding len data bytes has its CRC. */
static bool chunk_crc_ok(const uint8_t *p, uint32_t len)
{
    return (uint32_t)libdeflate_crc32(0, p + 4, (size_t)len + 4) == be32(p + 8 + len);
}

typedef struct quick_png {
    uint32_t width, height;
    int channels;
    const uint8_t *z; /* the zlib stream: in the file, or in own */
    size_t zlen;
    uint8_t *own;
} quick_png;

/* The header, and the IDAT chunks' data in one piece: false for a file
 * this reader leaves to libspng. */
static bool quick_chunks(const uint8_t *d, size_t size, quick_png *q)
{
    static const int channels[7] = {1, 0, 3, 0, 2, 0, 4};
    if (size < 8 + 25 || be32(d + 8) != 13 || memcmp(d + 12, "IHDR", 4) || !chunk_crc_ok(d + 8, 13))
        return false;
    const uint8_t *h = d + 16;
    q->width = be32(h), q->height = be32(h + 4);
    if (h[8] != 8 || h[9] > 6 || !channels[h[9]] || h[10] || h[11] || h[12])
        return false; /* not 8 bits, a palette, or interlaced */
    q->channels = channels[h[9]];
    size_t at = 8 + 25, first = 0, total = 0, runs = 0, extras = 0, extra_bytes = 0;
    bool in_idat = false;
    for (;;) {
        if (size - at < 12 || be32(d + at) > size - at - 12)
            return false; /* no IEND: truncated */
        uint32_t len = be32(d + at);
        const uint8_t *type = d + at + 4;
        bool idat = !memcmp(type, "IDAT", 4);
        if (idat && !in_idat) {
            runs++;
            first = at;
        }
        in_idat = idat;
        if (!memcmp(type, "IEND", 4))
            break;
        for (int i = 0; i < 4; i++)
            if (!((type[i] | 0x20) >= 'a' && (type[i] | 0x20) <= 'z'))
                return false;
        if (idat && !chunk_crc_ok(d + at, len))
            return false;
        if (idat)
            total += len;
        else if (!(type[0] & 0x20)) /* another critical chunk (PLTE, a second IHDR) */
            return false;
        else if (++extras > QUICK_ANCILLARY_MAX || (extra_bytes += len) > QUICK_ANCILLARY_BYTES)
            return false;
        at += 12 + (size_t)len;
    }
    if (runs != 1 || !chunk_crc_ok(d + at, be32(d + at)))
        return false;
    q->zlen = total;
    if (be32(d + first) == total) { /* one IDAT chunk */
        q->z = d + first + 8;
        return true;
    }
    if (!(q->own = malloc(total ? total : 1)))
        return false;
    size_t n = 0;
    for (at = first; !memcmp(d + at + 4, "IDAT", 4); at += 12 + (size_t)be32(d + at)) {
        memcpy(q->own + n, d + at + 8, be32(d + at));
        n += be32(d + at);
    }
    q->z = q->own;
    return true;
}

static inline uint8_t paeth(int a, int b, int c)
{
    int pa = abs(b - c), pb = abs(a - c), pc = abs(a + b - 2 * c);
    return (uint8_t)(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

/* A row of n bytes, bpp a pixel, filtered with f, from in to out against
 * the unfiltered row above (NULL for the first): out may be in itself or
 * lie before it (each byte is read before any byte after it is written).
 * False for an unknown filter. */
static bool unfilter(uint8_t *out, const uint8_t *in, const uint8_t *prev, size_t n, size_t bpp,
                     int f)
{
    size_t i = 0;
    switch (f) {
    case 0:
        memmove(out, in, n);
        return true;
    case 1:
        for (; i < bpp && i < n; i++)
            out[i] = in[i];
        for (; i < n; i++)
            out[i] = (uint8_t)(in[i] + out[i - bpp]);
        return true;
    case 2:
        if (!prev)
            memmove(out, in, n);
        else
            for (; i < n; i++)
                out[i] = (uint8_t)(in[i] + prev[i]);
        return true;
    case 3:
        for (; i < bpp && i < n; i++)
            out[i] = (uint8_t)(in[i] + (prev ? prev[i] >> 1 : 0));
        for (; i < n; i++)
            out[i] = (uint8_t)(in[i] + ((out[i - bpp] + (prev ? prev[i] : 0)) >> 1));
        return true;
    case 4:
        if (!prev)
            return unfilter(out, in, NULL, n, bpp, 1); /* Paeth of a, 0, 0 is a */
        for (; i < bpp && i < n; i++)
            out[i] = (uint8_t)(in[i] + prev[i]);
        for (; i < n; i++)
            out[i] = (uint8_t)(in[i] + paeth(out[i - bpp], prev[i], prev[i - bpp]));
        return true;
    default:
        return false;
    }
}

/* Pixel i of ch bytes at in + i * ch as RGB at out + i * 3 (grey spread,
 * alpha dropped), for n pixels in one block: forwards where a pixel
 * shrinks (4 bytes), backwards where it grows (1 or 2), so that every
 * byte is read before it is written over. */
static void to_rgb(uint8_t *p, size_t n, size_t ch)
{
    if (ch == 4)
        for (size_t i = 0; i < n; i++) {
            const uint8_t *q = p + i * 4;
            uint8_t r = q[0], g = q[1], b = q[2];
            p[i * 3] = r, p[i * 3 + 1] = g, p[i * 3 + 2] = b;
        }
    else
        for (size_t i = n; i-- > 0;) {
            uint8_t v = p[i * ch];
            p[i * 3] = p[i * 3 + 1] = p[i * 3 + 2] = v;
        }
}

/* The pixels as RGB, or NULL: inflated, unfiltered and made RGB in one
 * block, of at least the stream's bytes and the pixels' (from 1 MiB in
 * huge pages mapped at once, array_calloc_big: a fresh process's first
 * touches of 4 KiB pages took the globe 6.5 ms). */
static uint8_t *quick_pixels(const quick_png *q, struct libdeflate_decompressor *dc)
{
    size_t w = q->width, h = q->height, ch = (size_t)q->channels, stride = w * ch;
    size_t raw = (stride + 1) * h, rgb_bytes = w * h * 3;
    if (raw / DEFLATE_MAX_RATIO > q->zlen) /* more than the stream can hold: truncated */
        return NULL;
    uint8_t *p = array_calloc_big(raw > rgb_bytes ? raw : rgb_bytes);
    bool ok = p && libdeflate_zlib_decompress(dc, q->z, q->zlen, p, raw, NULL) ==
                       LIBDEFLATE_SUCCESS;
    for (size_t y = 0; ok && y < h; y++) /* rows packed in place, filter bytes dropped */
        ok = unfilter(p + y * stride, p + y * (stride + 1) + 1, y ? p + (y - 1) * stride : NULL,
                      stride, ch, p[y * (stride + 1)]);
    if (ok && ch != 3)
        to_rgb(p, w * h, ch);
    if (!ok) {
        free(p);
        return NULL;
    }
    return p;
}

bool png_decode_common(const uint8_t *data, size_t size, image *out)
{
    quick_png q = {0};
    glint_error ignored;
    if (!quick_chunks(data, size, &q) ||
        codec_check_size(q.width, q.height, "", &ignored) != GLINT_OK) {
        free(q.own);
        return false;
    }
    struct libdeflate_decompressor *dc = libdeflate_alloc_decompressor();
    uint8_t *rgb = dc ? quick_pixels(&q, dc) : NULL;
    libdeflate_free_decompressor(dc);
    free(q.own);
    if (!rgb)
        return false;
    *out = (image){.width = (int)q.width, .height = (int)q.height, .rgb = rgb};
    return true;
}

glint_rc png_decode(const uint8_t *data, size_t size, const char *name, image *out,
                    glint_error *err)
{
    if (png_decode_common(data, size, out))
        return GLINT_OK;
    const char *why;
    if (!dynlib_open(&spng_lib, &why))
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot read this PNG file (%s)", name, why);
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
    /* a byte of 1-bit pixels holds 8 of them */
    if (rc == GLINT_OK)
        rc = codec_check_data(ihdr.width, ihdr.height, size, DEFLATE_MAX_RATIO * 8, name, err);
    if (rc != GLINT_OK)
        goto out;
    size_t len;
    e = spng_decoded_image_size(ctx, SPNG_FMT_RGB8, &len);
    if (e) {
        rc = spng_failure(e, name, err);
        goto out;
    }
    px = array_calloc_big(len);
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
