/* exr: OpenEXR through the library's C API (OpenEXRCore, openexr.h), to
 * and from memory through custom stream functions, so the file writer can
 * stay atomic and the reader sees only bytes.
 *
 * Written: one scanline part, ZIP-compressed (lossless), channels R, G, B
 * and A when there is alpha, as half (16 bits) or float (32 bits). Read:
 * the first part when it holds scanlines; R, G and B (or Y, grey) become
 * linear floats; a missing channel reads as 0. The data window's size is
 * checked against IMAGE_MAX_PIXELS before any chunk is decoded.
 *
 * OpenEXRCore is opened at the first OpenEXR file read or written
 * (core/dynlib.h), not linked. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

#include "codec.h"
#include "core/dynlib.h"
#include "core/error.h"
#include "image.h"

#define EXR_FUNCTIONS(X, t)                                                                    \
    X(t, exr_get_user_data) X(t, exr_get_error_code_as_string) X(t, exr_start_write)           \
    X(t, exr_add_part) X(t, exr_initialize_required_attr_simple) X(t, exr_add_channel)         \
    X(t, exr_write_header) X(t, exr_get_scanlines_per_chunk)                                   \
    X(t, exr_write_scanline_chunk_info) X(t, exr_encoding_initialize)                          \
    X(t, exr_encoding_update) X(t, exr_encoding_choose_default_routines)                       \
    X(t, exr_encoding_run) X(t, exr_encoding_destroy) X(t, exr_finish) X(t, exr_start_read)    \
    X(t, exr_get_storage) X(t, exr_get_data_window) X(t, exr_get_channels)                     \
    X(t, exr_read_scanline_chunk_info) X(t, exr_decoding_initialize)                           \
    X(t, exr_decoding_update) X(t, exr_decoding_choose_default_routines)                       \
    X(t, exr_decoding_run) X(t, exr_decoding_destroy)

static DYNLIB_STRUCT(EXR_FUNCTIONS) exr_fn;
static dynlib exr_lib = DYNLIB(GLINT_SONAME_EXR, EXR_FUNCTIONS, exr_fn);

#define exr_get_user_data (exr_fn.exr_get_user_data)
#define exr_get_error_code_as_string (exr_fn.exr_get_error_code_as_string)
#define exr_start_write (exr_fn.exr_start_write)
#define exr_add_part (exr_fn.exr_add_part)
#define exr_initialize_required_attr_simple (exr_fn.exr_initialize_required_attr_simple)
#define exr_add_channel (exr_fn.exr_add_channel)
#define exr_write_header (exr_fn.exr_write_header)
#define exr_get_scanlines_per_chunk (exr_fn.exr_get_scanlines_per_chunk)
#define exr_write_scanline_chunk_info (exr_fn.exr_write_scanline_chunk_info)
#define exr_encoding_initialize (exr_fn.exr_encoding_initialize)
#define exr_encoding_update (exr_fn.exr_encoding_update)
#define exr_encoding_choose_default_routines (exr_fn.exr_encoding_choose_default_routines)
#define exr_encoding_run (exr_fn.exr_encoding_run)
#define exr_encoding_destroy (exr_fn.exr_encoding_destroy)
#define exr_finish (exr_fn.exr_finish)
#define exr_start_read (exr_fn.exr_start_read)
#define exr_get_storage (exr_fn.exr_get_storage)
#define exr_get_data_window (exr_fn.exr_get_data_window)
#define exr_get_channels (exr_fn.exr_get_channels)
#define exr_read_scanline_chunk_info (exr_fn.exr_read_scanline_chunk_info)
#define exr_decoding_initialize (exr_fn.exr_decoding_initialize)
#define exr_decoding_update (exr_fn.exr_decoding_update)
#define exr_decoding_choose_default_routines (exr_fn.exr_decoding_choose_default_routines)
#define exr_decoding_run (exr_fn.exr_decoding_run)
#define exr_decoding_destroy (exr_fn.exr_decoding_destroy)

/* The stream behind a context, and the library's last message (its error
 * handler must not print: library code never does). */
typedef struct exr_stream {
    bytebuf *out;          /* writing */
    const uint8_t *data; /* reading */
    size_t size;
    bool nomem;
    char msg[256];
} exr_stream;

static exr_stream *stream_of(exr_const_context_t ctxt)
{
    void *user = NULL;
    exr_get_user_data(ctxt, &user);
    return user;
}

static void on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    exr_stream *s = stream_of(ctxt);
    if (s)
        snprintf(s->msg, sizeof s->msg, "%s", msg ? msg : exr_get_error_code_as_string(code));
}

/* pwrite into a growing buffer */
static int64_t on_write(exr_const_context_t ctxt, void *user, const void *buf, uint64_t sz,
                        uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt, (void)error_cb;
    exr_stream *s = user;
    if (offset > SIZE_MAX / 2 || sz > SIZE_MAX / 2) {
        s->nomem = true;
        return -1;
    }
    size_t end = (size_t)offset + (size_t)sz;
    if (end > s->out->len) {
        if (!bytes_grow(s->out, end - s->out->len)) {
            s->nomem = true;
            return -1;
        }
    }
    memcpy(s->out->data + offset, buf, (size_t)sz);
    return (int64_t)sz;
}

/* pread from memory */
static int64_t on_read(exr_const_context_t ctxt, void *user, void *buf, uint64_t sz,
                       uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt, (void)error_cb;
    exr_stream *s = user;
    if (offset >= s->size)
        return 0;
    size_t n = s->size - (size_t)offset < sz ? s->size - (size_t)offset : (size_t)sz;
    memcpy(buf, s->data + offset, n);
    return (int64_t)n;
}

static int64_t on_size(exr_const_context_t ctxt, void *user)
{
    (void)ctxt;
    return (int64_t)((exr_stream *)user)->size;
}

/* ---- writing ------------------------------------------------------------ */

/* Points each channel of the chunk at the film (interleaved RGB floats, and
 * the separate alpha plane). */
static void bind_film(exr_encode_pipeline_t *enc, const raster *r, int y0)
{
    size_t w = (size_t)r->width;
    for (int c = 0; c < enc->channel_count; c++) {
        exr_coding_channel_info_t *ch = &enc->channels[c];
        const char *n = ch->channel_name;
        const float *src;
        if (n[0] == 'A') {
            src = r->alpha + (size_t)y0 * w;
            ch->user_pixel_stride = 4;
        } else {
            int k = n[0] == 'R' ? 0 : n[0] == 'G' ? 1 : 2;
            src = r->rgb + (size_t)y0 * w * 3 + k;
            ch->user_pixel_stride = 12;
        }
        ch->user_line_stride = (int32_t)(w * (size_t)ch->user_pixel_stride);
        ch->user_bytes_per_element = 4;
        ch->user_data_type = EXR_PIXEL_FLOAT;
        ch->encode_from_ptr = (const uint8_t *)src;
    }
}

static exr_result_t write_chunks(exr_context_t ctx, const raster *r)
{
    int lines;
    exr_result_t e = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool started = false;
    for (int y = 0; !e && y < r->height; y += lines) {
        exr_chunk_info_t cinfo;
        e = exr_write_scanline_chunk_info(ctx, 0, y, &cinfo);
        if (e)
            break;
        e = started ? exr_encoding_update(ctx, 0, &cinfo, &enc)
                    : exr_encoding_initialize(ctx, 0, &cinfo, &enc);
        if (e)
            break;
        bind_film(&enc, r, y);
        if (!started) {
            e = exr_encoding_choose_default_routines(ctx, 0, &enc);
            started = true;
        }
        if (!e)
            e = exr_encoding_run(ctx, 0, &enc);
    }
    if (started)
        exr_encoding_destroy(ctx, &enc);
    return e;
}

glint_rc exr_writer_ready(const char *name, glint_error *err)
{
    const char *why;
    if (!dynlib_open(&exr_lib, &why))
        return err_set(err, GLINT_ERR_IO, "%s: cannot write OpenEXR files (%s)",
                       name ? name : "OpenEXR", why);
    return GLINT_OK;
}

glint_rc exr_encode(const raster *r, bytebuf *out, glint_error *err)
{
    glint_rc ready = exr_writer_ready(r->name, err);
    if (ready != GLINT_OK)
        return ready;
    exr_stream s = {.out = out};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &s;
    init.write_fn = on_write;
    init.error_handler_fn = on_error;
    exr_context_t ctx = NULL;
    exr_pixel_type_t type = r->bits == 32 ? EXR_PIXEL_FLOAT : EXR_PIXEL_HALF;
    int part;
    exr_result_t e = exr_start_write(&ctx, "film.exr", EXR_WRITE_FILE_DIRECTLY, &init);
    if (!e)
        e = exr_add_part(ctx, "rgb", EXR_STORAGE_SCANLINE, &part);
    if (!e)
        e = exr_initialize_required_attr_simple(ctx, 0, r->width, r->height,
                                                EXR_COMPRESSION_ZIP);
    static const char *const names[4] = {"R", "G", "B", "A"};
    for (int c = 0; !e && c < (r->alpha ? 4 : 3); c++)
        e = exr_add_channel(ctx, 0, names[c], type, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (!e)
        e = exr_write_header(ctx);
    if (!e)
        e = write_chunks(ctx, r);
    exr_result_t f = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
    if (!e)
        e = f;
    if (!e)
        return GLINT_OK;
    if (s.nomem || e == EXR_ERR_OUT_OF_MEMORY)
        return err_nomem(err);
    return err_set(err, GLINT_ERR_IO, "OpenEXR: cannot encode (%s)",
                   s.msg[0] ? s.msg : exr_get_error_code_as_string(e));
}

/* ---- reading ------------------------------------------------------------ */

/* Channel name to RGB slot: R, G, B by their last letter (so "rgb.R"
 * layers work too), Y to all three; -1 to skip. */
static int slot_of(const char *name, bool grey)
{
    const char *dot = strrchr(name, '.');
    const char *n = dot ? dot + 1 : name;
    if (grey && strcmp(n, "Y") == 0)
        return 3;
    return strcmp(n, "R") == 0 ? 0 : strcmp(n, "G") == 0 ? 1 : strcmp(n, "B") == 0 ? 2 : -1;
}

/* Points each channel at its place in px (rows from row on); a channel
 * glint does not use is decoded into skip (one float per pixel of a chunk)
 * and dropped: OpenEXR 3.1's unpackers read through a NULL destination
 * when some channels have one and others not (found by fuzzing). */
static void bind_image(exr_decode_pipeline_t *dec, float *px, float *skip, int width, int row,
                       bool grey)
{
    for (int c = 0; c < dec->channel_count; c++) {
        exr_coding_channel_info_t *ch = &dec->channels[c];
        int k = slot_of(ch->channel_name, grey);
        ch->user_bytes_per_element = 4;
        ch->user_data_type = EXR_PIXEL_FLOAT;
        if (k < 0) {
            ch->user_pixel_stride = 4;
            ch->user_line_stride = width * 4;
            ch->decode_to_ptr = (uint8_t *)skip;
            continue;
        }
        if (k == 3) /* Y goes to R; copied to G, B after the last chunk */
            k = 0;
        ch->user_pixel_stride = 12;
        ch->user_line_stride = width * 12;
        ch->decode_to_ptr = (uint8_t *)(px + ((size_t)row * (size_t)width * 3 + (size_t)k));
    }
}

/* Whether the channels hold R, G or B; otherwise Y is looked for. */
static bool has_rgb(exr_context_t ctx)
{
    const exr_attr_chlist_t *list = NULL;
    if (exr_get_channels(ctx, 0, &list) || !list)
        return false;
    for (int i = 0; i < list->num_channels; i++)
        if (slot_of(list->entries[i].name.str, false) >= 0)
            return true;
    return false;
}

static exr_result_t read_chunks(exr_context_t ctx, float *px, exr_attr_box2i_t dw, bool grey)
{
    int width = dw.max.x - dw.min.x + 1, height = dw.max.y - dw.min.y + 1;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int lines;
    exr_result_t e = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    float *skip = e || lines < 1 ? NULL : malloc((size_t)width * (size_t)lines * sizeof *skip);
    if (!e && !skip)
        return lines < 1 ? EXR_ERR_CORRUPT_CHUNK : EXR_ERR_OUT_OF_MEMORY;
    bool started = false;
    for (int y = dw.min.y; !e && y <= dw.max.y; y += lines) {
        exr_chunk_info_t cinfo;
        e = exr_read_scanline_chunk_info(ctx, 0, y, &cinfo);
        if (e)
            break;
        e = started ? exr_decoding_update(ctx, 0, &cinfo, &dec)
                    : exr_decoding_initialize(ctx, 0, &cinfo, &dec);
        if (e)
            break;
        int row = cinfo.start_y - dw.min.y;
        if (row < 0 || row + cinfo.height > height) {
            e = EXR_ERR_CORRUPT_CHUNK;
            break;
        }
        bind_image(&dec, px, skip, width, row, grey);
        if (!started) {
            e = exr_decoding_choose_default_routines(ctx, 0, &dec);
            started = true;
        }
        if (!e)
            e = exr_decoding_run(ctx, 0, &dec);
    }
    if (started)
        exr_decoding_destroy(ctx, &dec);
    free(skip);
    size_t n = (size_t)width * (size_t)height;
    if (!e && grey)
        for (size_t i = 0; i < n; i++)
            px[3 * i + 1] = px[3 * i + 2] = px[3 * i];
    for (size_t i = 0; !e && i < n * 3; i++) /* infinities and NaNs are no colour */
        if (!isfinite(px[i]))
            px[i] = 0.0f;
    return e;
}

glint_rc exr_decode(const uint8_t *data, size_t size, const char *name, image *out,
                    glint_error *err)
{
    const char *why;
    if (!dynlib_open(&exr_lib, &why))
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot read OpenEXR files (%s)", name, why);
    exr_stream s = {.data = data, .size = size};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &s;
    init.read_fn = on_read;
    init.size_fn = on_size;
    init.error_handler_fn = on_error;
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    exr_context_t ctx = NULL;
    float *px = NULL;
    glint_rc rc = GLINT_OK;
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    exr_result_t e = exr_start_read(&ctx, name, &init);
    if (!e)
        e = exr_get_storage(ctx, 0, &storage);
    if (!e && storage != EXR_STORAGE_SCANLINE) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: only scanline OpenEXR images are read", name);
        goto out;
    }
    if (!e)
        e = exr_get_data_window(ctx, 0, &dw);
    if (e)
        goto out;
    int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
    rc = codec_check_size(w > 0 ? (uint64_t)w : 0, h > 0 ? (uint64_t)h : 0, name, err);
    /* ZIP (deflate) expands at most about 1032 times, RLE 64 times; 4096
     * pixels per byte leaves room for half-float grey */
    if (rc == GLINT_OK)
        rc = codec_check_data((uint64_t)w, (uint64_t)h, size, 4096, name, err);
    if (rc != GLINT_OK)
        goto out;
    px = calloc((size_t)w * (size_t)h * 3, sizeof *px);
    if (!px) {
        rc = err_nomem(err);
        goto out;
    }
    e = read_chunks(ctx, px, dw, !has_rgb(ctx));
    if (!e) {
        *out = (image){.width = (int)w, .height = (int)h, .linear = px};
        px = NULL;
    }
out:
    if (ctx)
        exr_finish(&ctx);
    free(px);
    if (rc != GLINT_OK || !e)
        return rc;
    if (e == EXR_ERR_OUT_OF_MEMORY)
        return err_nomem(err);
    if (e == EXR_ERR_READ_IO || e == EXR_ERR_BAD_CHUNK_LEADER)
        return codec_truncated(name, err);
    return err_set(err, GLINT_ERR_INPUT, "%s: broken OpenEXR file (%s)", name,
                   s.msg[0] ? s.msg : exr_get_error_code_as_string(e));
}
