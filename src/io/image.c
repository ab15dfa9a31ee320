/* image: reading files, telling formats apart by their first bytes, and the
 * 8-bit conversions shared by readers and writers. */
#include "image.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "codec.h"
#include "core/array.h"
#include "core/error.h"

/* ---- byte buffers and shared messages ----------------------------------- */

bool bytes_reserve(bytebuf *b, size_t n)
{
    if (n > SIZE_MAX / 4 - b->len)
        return false;
    if (b->len + n > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->len + n)
            cap *= 2;
        uint8_t *p = array_realloc(b->data, b->len, cap);
        if (!p)
            return false;
        b->data = p;
        b->cap = cap;
    }
    return true;
}

uint8_t *bytes_grow(bytebuf *b, size_t n)
{
    if (!bytes_reserve(b, n))
        return NULL;
    uint8_t *at = b->data + b->len;
    b->len += n;
    return at;
}

bool bytes_append(bytebuf *b, const void *data, size_t n)
{
    uint8_t *p = bytes_grow(b, n);
    if (!p)
        return false;
    if (n)
        memcpy(p, data, n);
    return true;
}

void bytes_free(bytebuf *b)
{
    free(b->data);
    *b = (bytebuf){0};
}

glint_rc codec_check_size(uint64_t width, uint64_t height, const char *name, glint_error *err)
{
    if (width == 0 || height == 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: image has no pixels (%llux%llu)", name,
                       (unsigned long long)width, (unsigned long long)height);
    if (width > IMAGE_MAX_PIXELS || height > IMAGE_MAX_PIXELS ||
        width * height > IMAGE_MAX_PIXELS)
        return err_set(err, GLINT_ERR_INPUT, "%s: image %llux%llu is too large (limit %u pixels)",
                       name, (unsigned long long)width, (unsigned long long)height,
                       IMAGE_MAX_PIXELS);
    return GLINT_OK;
}

glint_rc codec_check_data(uint64_t width, uint64_t height, size_t size, uint64_t per_byte,
                          const char *name, glint_error *err)
{
    if (width * height / per_byte > (uint64_t)size)
        return codec_truncated(name, err);
    return GLINT_OK;
}

glint_rc codec_truncated(const char *name, glint_error *err)
{
    return err_set(err, GLINT_ERR_INPUT, "%s: file is truncated", name);
}

/* ---- reading ------------------------------------------------------------ */

static bool starts(const uint8_t *d, size_t n, const char *magic, size_t m)
{
    return n >= m && memcmp(d, magic, m) == 0;
}

static bool is_space(uint8_t c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

/* TGA has no signature: a plausible header (no or a valid colour map, a
 * known image type, 8 to 32 bits per pixel) is as close as one gets. */
static bool looks_like_tga(const uint8_t *d, size_t n)
{
    if (n < 18 || d[1] > 1)
        return false;
    int type = d[2];
    bool known = type == 1 || type == 2 || type == 3 || type == 9 || type == 10 || type == 11;
    int bpp = d[16];
    return known && (bpp == 8 || bpp == 15 || bpp == 16 || bpp == 24 || bpp == 32);
}

glint_rc image_load_memory(const void *data, size_t size, const char *name, image *out,
                           glint_error *err)
{
    const uint8_t *d = data;
    if (size == 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: image file is empty", name);
    if (starts(d, size, "\x89PNG\r\n\x1a\n", 8))
        return png_decode(d, size, name, out, err);
    if (starts(d, size, "\xff\xd8\xff", 3))
        return jpeg_decode(d, size, name, out, err);
    if (starts(d, size, "#?", 2))
        return rgbe_decode(d, size, name, out, err);
    if (starts(d, size, "v/1\x01", 4))
        return exr_decode(d, size, name, out, err);
    if (size > 2 && d[0] == 'P' && (d[1] == 'F' || d[1] == 'f') && is_space(d[2]))
        return pfm_decode(d, size, name, out, err);
    if (size > 2 && d[0] == 'P' && (d[1] == '5' || d[1] == '6') && is_space(d[2]))
        return pnm_decode(d, size, name, out, err);
    if (starts(d, size, "BM", 2) || starts(d, size, "GIF8", 4) || looks_like_tga(d, size))
        return legacy_decode(d, size, name, out, err);
    return err_set(err, GLINT_ERR_INPUT,
                   "%s: not an image glint reads (PNG, JPEG, HDR, EXR, PFM, PPM, BMP, TGA, GIF)",
                   name);
}

/* Opens without blocking (a FIFO would wait for a writer for ever) and
 * refuses anything but a regular file before reading a byte. */
glint_rc image_load(const char *path, image *out, glint_error *err)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot open image: %s", path, strerror(errno));
    glint_rc rc = GLINT_OK;
    uint8_t *buf = NULL;
    struct stat st;
    if (fstat(fd, &st) != 0) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot read image: %s", path, strerror(errno));
        goto out;
    }
    if (S_ISDIR(st.st_mode)) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot open image: %s", path, strerror(EISDIR));
        goto out;
    }
    if (!S_ISREG(st.st_mode)) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: not a regular file", path);
        goto out;
    }
    if (st.st_size == 0 || st.st_size > IMAGE_MAX_FILE_BYTES) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: image file is %s", path,
                     st.st_size == 0 ? "empty" : "too large (over 1 GiB)");
        goto out;
    }
    size_t size = (size_t)st.st_size, got = 0;
    buf = malloc(size);
    if (!buf) {
        rc = err_nomem(err);
        goto out;
    }
    while (got < size) {
        ssize_t n = read(fd, buf + got, size - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot read image: %s", path, strerror(errno));
            goto out;
        }
        if (n == 0)
            break; /* the file shrank while we read: decode what is there */
        got += (size_t)n;
    }
    rc = image_load_memory(buf, got, path, out, err);
out:
    free(buf);
    close(fd);
    return rc;
}

void image_free(image *img)
{
    if (!img)
        return;
    free(img->rgb);
    free(img->linear);
    *img = (image){0};
}

/* ---- 8- and 16-bit conversions ------------------------------------------ */

static float srgb_encode(float x)
{
    return x <= 0.0031308f ? 12.92f * x : 1.055f * powf(x, 1.0f / 2.4f) - 0.055f;
}

static float srgb_decode(float x)
{
    return x <= 0.04045f ? x / 12.92f : powf((x + 0.055f) / 1.055f, 2.4f);
}

float image_display_value(float x, glint_transfer transfer)
{
    if (!(x > 0.0f))
        x = 0.0f;
    if (x > 1.0f)
        x = 1.0f;
    switch (transfer) {
    case GLINT_TRANSFER_NONE:
        break;
    case GLINT_TRANSFER_SRGB:
        x = srgb_encode(x);
        break;
    }
    return x;
}

/* The first values of src without a transfer function, sixteen at a time
 * with SSE2; returns how many it did. The same results as the loop in
 * image_quantize: max(x, 0) and min(x, 1) pick as its comparisons do (a
 * NaN becomes 0), and the conversion rounds to nearest, ties to even, as
 * lrintf does in the default rounding mode. */
static size_t quantize_linear_simd(const float *src, size_t count, uint8_t *dst)
{
    size_t i = 0;
#if defined(__SSE2__)
    const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), scale = _mm_set1_ps(255.0f);
    for (; i + 16 <= count; i += 16) {
        /* a page ahead: a PNG strip converts its rows between compressions
         * that leave the cache and the prefetchers cold (row 5's 1080p image
         * on a Xeon, Emerald Rapids: 24.7-24.9 -> 23.6-23.9 ms) */
        _mm_prefetch((const char *)((uintptr_t)(src + i) + 4096), _MM_HINT_T0);
        __m128i q[4];
        for (int k = 0; k < 4; k++) {
            __m128 x = _mm_min_ps(_mm_max_ps(_mm_loadu_ps(src + i + 4 * k), zero), one);
            q[k] = _mm_cvtps_epi32(_mm_mul_ps(x, scale));
        }
        __m128i lo = _mm_packs_epi32(q[0], q[1]), hi = _mm_packs_epi32(q[2], q[3]);
        _mm_storeu_si128((__m128i *)(void *)(dst + i), _mm_packus_epi16(lo, hi));
    }
#else
    (void)src, (void)count, (void)dst;
#endif
    return i;
}

void image_quantize(const float *src, size_t count, glint_transfer transfer, uint8_t *dst)
{
    switch (transfer) {
    case GLINT_TRANSFER_NONE:
        /* the common case */
        for (size_t i = quantize_linear_simd(src, count, dst); i < count; i++) {
            float x = src[i];
            x = x > 0.0f ? x : 0.0f;
            x = x < 1.0f ? x : 1.0f;
            dst[i] = (uint8_t)lrintf(x * 255.0f);
        }
        return;
    case GLINT_TRANSFER_SRGB:
        break;
    }
    for (size_t i = 0; i < count; i++)
        dst[i] = (uint8_t)lrintf(image_display_value(src[i], transfer) * 255.0f);
}

void image_quantize16(const float *src, size_t count, glint_transfer transfer, uint16_t *dst)
{
    for (size_t i = 0; i < count; i++)
        dst[i] = (uint16_t)lrintf(image_display_value(src[i], transfer) * 65535.0f);
}

void image_decode_table(glint_transfer transfer, float table[256])
{
    for (int i = 0; i < 256; i++) {
        float x = (float)i / 255.0f;
        switch (transfer) {
        case GLINT_TRANSFER_NONE:
            break;
        case GLINT_TRANSFER_SRGB:
            x = srgb_decode(x);
            break;
        }
        table[i] = x;
    }
}
