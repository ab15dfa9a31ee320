/* jpeg: JPEG read and written through libjpeg-turbo (libjpeg's API, as its
 * libjpeg.txt documents). libjpeg reports errors by calling error_exit,
 * which must not return: ours longjmps back to the call, the library's
 * documented way. A "premature end of data" warning, or a marker met where
 * coded data should go on (libjpeg would paper over both with grey), is an
 * error here ("file is truncated"). libjpeg is opened at the first JPEG
 * read or written (core/dynlib.h), not linked. */
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jerror.h>
#include <jpeglib.h>

#include "codec.h"
#include "core/array.h"
#include "core/dynlib.h"
#include "core/error.h"
#include "image.h"

#define JPEG_FUNCTIONS(X, t)                                                                   \
    X(t, jpeg_std_error) X(t, jpeg_CreateDecompress) X(t, jpeg_destroy_decompress)             \
    X(t, jpeg_mem_src) X(t, jpeg_read_header) X(t, jpeg_start_decompress)                      \
    X(t, jpeg_read_scanlines) X(t, jpeg_finish_decompress) X(t, jpeg_CreateCompress)           \
    X(t, jpeg_destroy_compress) X(t, jpeg_mem_dest) X(t, jpeg_set_defaults)                    \
    X(t, jpeg_set_quality) X(t, jpeg_start_compress) X(t, jpeg_write_scanlines)                \
    X(t, jpeg_finish_compress)

static DYNLIB_STRUCT(JPEG_FUNCTIONS) jpeg_fn;
static dynlib jpeg_lib = DYNLIB(GLINT_SONAME_JPEG, JPEG_FUNCTIONS, jpeg_fn);

#define jpeg_std_error (jpeg_fn.jpeg_std_error)
#define jpeg_CreateDecompress (jpeg_fn.jpeg_CreateDecompress)
#define jpeg_destroy_decompress (jpeg_fn.jpeg_destroy_decompress)
#define jpeg_mem_src (jpeg_fn.jpeg_mem_src)
#define jpeg_read_header (jpeg_fn.jpeg_read_header)
#define jpeg_start_decompress (jpeg_fn.jpeg_start_decompress)
#define jpeg_read_scanlines (jpeg_fn.jpeg_read_scanlines)
#define jpeg_finish_decompress (jpeg_fn.jpeg_finish_decompress)
#define jpeg_CreateCompress (jpeg_fn.jpeg_CreateCompress)
#define jpeg_destroy_compress (jpeg_fn.jpeg_destroy_compress)
#define jpeg_mem_dest (jpeg_fn.jpeg_mem_dest)
#define jpeg_set_defaults (jpeg_fn.jpeg_set_defaults)
#define jpeg_set_quality (jpeg_fn.jpeg_set_quality)
#define jpeg_start_compress (jpeg_fn.jpeg_start_compress)
#define jpeg_write_scanlines (jpeg_fn.jpeg_write_scanlines)
#define jpeg_finish_compress (jpeg_fn.jpeg_finish_compress)

typedef struct jpeg_failure {
    struct jpeg_error_mgr mgr;
    jmp_buf jump;
    bool truncated;
    char msg[JMSG_LENGTH_MAX];
    /* jpeg_mem_dest's buffer; libjpeg updates these as it grows it, and
     * they live here (in memory, address taken) to survive the longjmp */
    unsigned char *mem;
    unsigned long mem_size;
} jpeg_failure;

static void on_error(j_common_ptr cinfo)
{
    jpeg_failure *f = (jpeg_failure *)cinfo->err;
    (*cinfo->err->format_message)(cinfo, f->msg);
    longjmp(f->jump, 1);
}

/* Warnings (level -1) are collected, never printed; the end-of-data one
 * and a marker inside the coded data mean the file was cut short. */
static void on_message(j_common_ptr cinfo, int level)
{
    jpeg_failure *f = (jpeg_failure *)cinfo->err;
    if (level < 0 &&
        (cinfo->err->msg_code == JWRN_JPEG_EOF || cinfo->err->msg_code == JWRN_HIT_MARKER))
        f->truncated = true;
}

static void failure_init(jpeg_failure *f)
{
    jpeg_std_error(&f->mgr);
    f->mgr.error_exit = on_error;
    f->mgr.emit_message = on_message;
    f->truncated = false;
    f->msg[0] = '\0';
    f->mem = NULL;
    f->mem_size = 0;
}

glint_rc jpeg_decode(const uint8_t *data, size_t size, const char *name, image *out,
                     glint_error *err)
{
    const char *why;
    if (!dynlib_open(&jpeg_lib, &why))
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot read JPEG files (%s)", name, why);
    struct jpeg_decompress_struct cinfo;
    jpeg_failure f;
    uint8_t *volatile px = NULL;
    failure_init(&f);
    cinfo.err = &f.mgr;
    if (setjmp(f.jump)) {
        jpeg_destroy_decompress(&cinfo);
        free(px);
        if (f.truncated || f.mgr.msg_code == JERR_INPUT_EOF)
            return codec_truncated(name, err);
        if (f.mgr.msg_code == JERR_OUT_OF_MEMORY)
            return err_nomem(err);
        return err_set(err, GLINT_ERR_INPUT, "%s: broken JPEG file (%s)", name, f.msg);
    }
    jpeg_create_decompress(&cinfo);
    /* bound libjpeg's own working memory (progressive files keep every
     * coefficient: 128 bytes per pixel per component at worst) */
    cinfo.mem->max_memory_to_use = 1L << 30;
    jpeg_mem_src(&cinfo, data, (unsigned long)size);
    jpeg_read_header(&cinfo, TRUE);
    /* Huffman coding spends at least one bit on each 8x8 block's DC term
     * (in some scan), so a byte holds at most 512 pixels; arithmetic
     * coding has no such floor. */
    if (codec_check_size(cinfo.image_width, cinfo.image_height, name, err) != GLINT_OK ||
        (!cinfo.arith_code &&
         codec_check_data(cinfo.image_width, cinfo.image_height, size, 512, name, err) !=
             GLINT_OK)) {
        jpeg_destroy_decompress(&cinfo);
        return GLINT_ERR_INPUT;
    }
    cinfo.out_color_space = JCS_RGB; /* grey and YCbCr alike; CMYK fails below */
    jpeg_start_decompress(&cinfo);
    if (cinfo.output_components != 3) {
        jpeg_destroy_decompress(&cinfo);
        return err_set(err, GLINT_ERR_INPUT, "%s: JPEG colour space is not supported", name);
    }
    size_t w = cinfo.output_width, h = cinfo.output_height;
    px = array_calloc_big(w * h * 3);
    if (!px) {
        jpeg_destroy_decompress(&cinfo);
        return err_nomem(err);
    }
    while (cinfo.output_scanline < cinfo.output_height) {
        JSAMPROW row = px + (size_t)cinfo.output_scanline * w * 3;
        jpeg_read_scanlines(&cinfo, &row, 1);
        if (f.truncated)
            longjmp(f.jump, 1);
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    if (f.truncated) {
        free(px);
        return codec_truncated(name, err);
    }
    *out = (image){.width = (int)w, .height = (int)h, .rgb = px};
    return GLINT_OK;
}

glint_rc jpeg_writer_ready(const char *name, glint_error *err)
{
    const char *why;
    if (!dynlib_open(&jpeg_lib, &why))
        return err_set(err, GLINT_ERR_IO, "%s: cannot write JPEG files (%s)",
                       name ? name : "JPEG", why);
    return GLINT_OK;
}

glint_rc jpeg_encode(const raster *r, bytebuf *out, glint_error *err)
{
    glint_rc ready = jpeg_writer_ready(r->name, err);
    if (ready != GLINT_OK)
        return ready;
    struct jpeg_compress_struct cinfo;
    jpeg_failure f;
    size_t w = (size_t)r->width;
    uint8_t *volatile row = malloc(w * 3);
    if (!row)
        return err_nomem(err);
    failure_init(&f);
    cinfo.err = &f.mgr;
    if (setjmp(f.jump)) {
        jpeg_destroy_compress(&cinfo);
        free(row);
        free(f.mem);
        if (f.mgr.msg_code == JERR_OUT_OF_MEMORY)
            return err_nomem(err);
        return err_set(err, GLINT_ERR_INPUT, "JPEG: cannot encode (%s)", f.msg);
    }
    jpeg_create_compress(&cinfo);
    jpeg_mem_dest(&cinfo, &f.mem, &f.mem_size);
    cinfo.image_width = (JDIMENSION)r->width;
    cinfo.image_height = (JDIMENSION)r->height;
    cinfo.input_components = 3;
    cinfo.in_color_space = JCS_RGB;
    jpeg_set_defaults(&cinfo);
    jpeg_set_quality(&cinfo, r->quality, TRUE);
    jpeg_start_compress(&cinfo, TRUE);
    while (cinfo.next_scanline < cinfo.image_height) {
        const float *src = r->rgb + (size_t)cinfo.next_scanline * w * 3;
        image_quantize(src, w * 3, r->transfer, row);
        JSAMPROW rows[1] = {row};
        jpeg_write_scanlines(&cinfo, rows, 1);
    }
    jpeg_finish_compress(&cinfo);
    jpeg_destroy_compress(&cinfo);
    free(row);
    bool ok = bytes_append(out, f.mem, f.mem_size);
    free(f.mem);
    return ok ? GLINT_OK : err_nomem(err);
}
