/* Reading PNG files (src/io/png.c): the common forms (8-bit grey, grey and
 * alpha, RGB, RGBA, not interlaced) go through glint's own reader
 * (png_decode_common, which each test checks took the file or left it),
 * the rest through libspng. Files are made here byte by byte (each row with a
 * chosen filter, the zlib stream cut into several IDAT chunks, ancillary
 * chunks around them), so each filter and chunk layout is known to be in
 * the file; the pixels must be the source's, as RGB, and the ones libspng
 * reads from the same bytes. Files the own reader leaves to libspng (a
 * palette, an unknown critical chunk) read as libspng reads them,
 * and damaged ones are errors naming the file. */
#include <criterion/criterion.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include <libdeflate.h>
#include <spng.h>

#include "io/codec.h"
#include "io/image.h"

/* The largest block asked for (tests/test_alloc.c's allocation wrappers). */
extern atomic_size_t alloc_largest;

typedef struct png_bytes {
    uint8_t *p;
    size_t n, cap;
} png_bytes;

static void put(png_bytes *b, const void *data, size_t n)
{
    if (b->n + n > b->cap) {
        b->cap = (b->n + n) * 2;
        b->p = realloc(b->p, b->cap);
        cr_assert_not_null(b->p);
    }
    memcpy(b->p + b->n, data, n);
    b->n += n;
}

static void store32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (24 - 8 * i));
}

static void put32(png_bytes *b, uint32_t v)
{
    uint8_t x[4];
    store32(x, v);
    put(b, x, 4);
}

/* The CRC of the chunk at byte `at` of the file made right again, after
 * its type or data were changed. */
static void refresh_crc(png_bytes *b, size_t at)
{
    const uint8_t *p = b->p + at;
    uint32_t len = (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
    store32(b->p + at + 8 + len, (uint32_t)libdeflate_crc32(0, p + 4, (size_t)len + 4));
}

/* The first n bytes of the file read as an image: an input error whose
 * message starts with "name: ", and no pixels. */
static void expect_load_error(const png_bytes *b, size_t n, const char *name)
{
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load_memory(b->p, n, name, &img, &err), GLINT_ERR_INPUT, "%s", name);
    cr_assert_eq(strncmp(err.msg, name, strlen(name)), 0, "%s", err.msg);
    cr_assert_eq(strncmp(err.msg + strlen(name), ": ", 2), 0, "%s", err.msg);
    cr_assert_null(img.rgb);
}

static void chunk(png_bytes *b, const char *type, const void *data, uint32_t n)
{
    put32(b, n);
    size_t at = b->n;
    put(b, type, 4);
    put(b, data, n);
    put32(b, (uint32_t)libdeflate_crc32(0, b->p + at, (size_t)n + 4));
}

static int paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* Row y of px (w pixels of ch bytes) filtered with f, after its filter
 * byte, into out. */
static void filter_row(const uint8_t *px, int w, int ch, int y, int f, uint8_t *out)
{
    size_t stride = (size_t)w * (size_t)ch;
    const uint8_t *row = px + (size_t)y * stride, *up = y ? row - stride : NULL;
    out[0] = (uint8_t)f;
    for (size_t i = 0; i < stride; i++) {
        int a = i >= (size_t)ch ? row[i - (size_t)ch] : 0, b = up ? up[i] : 0;
        int c = up && i >= (size_t)ch ? up[i - (size_t)ch] : 0;
        int pred = f == 1 ? a : f == 2 ? b : f == 3 ? (a + b) / 2 : f == 4 ? paeth(a, b, c) : 0;
        out[1 + i] = (uint8_t)(row[i] - pred);
    }
}

/* A PNG of px: colour type `type` (ch bytes a pixel), row y filtered with
 * filters[y % nf], the zlib stream (window bits `cinfo` + 8 in its header)
 * cut into IDAT chunks of at most `piece` bytes, a tEXt chunk before them
 * and another after, and `extra` (a chunk type, or NULL) before the first. */
static png_bytes make_png(const uint8_t *px, int w, int h, int type, int ch, const int *filters,
                          int nf, size_t piece, int cinfo, const char *extra)
{
    size_t stride = (size_t)w * (size_t)ch, raw = (stride + 1) * (size_t)h;
    uint8_t *rows = malloc(raw);
    cr_assert_not_null(rows);
    for (int y = 0; y < h; y++)
        filter_row(px, w, ch, y, filters[y % nf], rows + (size_t)y * (stride + 1));
    struct libdeflate_compressor *c = libdeflate_alloc_compressor(6);
    size_t zcap = libdeflate_zlib_compress_bound(c, raw);
    uint8_t *z = malloc(zcap);
    size_t zn = libdeflate_zlib_compress(c, rows, raw, z, zcap);
    cr_assert_gt(zn, 2);
    libdeflate_free_compressor(c);
    if (cinfo != 7) { /* a smaller window, its header check bits made right again */
        z[0] = (uint8_t)(cinfo << 4 | 8);
        z[1] = (uint8_t)(z[1] & 0xe0);
        z[1] = (uint8_t)(z[1] + 31 - (z[0] * 256 + z[1]) % 31);
    }
    png_bytes b = {0};
    put(&b, "\x89PNG\r\n\x1a\n", 8);
    uint8_t ihdr[13] = {0};
    store32(ihdr, (uint32_t)w);
    store32(ihdr + 4, (uint32_t)h);
    ihdr[8] = 8;
    ihdr[9] = (uint8_t)type;
    chunk(&b, "IHDR", ihdr, 13);
    chunk(&b, "tEXt", "Comment\0made here", 17);
    if (extra)
        chunk(&b, extra, "\0\0\0\xff\xff\xff", 6);
    for (size_t at = 0; at < zn; at += piece)
        chunk(&b, "IDAT", z + at, (uint32_t)(zn - at < piece ? zn - at : piece));
    chunk(&b, "tEXt", "Comment\0after", 13);
    chunk(&b, "IEND", "", 0);
    free(rows);
    free(z);
    return b;
}

/* Pixels of ch bytes with a little of everything: smooth runs, steps and
 * noise, so that every filter's arithmetic wraps somewhere. */
static uint8_t *test_pixels(int w, int h, int ch)
{
    uint8_t *px = malloc((size_t)w * (size_t)h * (size_t)ch);
    cr_assert_not_null(px);
    uint32_t s = 12345;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < ch; c++) {
                s = s * 1103515245u + 12345u;
                int v = (x * 7 + y * 13 + c * 50) + ((x / 5 + y / 3) % 2) * 120 + (int)(s >> 28);
                px[((size_t)y * (size_t)w + (size_t)x) * (size_t)ch + (size_t)c] = (uint8_t)v;
            }
    return px;
}

/* The RGB pixels of px as glint reads them: grey spread to three
 * channels, alpha dropped. */
static void expect_rgb(const image *img, const uint8_t *px, int w, int h, int ch)
{
    cr_assert_eq(img->width, w);
    cr_assert_eq(img->height, h);
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
        for (int c = 0; c < 3; c++) {
            uint8_t want = px[i * (size_t)ch + (size_t)(ch < 3 ? 0 : c)];
            cr_assert_eq(img->rgb[i * 3 + (size_t)c], want, "pixel %zu channel %d: %d, want %d",
                         i, c, img->rgb[i * 3 + (size_t)c], want);
        }
}

/* libspng's RGB pixels of the same bytes. */
static void expect_as_spng(const image *img, const png_bytes *b)
{
    spng_ctx *ctx = spng_ctx_new(0);
    cr_assert_eq(spng_set_png_buffer(ctx, b->p, b->n), 0);
    size_t len;
    cr_assert_eq(spng_decoded_image_size(ctx, SPNG_FMT_RGB8, &len), 0);
    cr_assert_eq(len, (size_t)img->width * (size_t)img->height * 3);
    uint8_t *px = malloc(len);
    cr_assert_eq(spng_decode_image(ctx, px, len, SPNG_FMT_RGB8, 0), 0);
    cr_assert_eq(memcmp(px, img->rgb, len), 0, "the pixels differ from libspng's");
    free(px);
    spng_ctx_free(ctx);
}

static const int types[4] = {0, 4, 2, 6}; /* grey, grey + alpha, RGB, RGBA: 1 to 4 bytes */

Test(png_read, every_filter_of_every_common_form_reads_exactly)
{
    const int mixed[5] = {4, 0, 3, 1, 2};
    for (int ch = 1; ch <= 4; ch++)
        for (int f = 0; f <= 5; f++) /* 5: the five in turn */
            for (int w = 1; w <= 41; w += 20) {
                int h = 9;
                uint8_t *px = test_pixels(w, h, ch);
                int one = f;
                png_bytes b = make_png(px, w, h, types[ch - 1], ch, f == 5 ? mixed : &one,
                                       f == 5 ? 5 : 1, f == 5 ? 37 : 1 << 20, 7, NULL);
                image img = {0}, own = {0};
                glint_error err = {0};
                cr_assert_eq(image_load_memory(b.p, b.n, "t.png", &img, &err), GLINT_OK, "%s",
                             err.msg);
                expect_rgb(&img, px, w, h, ch);
                expect_as_spng(&img, &b);
                cr_assert(png_decode_common(b.p, b.n, &own), "own reader declined it");
                expect_rgb(&own, px, w, h, ch);
                image_free(&own);
                image_free(&img);
                free(b.p);
                free(px);
            }
}

Test(png_read, files_left_to_libspng_read_the_same)
{
    int w = 23, h = 11, up = 2;
    uint8_t *px = test_pixels(w, h, 3);
    /* an unknown critical chunk is an error libspng reports */
    png_bytes b = make_png(px, w, h, 2, 3, &up, 1, 1000, 7, "ABCD");
    image img = {0};
    glint_error err = {0};
    cr_assert_not(png_decode_common(b.p, b.n, &img));
    expect_load_error(&b, b.n, "odd.png");
    free(b.p);
    /* the zlib header: a 512-byte window named, the stream referring back
     * 691 bytes (each row repeats the one above), read as zlib reads it
     * (it holds a stream to its window only when built to); a preset
     * dictionary asked for, refused */
    int wide = 230, none = 0;
    uint8_t *rep = malloc((size_t)wide * 3 * 4);
    for (int i = 0; i < wide * 3 * 4; i++)
        rep[i] = (uint8_t)(i % (wide * 3) * 7 % 251);
    for (int dict = 0; dict <= 1; dict++) {
        b = make_png(rep, wide, 4, 2, 3, &none, 1, 1000, 1, NULL);
        if (dict) { /* FDICT set, the check bits made right, the CRC again */
            size_t idat = 8 + 25 + 12 + 17, z = idat + 8;
            b.p[z + 1] = (uint8_t)((b.p[z + 1] | 0x20) & 0xe0);
            b.p[z + 1] = (uint8_t)(b.p[z + 1] + 31 - (b.p[z] * 256 + b.p[z + 1]) % 31);
            refresh_crc(&b, idat);
        }
        glint_rc rc = image_load_memory(b.p, b.n, "window.png", &img, &err);
        spng_ctx *ctx = spng_ctx_new(0);
        spng_set_png_buffer(ctx, b.p, b.n);
        uint8_t out[230 * 4 * 3];
        int e = spng_decode_image(ctx, out, sizeof out, SPNG_FMT_RGB8, 0);
        spng_ctx_free(ctx);
        cr_assert_eq(e != 0, dict, "libspng: %d", e);
        if (dict) {
            expect_load_error(&b, b.n, "window.png");
        } else {
            cr_assert_eq(rc, GLINT_OK, "%s", err.msg);
            expect_rgb(&img, rep, wide, 4, 3);
            image_free(&img);
        }
        free(b.p);
    }
    free(rep);
    /* a palette: colour type 3, two entries, every pixel an index */
    uint8_t idx[23 * 11];
    for (int i = 0; i < w * h; i++)
        idx[i] = (uint8_t)(i % 3 == 0);
    b = make_png(idx, w, h, 3, 1, &none, 1, 1000, 7, "PLTE");
    cr_assert_not(png_decode_common(b.p, b.n, &img));
    cr_assert_eq(image_load_memory(b.p, b.n, "pal.png", &img, &err), GLINT_OK, "%s", err.msg);
    for (int i = 0; i < w * h; i++)
        for (int c = 0; c < 3; c++)
            cr_assert_eq(img.rgb[i * 3 + c], i % 3 == 0 ? 255 : 0, "pixel %d", i);
    image_free(&img);
    free(b.p);
    free(px);
}

Test(png_read, damaged_files_are_errors_naming_the_file)
{
    int w = 31, h = 17, paeth_only = 4;
    uint8_t *px = test_pixels(w, h, 4);
    png_bytes good = make_png(px, w, h, 6, 4, &paeth_only, 1, 100, 7, NULL);
    const size_t first_idat = 8 + 25 + 12 + 17;
    /* a byte of the zlib stream changed, every CRC still right: the stream
     * no longer decodes, or its Adler-32 no longer matches */
    for (size_t k = 2; k < 60; k += 7) {
        png_bytes b = {0};
        put(&b, good.p, good.n);
        b.p[first_idat + 8 + k] ^= 0x5a;
        refresh_crc(&b, first_idat);
        image img = {0};
        glint_error err = {0};
        if (image_load_memory(b.p, b.n, "bad.png", &img, &err) == GLINT_OK) {
            /* a change the decoder cannot see must leave the pixels */
            expect_rgb(&img, px, w, h, 4);
            image_free(&img);
        } else {
            expect_load_error(&b, b.n, "bad.png");
        }
        free(b.p);
    }
    /* a CRC wrong, and the file cut in its pixel data */
    png_bytes b = {0};
    put(&b, good.p, good.n);
    b.p[first_idat + 8 + 50] ^= 1;
    expect_load_error(&b, b.n, "crc.png");
    expect_load_error(&good, good.n / 2, "cut.png");
    free(b.p);
    free(good.p);
    free(px);
}

/* A small file whose header claims far more pixels than its stream can
 * inflate to (2^28 RGBA pixels from a few dozen bytes) is declined before
 * memory is asked for, and is an error; so is one with more ancillary
 * chunks than the own reader takes, which libspng then reads. */
Test(png_read, claims_beyond_the_data_and_many_chunks_go_to_libspng)
{
    uint8_t px[4] = {1, 2, 3, 4};
    int none = 0;
    png_bytes b = make_png(px, 1, 1, 6, 4, &none, 1, 1000, 7, NULL);
    store32(b.p + 16, 16384); /* IHDR: 16384 x 16384, the CRC made right */
    store32(b.p + 20, 16384);
    refresh_crc(&b, 8);
    image img = {0};
    glint_error err = {0};
    atomic_store(&alloc_largest, 0);
    cr_assert_not(png_decode_common(b.p, b.n, &img));
    cr_assert_lt(atomic_load(&alloc_largest), (size_t)1 << 20, "asked for %zu bytes",
                 atomic_load(&alloc_largest));
    expect_load_error(&b, b.n, "claim.png");
    free(b.p);
    /* 65 tEXt chunks before the pixels */
    b = make_png(px, 1, 1, 6, 4, &none, 1, 1000, 7, NULL);
    png_bytes many = {0};
    put(&many, b.p, 33);
    for (int i = 0; i < 65; i++)
        chunk(&many, "tEXt", "Comment\0x", 9);
    put(&many, b.p + 33, b.n - 33);
    cr_assert(png_decode_common(b.p, b.n, &img));
    image_free(&img);
    cr_assert_not(png_decode_common(many.p, many.n, &img));
    cr_assert_eq(image_load_memory(many.p, many.n, "many.png", &img, &err), GLINT_OK, "%s",
                 err.msg);
    expect_rgb(&img, px, 1, 1, 4);
    image_free(&img);
    free(many.p);
    free(b.p);
}
