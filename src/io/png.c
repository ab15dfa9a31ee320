/* png: PNG read through libspng (the writer is png_write.c). */
#include <stdlib.h>

#include <spng.h>

#include "codec.h"
#include "core/array.h"
#include "core/error.h"
#include "image.h"

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
