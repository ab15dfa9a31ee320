#include "image_write.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "codec.h"
#include "core/error.h"
#include "file.h"

const char *image_format_name(glint_format f)
{
    switch (f) {
    case GLINT_FORMAT_AUTO:
        return "";
    case GLINT_FORMAT_PNG:
        return "png";
    case GLINT_FORMAT_PPM:
        return "ppm";
    case GLINT_FORMAT_JPEG:
        return "jpg";
    case GLINT_FORMAT_HDR:
        return "hdr";
    case GLINT_FORMAT_PFM:
        return "pfm";
    case GLINT_FORMAT_EXR:
        return "exr";
    }
    return "";
}

#define FORMAT_LIST ".png, .ppm, .jpg, .hdr, .pfm or .exr"

static bool format_known(glint_format f)
{
    return f >= GLINT_FORMAT_AUTO && f <= GLINT_FORMAT_EXR;
}

/* The format for name (an extension or a format name), or AUTO. */
static glint_format lookup(const char *name)
{
    if (name[0] == '.')
        name++;
    if (strcasecmp(name, "jpeg") == 0)
        return GLINT_FORMAT_JPEG;
    for (glint_format f = GLINT_FORMAT_PNG; f <= GLINT_FORMAT_EXR; f++)
        if (strcasecmp(name, image_format_name(f)) == 0)
            return f;
    return GLINT_FORMAT_AUTO;
}

glint_rc image_format_parse(const char *name, glint_format *out, glint_error *err)
{
    glint_format f = name ? lookup(name) : GLINT_FORMAT_AUTO;
    if (f == GLINT_FORMAT_AUTO)
        return err_set(err, GLINT_ERR_INPUT, "unknown image format '%s' (use png, ppm, jpg, hdr, "
                       "pfm or exr)", name ? name : "(null)");
    *out = f;
    return GLINT_OK;
}

static const char *extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash))
        return "";
    return dot;
}

/* Bits per channel: 0 is the format's default; the rest must fit it. */
static int bits_for(glint_format f, int bits)
{
    switch (f) {
    case GLINT_FORMAT_AUTO:
        return -1;
    case GLINT_FORMAT_PNG:
    case GLINT_FORMAT_PPM:
        return bits == 0 ? 8 : bits == 8 || bits == 16 ? bits : -1;
    case GLINT_FORMAT_JPEG:
        return bits == 0 || bits == 8 ? 8 : -1;
    case GLINT_FORMAT_HDR:
        return bits == 0 ? 32 : -1; /* RGBE: a shared exponent, no choice */
    case GLINT_FORMAT_PFM:
        return bits == 0 || bits == 32 ? 32 : -1;
    case GLINT_FORMAT_EXR:
        return bits == 0 ? 16 : bits == 16 || bits == 32 ? bits : -1;
    }
    return -1;
}

typedef struct resolved {
    glint_format format;
    int bits, quality;
} resolved;

static glint_rc resolve(const char *path, const glint_write_options *o, resolved *r,
                        glint_error *err)
{
    static const glint_write_options defaults = {0};
    if (!o)
        o = &defaults;
    const char *shown = strcmp(path, "-") == 0 ? "standard output" : path;
    if (!format_known(o->format))
        return err_set(err, GLINT_ERR_INPUT, "%s: unknown format code %d", shown, (int)o->format);
    if (o->transfer != GLINT_TRANSFER_NONE && o->transfer != GLINT_TRANSFER_SRGB)
        return err_set(err, GLINT_ERR_INPUT, "%s: unknown transfer function %d", shown,
                       (int)o->transfer);
    /* a folder is named as such before its name is judged as a format */
    struct stat st;
    bool exists = strcmp(path, "-") != 0 && stat(path, &st) == 0;
    if (exists && S_ISDIR(st.st_mode))
        return err_set(err, GLINT_ERR_INPUT, "%s: is a directory", shown);
    r->format = o->format;
    if (r->format == GLINT_FORMAT_AUTO)
        r->format = lookup(extension(path));
    /* standard output, devices and pipes have no extension to go by: PNG */
    if (r->format == GLINT_FORMAT_AUTO && (!strcmp(path, "-") || (exists && !S_ISREG(st.st_mode))))
        r->format = GLINT_FORMAT_PNG;
    if (r->format == GLINT_FORMAT_AUTO) {
        const char *ext = extension(path);
        return ext[0] ? err_set(err, GLINT_ERR_INPUT,
                                "%s: unknown output format '%s' (use " FORMAT_LIST ")", shown, ext)
                      : err_set(err, GLINT_ERR_INPUT,
                                "%s: no extension to choose the format by (use " FORMAT_LIST ")",
                                shown);
    }
    r->bits = bits_for(r->format, o->bits);
    if (r->bits < 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: %d bits per channel is not possible in .%s",
                       shown, o->bits, image_format_name(r->format));
    if (o->threads < 0 || o->threads > 1024)
        return err_set(err, GLINT_ERR_INPUT, "%s: threads must be 0 to 1024 (got %d)", shown,
                       o->threads);
    if (o->quality < 0 || o->quality > 100)
        return err_set(err, GLINT_ERR_INPUT, "%s: JPEG quality must be 1 to 100 (got %d)", shown,
                       o->quality);
    r->quality = o->quality ? o->quality : 90;
    return GLINT_OK;
}

glint_rc image_write_options_check(const char *path, const glint_write_options *opts,
                                   glint_error *err)
{
    resolved r;
    return resolve(path, opts, &r, err);
}

glint_rc image_write_check(const char *path, const glint_write_options *opts, glint_error *err)
{
    resolved r;
    glint_rc rc = resolve(path, opts, &r, err);
    const char *shown = strcmp(path, "-") == 0 ? "standard output" : path;
    if (rc == GLINT_OK && r.format == GLINT_FORMAT_JPEG)
        rc = jpeg_writer_ready(shown, err);
    if (rc == GLINT_OK && r.format == GLINT_FORMAT_EXR)
        rc = exr_writer_ready(shown, err);
    return rc != GLINT_OK ? rc : file_check_output(path, err);
}

static glint_rc encode_block(const raster *r, glint_format f, bytebuf *out, glint_error *err)
{
    switch (f) {
    case GLINT_FORMAT_AUTO:
    case GLINT_FORMAT_PNG: /* in pieces: encode */
        break;
    case GLINT_FORMAT_PPM:
        return pnm_encode(r, out, err);
    case GLINT_FORMAT_JPEG:
        return jpeg_encode(r, out, err);
    case GLINT_FORMAT_HDR:
        return rgbe_encode(r, out, err);
    case GLINT_FORMAT_PFM:
        return pfm_encode(r, out, err);
    case GLINT_FORMAT_EXR:
        return exr_encode(r, out, err);
    }
    return err_set(err, GLINT_ERR_INPUT, "no image format chosen");
}

/* The file's bytes: a PNG in pieces (codec.h), any other in one block. */
static glint_rc encode(const raster *r, glint_format f, bytelist *out, glint_error *err)
{
    if (f == GLINT_FORMAT_PNG)
        return png_encode(r, out, err);
    bytebuf b = {0};
    glint_rc rc = encode_block(r, f, &b, err);
    if (rc == GLINT_OK && !bytelist_of(out, &b))
        rc = err_nomem(err);
    bytes_free(&b);
    return rc;
}

/* The pieces as the file's content (file_write_pieces). */
static glint_rc write_list(const char *path, const bytelist *l, glint_error *err)
{
    struct iovec *iov = malloc(sizeof *iov * (size_t)(l->n ? l->n : 1));
    if (!iov)
        return err_nomem(err);
    for (int i = 0; i < l->n; i++)
        iov[i] = (struct iovec){(void *)bytelist_at(l, i), l->pieces[i].n};
    glint_rc rc = file_write_pieces(path, iov, l->n, err);
    free(iov);
    return rc;
}

glint_rc image_write_film(const char *path, int width, int height, const float *rgb,
                          const glint_write_options *opts, glint_error *err)
{
    resolved res;
    glint_rc rc = resolve(path, opts, &res, err);
    if (rc != GLINT_OK)
        return rc;
    raster r = {
        .width = width,
        .height = height,
        .rgb = rgb,
        .alpha = opts ? opts->alpha : NULL,
        .transfer = opts ? opts->transfer : GLINT_TRANSFER_NONE,
        .bits = res.bits,
        .quality = res.quality,
        .threads = opts ? opts->threads : 0,
        .name = strcmp(path, "-") == 0 ? "standard output" : path,
    };
    bytelist out = {0};
    rc = encode(&r, res.format, &out, err);
    if (rc == GLINT_OK)
        rc = write_list(path, &out, err);
    bytelist_free(&out);
    return rc;
}
