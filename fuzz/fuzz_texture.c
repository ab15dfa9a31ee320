/* libFuzzer target for the image readers: any bytes as a texture file,
 * through the same entry the scene loader uses (image_load_memory), so the
 * format is told from the bytes and every reader is reached: PNG (libspng),
 * JPEG (libjpeg-turbo), OpenEXR, Radiance HDR, PFM, PPM/PGM and the
 * stb_image formats (BMP, TGA, GIF). A decoded image is read whole, so a
 * short buffer shows up under AddressSanitizer. Seeds: tools/fuzzseeds.c. */
#include <stdint.h>
#include <stdlib.h>

#include "io/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    image img = {0};
    glint_error err = {0};
    if (image_load_memory(data, size, "fuzz", &img, &err) != GLINT_OK) {
        if (img.rgb || img.linear || !err.msg[0])
            abort(); /* a failure leaves nothing behind and always says why */
        return 0;
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
    return 0;
}
