/* fuzzseeds: writes one small file of every image format glint reads into
 * a folder, the seed corpus of fuzz/fuzz_texture.c. Usage: fuzzseeds DIR.
 * glint's own writers make most; stb_image_write makes the variants glint
 * does not write (grey PNG, BMP, TGA, grey JPEG). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

#include "glint.h"

enum { W = 16, H = 12 };

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: fuzzseeds DIR\n");
        return 2;
    }
    static float rgb[W * H * 3], alpha[W * H];
    static unsigned char bytes[W * H * 4];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float *p = rgb + (y * W + x) * 3;
            p[0] = (float)x / W;                     /* gradient */
            p[1] = y < H / 2 ? 0.25f : 3.5f;          /* flat, and over 1 */
            p[2] = (x / 4 + y / 4) % 2 ? 1.0f : 0.0f; /* chequer */
            alpha[y * W + x] = x < W / 2 ? 1.0f : 0.5f;
            for (int k = 0; k < 4; k++)
                bytes[(y * W + x) * 4 + k] = (unsigned char)(x * 16 + y * 5 + k * 60);
        }
    glint_film film = {W, H, rgb, NULL};
    struct {
        const char *name;
        glint_write_options o;
    } outs[] = {
        {"rgb.png", {0}},
        {"rgb16.png", {.bits = 16}},
        {"rgba.png", {.alpha = alpha}},
        {"rgba16.png", {.bits = 16, .alpha = alpha}},
        {"q75.jpg", {.quality = 75}},
        {"rgbe.hdr", {0}},
        {"float.pfm", {0}},
        {"rgb.ppm", {0}},
        {"rgb16.ppm", {.bits = 16}},
        {"half.exr", {0}},
        {"float.exr", {.bits = 32}},
        {"rgba.exr", {.alpha = alpha}},
    };
    char path[4096];
    glint_error err;
    for (size_t i = 0; i < sizeof outs / sizeof outs[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", argv[1], outs[i].name);
        if (glint_film_write(&film, path, &outs[i].o, &err) != GLINT_OK) {
            fprintf(stderr, "fuzzseeds: %s\n", err.msg);
            return 1;
        }
    }
    /* a Radiance file too narrow for run-length scanlines */
    glint_film narrow = {4, 3, rgb, NULL};
    snprintf(path, sizeof path, "%s/narrow.hdr", argv[1]);
    if (glint_film_write(&narrow, path, NULL, &err) != GLINT_OK) {
        fprintf(stderr, "fuzzseeds: %s\n", err.msg);
        return 1;
    }
    int ok = 1;
#define SEED(name, call) (snprintf(path, sizeof path, "%s/" name, argv[1]), ok &= !!(call))
    SEED("grey.png", stbi_write_png(path, W, H, 1, bytes, W));
    SEED("grey-alpha.png", stbi_write_png(path, W, H, 2, bytes, W * 2));
    SEED("rgb.bmp", stbi_write_bmp(path, W, H, 3, bytes));
    SEED("rgba.bmp", stbi_write_bmp(path, W, H, 4, bytes));
    SEED("rgb.tga", stbi_write_tga(path, W, H, 3, bytes));
    SEED("grey.jpg", stbi_write_jpg(path, W, H, 1, bytes, 90));
    /* a PGM with a comment, written by hand */
    snprintf(path, sizeof path, "%s/grey.pgm", argv[1]);
    FILE *f = fopen(path, "wb");
    ok &= f && fprintf(f, "P5\n# seed\n%d %d\n255\n", W, H) > 0 &&
          fwrite(bytes, 1, W * H, f) == W * H;
    ok &= f && fclose(f) == 0;
    if (!ok) {
        fprintf(stderr, "fuzzseeds: cannot write the stb seeds in %s\n", argv[1]);
        return 1;
    }
    return 0;
}
