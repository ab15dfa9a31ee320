/* rgbe: Radiance HDR pictures (.hdr), linear floats stored as a shared
 * exponent and three 8-bit mantissas (Ward, "Real Pixels", Graphics Gems II,
 * 1991), scanlines run-length encoded per component as Radiance writes them
 * (color.c in the Radiance sources describes the layout; no code is taken).
 *
 * Read: the "#?" header lines up to a blank line (FORMAT must be RGBE when
 * given), the resolution line "-Y H +X W" (rows top to bottom; the other
 * seven orientations are refused), then H scanlines, each flat or in the
 * new run-length form. Decoded values are the bucket centres, (m + 0.5) 2^(e-136),
 * as Radiance's colr_color does, except that a zero mantissa stays exactly 0
 * (pure colours keep their zero channels). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "core/error.h"
#include "image.h"

/* ---- reading ------------------------------------------------------------ */

typedef struct cursor {
    const uint8_t *p, *end;
} cursor;

/* The next line without its '\n' (NULL at end of data). */
static const uint8_t *next_line(cursor *c, size_t *len)
{
    const uint8_t *nl = memchr(c->p, '\n', (size_t)(c->end - c->p));
    if (!nl)
        return NULL;
    const uint8_t *line = c->p;
    *len = (size_t)(nl - line);
    c->p = nl + 1;
    return line;
}

static glint_rc read_header(cursor *c, const char *name, long *w, long *h, glint_error *err)
{
    size_t len;
    const uint8_t *line;
    while ((line = next_line(c, &len)) != NULL && len > 0) {
        while (len > 0 && (line[len - 1] == '\r' || line[len - 1] == ' '))
            len--;
        static const char key[] = "FORMAT=", rgbe[] = "32-bit_rle_rgbe";
        size_t k = sizeof key - 1;
        if (len >= k && memcmp(line, key, k) == 0 &&
            !(len - k == sizeof rgbe - 1 && memcmp(line + k, rgbe, sizeof rgbe - 1) == 0))
            return err_set(err, GLINT_ERR_INPUT,
                           "%s: Radiance format '%.*s' is not supported (only RGBE)", name,
                           (int)(len - k > 40 ? 40 : len - k), (const char *)line + k);
    }
    if (!line || !(line = next_line(c, &len)))
        return codec_truncated(name, err);
    char res[64];
    if (len >= sizeof res)
        len = sizeof res - 1;
    memcpy(res, line, len);
    res[len] = '\0';
    char tail;
    if (sscanf(res, "-Y %ld +X %ld%c", h, w, &tail) != 2)
        return err_set(err, GLINT_ERR_INPUT,
                       "%s: Radiance resolution line '%s' is not supported (want -Y H +X W)",
                       name, res);
    if (*w <= 0 || *h <= 0)
        return codec_check_size(0, 0, name, err);
    return codec_check_size((uint64_t)*w, (uint64_t)*h, name, err);
}

/* One component of one new-style run-length scanline into dst[0], dst[4]...
 * Data that stops early leaves the cursor at its end (truncation). */
static bool read_component(cursor *c, uint8_t *dst, long width)
{
    long x = 0;
    while (x < width) {
        if (c->p >= c->end)
            return false;
        int code = *c->p++;
        if (code > 128) { /* a run */
            long n = code - 128;
            if (c->p >= c->end)
                return false;
            if (n > width - x)
                return false;
            uint8_t v = *c->p++;
            for (long i = 0; i < n; i++)
                dst[4 * (x + i)] = v;
            x += n;
        } else { /* code literal bytes; 0 is invalid */
            long n = code;
            if (n == 0 || n > width - x)
                return false;
            if (c->end - c->p < n) {
                c->p = c->end;
                return false;
            }
            for (long i = 0; i < n; i++)
                dst[4 * (x + i)] = c->p[i];
            c->p += n;
            x += n;
        }
    }
    return true;
}

/* One scanline of width RGBE quadruples into row; false on bad or short data
 * (*truncated tells which). */
static bool read_scanline(cursor *c, uint8_t *row, long width, bool *truncated)
{
    *truncated = false;
    bool rle = width >= 8 && width < 32768 && c->end - c->p >= 4 && c->p[0] == 2 &&
               c->p[1] == 2 && !(c->p[2] & 0x80) && ((long)c->p[2] << 8 | c->p[3]) == width;
    if (!rle) {
        size_t n = (size_t)width * 4;
        if ((size_t)(c->end - c->p) < n) {
            *truncated = true;
            return false;
        }
        memcpy(row, c->p, n);
        c->p += n;
        return true;
    }
    c->p += 4;
    for (int k = 0; k < 4; k++)
        if (!read_component(c, row + k, width)) {
            *truncated = c->p >= c->end;
            return false;
        }
    return true;
}

static float component(uint8_t m, uint8_t e)
{
    return e && m ? ((float)m + 0.5f) * ldexpf(1.0f, (int)e - 136) : 0.0f;
}

glint_rc rgbe_decode(const uint8_t *data, size_t size, const char *name, image *out,
                     glint_error *err)
{
    cursor c = {data, data + size};
    long w, h;
    glint_rc rc = read_header(&c, name, &w, &h, err);
    /* a 2-byte run covers at most 127 pixels of one of 4 components */
    if (rc == GLINT_OK)
        rc = codec_check_data((uint64_t)w, (uint64_t)h, (size_t)(c.end - c.p), 32, name, err);
    if (rc != GLINT_OK)
        return rc;
    float *px = malloc((size_t)w * (size_t)h * 3 * sizeof *px);
    uint8_t *row = malloc((size_t)w * 4);
    if (!px || !row) {
        free(px);
        free(row);
        return err_nomem(err);
    }
    for (long y = 0; y < h; y++) {
        bool truncated;
        if (!read_scanline(&c, row, w, &truncated)) {
            rc = truncated ? codec_truncated(name, err)
                           : err_set(err, GLINT_ERR_INPUT, "%s: broken Radiance scanline %ld",
                                     name, y);
            free(px);
            free(row);
            return rc;
        }
        float *dst = px + (size_t)y * (size_t)w * 3;
        for (long x = 0; x < w; x++) {
            const uint8_t *q = row + 4 * x;
            dst[3 * x] = component(q[0], q[3]);
            dst[3 * x + 1] = component(q[1], q[3]);
            dst[3 * x + 2] = component(q[2], q[3]);
        }
    }
    free(row);
    *out = (image){.width = (int)w, .height = (int)h, .linear = px};
    return GLINT_OK;
}

/* ---- writing ------------------------------------------------------------ */

/* Shared exponent of the largest component; the mantissas are truncated
 * as Radiance's setcolr does, so decoding to bucket centres is unbiased.
 * Negative and NaN values become 0. */
static void to_rgbe(const float *rgb, uint8_t q[4])
{
    float c[3];
    for (int k = 0; k < 3; k++)
        c[k] = rgb[k] > 0.0f ? rgb[k] : 0.0f;
    float v = fmaxf(c[0], fmaxf(c[1], c[2]));
    if (!(v >= 1e-32f)) {
        q[0] = q[1] = q[2] = q[3] = 0;
        return;
    }
    if (v > 1.7e38f) /* infinities clamp to the largest RGBE value */
        v = 1.7e38f;
    int e;
    float scale = frexpf(v, &e) * 256.0f / v;
    for (int k = 0; k < 3; k++) {
        float m = fminf(c[k], v) * scale;
        q[k] = (uint8_t)(m < 255.0f ? m : 255.0f);
    }
    q[3] = (uint8_t)(e + 128);
}

/* Runs of 4 or more equal bytes as run codes, the rest as literals. */
static bool write_component(bytebuf *out, const uint8_t *src, long width)
{
    long x = 0;
    while (x < width) {
        long run = 1;
        while (x + run < width && run < 127 && src[4 * (x + run)] == src[4 * x])
            run++;
        if (run >= 4) {
            uint8_t code[2] = {(uint8_t)(128 + run), src[4 * x]};
            if (!bytes_append(out, code, 2))
                return false;
            x += run;
            continue;
        }
        /* literals up to the next run of 4 */
        long n = 0;
        while (x + n < width && n < 128) {
            long r = 1;
            while (x + n + r < width && r < 4 && src[4 * (x + n + r)] == src[4 * (x + n)])
                r++;
            if (r >= 4)
                break;
            n++;
        }
        uint8_t *p = bytes_grow(out, 1 + (size_t)n);
        if (!p)
            return false;
        p[0] = (uint8_t)n;
        for (long i = 0; i < n; i++)
            p[1 + i] = src[4 * (x + i)];
        x += n;
    }
    return true;
}

glint_rc rgbe_encode(const raster *r, bytebuf *out, glint_error *err)
{
    long w = r->width, h = r->height;
    char header[128];
    int n = snprintf(header, sizeof header,
                     "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %ld +X %ld\n", h, w);
    uint8_t *row = malloc((size_t)w * 4);
    bool ok = row && bytes_append(out, header, (size_t)n);
    bool rle = w >= 8 && w < 32768;
    for (long y = 0; ok && y < h; y++) {
        const float *src = r->rgb + (size_t)y * (size_t)w * 3;
        for (long x = 0; x < w; x++)
            to_rgbe(src + 3 * x, row + 4 * x);
        if (!rle) {
            ok = bytes_append(out, row, (size_t)w * 4);
            continue;
        }
        uint8_t mark[4] = {2, 2, (uint8_t)(w >> 8), (uint8_t)w};
        ok = bytes_append(out, mark, 4);
        for (int k = 0; ok && k < 4; k++)
            ok = write_component(out, row + k, w);
    }
    free(row);
    return ok ? GLINT_OK : err_nomem(err);
}
