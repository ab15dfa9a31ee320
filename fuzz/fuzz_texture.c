/* libFuzzer target for the image readers: any bytes as a texture file,
 * through the same entry the scene loader uses (image_load_memory), so the
 * format is told from the bytes and every reader is reached: PNG (glint's
 * own reader for the common forms, libspng for the rest), JPEG
 * (libjpeg-turbo), OpenEXR, Radiance HDR, PFM, PPM/PGM and the stb_image
 * formats (BMP, TGA, GIF). A decoded image is read whole, so a short
 * buffer shows up under AddressSanitizer. A PNG is read a second time with
 * every chunk's CRC made right, so that the mutations reach the inflate
 * and the unfiltering behind the checksums. Seeds: tools/fuzzseeds.c. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <libdeflate.h>

#include "io/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static void read_once(const uint8_t *data, size_t size);

/* The PNG's chunks with their CRCs made right, read. */
static void read_crcs_fixed(const uint8_t *data, size_t size)
{
    uint8_t *m = malloc(size);
    if (!m)
        return;
    memcpy(m, data, size);
    for (size_t at = 8; size - at >= 12 && be32(m + at) <= size - at - 12;
         at += 12 + (size_t)be32(m + at)) {
        uint32_t len = be32(m + at);
        uint32_t crc = (uint32_t)libdeflate_crc32(0, m + at + 4, (size_t)len + 4);
        for (int i = 0; i < 4; i++)
            m[at + 8 + len + (size_t)i] = (uint8_t)(crc >> (24 - 8 * i));
    }
    read_once(m, size);
    free(m);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    read_once(data, size);
    if (size > 8 && !memcmp(data, "\x89PNG\r\n\x1a\n", 8))
        read_crcs_fixed(data, size);
    return 0;
}

static void read_once(const uint8_t *data, size_t size)
{
    image img = {0};
    glint_error err = {0};
    if (image_load_memory(data, size, "fuzz", &img, &err) != GLINT_OK) {
        if (img.rgb || img.linear || !err.msg[0])
            abort(); /* a failure leaves nothing behind and always says why */
        return;
    }
    if (img.width <= 0 || img.height <= 0 || (uint64_t)img.width * (uint64_t)img.height >
                                                  IMAGE_MAX_PIXELS ||
        !img.rgb == !img.linear)
        abort();
    size_t n = (size_t)img.width * (size_t)img.height * 3;
    volatile float sum = 0.0f;
    for (size_t i = 0; i < n; i++)
        sum += img.rgb ? (float)img.rgb[i] : img.linear[i];
    image_free(&img);
}
