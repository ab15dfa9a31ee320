/* pnm: the Netpbm family's binary formats. PPM (P6) and PGM (P5) with 8-
 * or 16-bit samples (Netpbm's ppm(5), pgm(5)), read into 8-bit RGB and
 * written as PPM; PFM (PF colour, Pf grey), little- or big-endian floats,
 * rows stored bottom to top, read as linear floats and written from the film
 * unquantised (the format as Debevec's HDRShop and Netpbm's pfm(5) define it). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "core/error.h"
#include "image.h"

typedef struct cursor {
    const uint8_t *p, *end;
} cursor;

static bool space(uint8_t c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/* Skips white space and '#' comments, then reads a decimal number up to
 * limit. Returns 0 on success, 1 at end of data, -1 on a bad number. */
static int read_number(cursor *c, unsigned long limit, unsigned long *out)
{
    for (;;) {
        while (c->p < c->end && space(*c->p))
            c->p++;
        if (c->p < c->end && *c->p == '#') {
            while (c->p < c->end && *c->p != '\n')
                c->p++;
            continue;
        }
        break;
    }
    if (c->p >= c->end)
        return 1;
    unsigned long v = 0;
    const uint8_t *start = c->p;
    while (c->p < c->end && *c->p >= '0' && *c->p <= '9') {
        v = v * 10 + (unsigned long)(*c->p++ - '0');
        if (v > limit)
            return -1;
    }
    if (c->p == start)
        return -1;
    *out = v;
    return 0;
}

static glint_rc header_failure(int r, const char *name, const char *what, glint_error *err)
{
    if (r > 0)
        return codec_truncated(name, err);
    return err_set(err, GLINT_ERR_INPUT, "%s: bad %s in the header", name, what);
}

/* The single white-space byte that ends a Netpbm header. */
static glint_rc end_header(cursor *c, const char *name, glint_error *err)
{
    if (c->p >= c->end)
        return codec_truncated(name, err);
    if (!space(*c->p))
        return err_set(err, GLINT_ERR_INPUT, "%s: bad header end", name);
    c->p++;
    return GLINT_OK;
}

glint_rc pnm_decode(const uint8_t *data, size_t size, const char *name, image *out,
                    glint_error *err)
{
    cursor c = {data + 2, data + size};
    int channels = data[1] == '6' ? 3 : 1;
    unsigned long w, h, maxval;
    int r;
    if ((r = read_number(&c, 1ul << 30, &w)) != 0)
        return header_failure(r, name, "width", err);
    if ((r = read_number(&c, 1ul << 30, &h)) != 0)
        return header_failure(r, name, "height", err);
    glint_rc rc = codec_check_size(w, h, name, err);
    if (rc != GLINT_OK)
        return rc;
    if ((r = read_number(&c, 65535, &maxval)) != 0 || maxval == 0)
        return header_failure(r, name, "maximum value", err);
    if ((rc = end_header(&c, name, err)) != GLINT_OK)
        return rc;
    size_t bps = maxval > 255 ? 2 : 1, n = (size_t)w * (size_t)h;
    if ((size_t)(c.end - c.p) / bps / (size_t)channels < n)
        return codec_truncated(name, err);
    uint8_t *px = malloc(n * 3);
    if (!px)
        return err_nomem(err);
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            const uint8_t *s = c.p + (i * (size_t)channels + (size_t)(channels == 3 ? k : 0)) * bps;
            unsigned long v = bps == 2 ? (unsigned long)s[0] << 8 | s[1] : s[0];
            if (v > maxval)
                v = maxval;
            px[i * 3 + (size_t)k] = (uint8_t)((v * 255 + maxval / 2) / maxval);
        }
    *out = (image){.width = (int)w, .height = (int)h, .rgb = px};
    return GLINT_OK;
}

glint_rc pnm_encode(const raster *r, bytebuf *out, glint_error *err)
{
    size_t n = (size_t)r->width * (size_t)r->height * 3;
    char header[64];
    int len = snprintf(header, sizeof header, "P6\n%d %d\n%d\n", r->width, r->height,
                       r->bits == 16 ? 65535 : 255);
    if (!bytes_append(out, header, (size_t)len))
        return err_nomem(err);
    uint8_t *px = bytes_grow(out, n * (size_t)(r->bits / 8));
    if (!px)
        return err_nomem(err);
    if (r->bits != 16) {
        image_quantize(r->rgb, n, r->transfer, px);
        return GLINT_OK;
    }
    uint16_t *wide = malloc(n * sizeof *wide);
    if (!wide)
        return err_nomem(err);
    image_quantize16(r->rgb, n, r->transfer, wide);
    for (size_t i = 0; i < n; i++) { /* big-endian, as pgm(5) says */
        px[2 * i] = (uint8_t)(wide[i] >> 8);
        px[2 * i + 1] = (uint8_t)wide[i];
    }
    free(wide);
    return GLINT_OK;
}

/* ---- PFM ---------------------------------------------------------------- */

static float load_float(const uint8_t *s, bool little)
{
    uint32_t u = little ? (uint32_t)s[0] | (uint32_t)s[1] << 8 | (uint32_t)s[2] << 16 |
                              (uint32_t)s[3] << 24
                        : (uint32_t)s[3] | (uint32_t)s[2] << 8 | (uint32_t)s[1] << 16 |
                              (uint32_t)s[0] << 24;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* The scale line: a decimal number whose sign gives the byte order. */
static glint_rc read_scale(cursor *c, const char *name, bool *little, glint_error *err)
{
    while (c->p < c->end && space(*c->p))
        c->p++;
    char buf[32];
    size_t n = 0;
    while (c->p < c->end && !space(*c->p) && n < sizeof buf - 1)
        buf[n++] = (char)*c->p++;
    buf[n] = '\0';
    if (c->p >= c->end)
        return codec_truncated(name, err);
    char *end;
    double s = strtod(buf, &end);
    if (n == 0 || *end || !(s != 0.0) || !isfinite(s))
        return err_set(err, GLINT_ERR_INPUT, "%s: bad scale '%s' in the header", name, buf);
    *little = s < 0.0;
    return end_header(c, name, err);
}

glint_rc pfm_decode(const uint8_t *data, size_t size, const char *name, image *out,
                    glint_error *err)
{
    cursor c = {data + 2, data + size};
    int channels = data[1] == 'F' ? 3 : 1;
    unsigned long w, h;
    int r;
    if ((r = read_number(&c, 1ul << 30, &w)) != 0)
        return header_failure(r, name, "width", err);
    if ((r = read_number(&c, 1ul << 30, &h)) != 0)
        return header_failure(r, name, "height", err);
    glint_rc rc = codec_check_size(w, h, name, err);
    if (rc != GLINT_OK)
        return rc;
    bool little = true;
    if ((rc = read_scale(&c, name, &little, err)) != GLINT_OK)
        return rc;
    size_t n = (size_t)w * (size_t)h;
    if ((size_t)(c.end - c.p) / 4 / (size_t)channels < n)
        return codec_truncated(name, err);
    float *px = malloc(n * 3 * sizeof *px);
    if (!px)
        return err_nomem(err);
    for (size_t y = 0; y < h; y++) {
        const uint8_t *row = c.p + (h - 1 - y) * (size_t)w * (size_t)channels * 4;
        for (size_t x = 0; x < w; x++)
            for (int k = 0; k < 3; k++) {
                float v = load_float(row + (x * (size_t)channels + (channels == 3 ? (size_t)k : 0)) * 4,
                                     little);
                px[(y * w + x) * 3 + (size_t)k] = isfinite(v) ? v : 0.0f;
            }
    }
    *out = (image){.width = (int)w, .height = (int)h, .linear = px};
    return GLINT_OK;
}

glint_rc pfm_encode(const raster *r, bytebuf *out, glint_error *err)
{
    size_t w = (size_t)r->width, h = (size_t)r->height;
    char header[64];
    int len = snprintf(header, sizeof header, "PF\n%d %d\n-1.0\n", r->width, r->height);
    if (!bytes_append(out, header, (size_t)len))
        return err_nomem(err);
    uint8_t *p = bytes_grow(out, w * h * 12);
    if (!p)
        return err_nomem(err);
    for (size_t y = 0; y < h; y++) { /* bottom row first, little-endian */
        const float *src = r->rgb + (h - 1 - y) * w * 3;
        for (size_t i = 0; i < w * 3; i++, p += 4) {
            uint32_t u;
            memcpy(&u, &src[i], 4);
            p[0] = (uint8_t)u;
            p[1] = (uint8_t)(u >> 8);
            p[2] = (uint8_t)(u >> 16);
            p[3] = (uint8_t)(u >> 24);
        }
    }
    return GLINT_OK;
}
