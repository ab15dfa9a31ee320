/* legacy: BMP, TGA and GIF (first frame) through stb_image, the only
 * formats left to it: no hardened Debian library reads them, and stb's
 * authors say it is not meant for untrusted input. The size is checked from
 * stb's header parse before any pixel is decoded, and the fuzz target
 * (fuzz/fuzz_texture.c) reaches this code too. Prefer PNG for textures.
 * Debian's libstb is opened at the first such file (core/dynlib.h), not
 * linked. */
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "codec.h"
#include "core/dynlib.h"
#include "core/error.h"
#include "image.h"

#define STB_FUNCTIONS(X, t)                                                                    \
    X(t, stbi_info_from_memory) X(t, stbi_load_from_memory) X(t, stbi_image_free)              \
    X(t, stbi_failure_reason)

static DYNLIB_STRUCT(STB_FUNCTIONS) stb_fn;
static dynlib stb_lib = DYNLIB(GLINT_SONAME_STB, STB_FUNCTIONS, stb_fn);

#define stbi_info_from_memory (stb_fn.stbi_info_from_memory)
#define stbi_load_from_memory (stb_fn.stbi_load_from_memory)
#define stbi_image_free (stb_fn.stbi_image_free)
#define stbi_failure_reason (stb_fn.stbi_failure_reason)

glint_rc legacy_decode(const uint8_t *data, size_t size, const char *name, image *out,
                       glint_error *err)
{
    const char *why;
    if (!dynlib_open(&stb_lib, &why))
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot read BMP, TGA or GIF files (%s)", name,
                       why);
    int w, h, comp;
    if (size > (size_t)INT32_MAX)
        return err_set(err, GLINT_ERR_INPUT, "%s: image file too large", name);
    if (!stbi_info_from_memory(data, (int)size, &w, &h, &comp))
        return err_set(err, GLINT_ERR_INPUT, "%s: broken BMP, TGA or GIF file (%s)", name,
                       stbi_failure_reason());
    glint_rc rc = codec_check_size(w > 0 ? (uint64_t)w : 0, h > 0 ? (uint64_t)h : 0, name, err);
    /* TGA and BMP run lengths reach 128 and 255 pixels per 2 bytes; GIF's
     * LZW codes at most 4096 pixels per 12-bit code */
    if (rc == GLINT_OK)
        rc = codec_check_data((uint64_t)w, (uint64_t)h, size, 4096, name, err);
    if (rc != GLINT_OK)
        return rc;
    unsigned char *px = stbi_load_from_memory(data, (int)size, &w, &h, &comp, 3);
    if (!px)
        return err_set(err, GLINT_ERR_INPUT, "%s: broken BMP, TGA or GIF file (%s)", name,
                       stbi_failure_reason());
    /* our own copy, so image_free needs no knowledge of stb's allocator */
    size_t n = (size_t)w * (size_t)h * 3;
    uint8_t *copy = malloc(n);
    if (!copy) {
        stbi_image_free(px);
        return err_nomem(err);
    }
    memcpy(copy, px, n);
    stbi_image_free(px);
    *out = (image){.width = w, .height = h, .rgb = copy};
    return GLINT_OK;
}
