/* Image files (src/io): every output format read back (exactly for PNG,
 * PPM, PFM and EXR float; within stated tolerances for JPEG, Radiance HDR
 * and EXR half); BMP and JPEG written with stb_image_write read through the
 * hardened readers; decoder errors (truncated, too large by the header, not
 * an image, a directory, a FIFO) with messages that start with the file's
 * name; the atomic writer (symbolic links written through, modes kept,
 * read-only files refused, no temporary file left after a failure, long
 * names); the output checks made before a render; the 8-bit transfer
 * tables. Every test works in its own mkdtemp directory, removed afterwards. */
#include <criterion/criterion.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb_image_write.h>

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <spng.h>

#include "io/codec.h"
#include "io/image.h"
#include "io/file.h"
#include "io/image_write.h"
#include "tmpdir.h"

static void make_dir(void) { tmpdir_make("image"); }

static void remove_dir(void) { tmpdir_remove(); }

TestSuite(image, .init = make_dir, .fini = remove_dir);

static const char *in_dir(const char *name)
{
    static char path[4][512];
    static int next;
    char *p = path[next++ % 4];
    snprintf(p, sizeof path[0], "%s/%s", dir, name);
    return p;
}

/* The names in dir, space-separated (in readdir order); returns how many. */
static int list_dir(char *names, size_t size)
{
    DIR *d = opendir(dir);
    cr_assert_not_null(d);
    int n = 0;
    names[0] = '\0';
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        n++;
        strncat(names, e->d_name, size - strlen(names) - 2);
        strcat(names, " ");
    }
    closedir(d);
    return n;
}

static void write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    cr_assert_not_null(f);
    cr_assert_eq(fwrite(data, 1, n, f), n);
    cr_assert_eq(fclose(f), 0);
}

static unsigned char *read_bytes(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f, "%s", path);
    static unsigned char buf[1 << 16];
    *n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    return buf;
}

/* 7x5 with every pixel distinct. */
static void test_pattern(uint8_t rgb[7 * 5 * 3])
{
    for (int y = 0; y < 5; y++)
        for (int x = 0; x < 7; x++) {
            uint8_t *p = rgb + (y * 7 + x) * 3;
            p[0] = (uint8_t)(x * 36 + 3);
            p[1] = (uint8_t)(y * 60 + 1);
            p[2] = (uint8_t)(255 - (x * 5 + y) * 7);
        }
}

/* Writes 8-bit values through the film writer: v / 255 quantises back to v
 * exactly (transfer none). */
static glint_rc write_rgb8(const char *path, int w, int h, const uint8_t *rgb, glint_error *err)
{
    size_t n = (size_t)w * (size_t)h * 3;
    float *f = malloc(n * sizeof *f);
    cr_assert_not_null(f);
    for (size_t i = 0; i < n; i++)
        f[i] = rgb[i] / 255.0f;
    glint_rc rc = image_write_film(path, w, h, f, NULL, err);
    free(f);
    return rc;
}

static void expect_pixels(const image *img, int w, int h, const uint8_t *want)
{
    cr_assert_eq(img->width, w);
    cr_assert_eq(img->height, h);
    for (int i = 0; i < w * h * 3; i++)
        cr_assert_eq(img->rgb[i], want[i], "byte %d (pixel %d, %d): %d, want %d", i, i / 3 % w,
                     i / 3 / w, img->rgb[i], want[i]);
}

/* An error whose code is rc and whose message starts with "path: ". */
static void expect_error(glint_rc got, const glint_error *err, glint_rc rc, const char *path)
{
    cr_assert_eq(got, rc, "rc %d, want %d (%s)", got, rc, err->msg);
    cr_assert_eq(err->code, rc);
    size_t n = strlen(path);
    cr_assert(strncmp(err->msg, path, n) == 0 && err->msg[n] == ':',
              "message does not start with the file name: %s", err->msg);
}

/* ---- round trips -------------------------------------------------------- */

Test(image, png_round_trip_is_exact)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    glint_error err = {0};
    const char *path = in_dir("pattern.png");
    cr_assert_eq(write_rgb8(path, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    image img = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    expect_pixels(&img, 7, 5, rgb);
    image_free(&img);
    cr_assert_null(img.rgb);
    /* and from memory */
    size_t n;
    unsigned char *bytes = read_bytes(path, &n);
    cr_assert_eq(memcmp(bytes, "\x89PNG\r\n\x1a\n", 8), 0);
    cr_assert_eq(image_load_memory(bytes, n, "mem.png", &img, &err), GLINT_OK, "%s", err.msg);
    expect_pixels(&img, 7, 5, rgb);
    image_free(&img);
    /* only the file itself is left: no temporary beside it */
    char names[256];
    cr_assert_eq(list_dir(names, sizeof names), 1, "files: %s", names);
}

Test(image, ppm_round_trip_is_exact)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    glint_error err = {0};
    const char *path = in_dir("pattern.PPM"); /* the extension in any case */
    cr_assert_eq(write_rgb8(path, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    size_t n;
    unsigned char *bytes = read_bytes(path, &n);
    const char header[] = "P6\n7 5\n255\n";
    cr_assert_eq(n, strlen(header) + sizeof rgb);
    cr_assert_eq(memcmp(bytes, header, strlen(header)), 0);
    cr_assert_eq(memcmp(bytes + strlen(header), rgb, sizeof rgb), 0);
    image img = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    expect_pixels(&img, 7, 5, rgb);
    image_free(&img);
}

Test(image, bmp_written_by_stb_reads_back_exactly)
{
    uint8_t rgb[7 * 5 * 3]; /* 7 pixels: rows need padding in BMP */
    test_pattern(rgb);
    const char *path = in_dir("pattern.bmp");
    cr_assert(stbi_write_bmp(path, 7, 5, 3, rgb));
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    expect_pixels(&img, 7, 5, rgb);
    image_free(&img);
}

/* A smooth 48x32 gradient at quality 95: JPEG is lossy, so each byte must
 * be within 12 levels of the original (typical error here is 1-3). */
Test(image, jpeg_written_by_stb_reads_back_within_tolerance)
{
    enum { W = 48, H = 32 };
    static uint8_t rgb[W * H * 3];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint8_t *p = rgb + (y * W + x) * 3;
            p[0] = (uint8_t)(40 + x * 3);
            p[1] = (uint8_t)(30 + y * 5);
            p[2] = (uint8_t)(200 - x - y);
        }
    const char *path = in_dir("smooth.jpg");
    cr_assert(stbi_write_jpg(path, W, H, 3, rgb, 95));
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(img.width, W);
    cr_assert_eq(img.height, H);
    int worst = 0;
    for (int i = 0; i < W * H * 3; i++) {
        int d = abs((int)img.rgb[i] - (int)rgb[i]);
        if (d > worst)
            worst = d;
    }
    cr_assert_leq(worst, 12, "max abs difference %d levels", worst);
    image_free(&img);
}

/* Grey and RGBA files come back as RGB. */
Test(image, other_channel_counts_become_rgb)
{
    const uint8_t grey[4] = {0, 85, 170, 255};
    const char *path = in_dir("grey.png");
    cr_assert(stbi_write_png(path, 2, 2, 1, grey, 2));
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    const uint8_t want[12] = {0, 0, 0, 85, 85, 85, 170, 170, 170, 255, 255, 255};
    expect_pixels(&img, 2, 2, want);
    image_free(&img);
    const uint8_t rgba[8] = {10, 20, 30, 0, 40, 50, 60, 255};
    path = in_dir("rgba.png");
    cr_assert(stbi_write_png(path, 2, 1, 4, rgba, 8));
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    const uint8_t want2[6] = {10, 20, 30, 40, 50, 60};
    expect_pixels(&img, 2, 1, want2);
    image_free(&img);
}

/* ---- errors ------------------------------------------------------------- */

Test(image, missing_file_is_an_error_naming_it)
{
    const char *path = in_dir("no-such.png");
    image img = {0};
    glint_error err = {0};
    expect_error(image_load(path, &img, &err), &err, GLINT_ERR_INPUT, path);
    cr_assert_not_null(strstr(err.msg, "No such file"), "%s", err.msg);
    cr_assert_null(img.rgb);
}

Test(image, a_directory_is_an_error_saying_so)
{
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load("/tmp", &img, &err), GLINT_ERR_INPUT);
    cr_assert_str_eq(err.msg, "/tmp: cannot open image: Is a directory");
    cr_assert_null(img.rgb);
}

Test(image, truncated_garbage_and_empty_files_are_errors)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    glint_error err = {0};
    const char *good = in_dir("good.png");
    cr_assert_eq(write_rgb8(good, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    size_t n;
    unsigned char *bytes = read_bytes(good, &n);
    image img = {0};
    /* cut in half: the header survives, the pixel data does not */
    const char *cut = in_dir("cut.png");
    write_bytes(cut, bytes, n / 2);
    expect_error(image_load(cut, &img, &err), &err, GLINT_ERR_INPUT, cut);
    cr_assert_null(img.rgb);
    /* only the signature */
    const char *sig = in_dir("sig.png");
    write_bytes(sig, bytes, 8);
    expect_error(image_load(sig, &img, &err), &err, GLINT_ERR_INPUT, sig);
    /* text with a picture's name */
    const char *junk = in_dir("junk.png");
    const char text[] = "this is not a picture\n";
    write_bytes(junk, text, sizeof text - 1);
    expect_error(image_load(junk, &img, &err), &err, GLINT_ERR_INPUT, junk);
    /* a PNG whose pixel data was overwritten */
    const char *mangled = in_dir("mangled.png");
    unsigned char copy[1 << 12];
    cr_assert_lt(n, sizeof copy);
    memcpy(copy, bytes, n);
    for (size_t i = 40; i < n - 12; i++)
        copy[i] ^= 0x5a;
    write_bytes(mangled, copy, n);
    expect_error(image_load(mangled, &img, &err), &err, GLINT_ERR_INPUT, mangled);
    /* empty */
    const char *empty = in_dir("empty.png");
    write_bytes(empty, "", 0);
    expect_error(image_load(empty, &img, &err), &err, GLINT_ERR_INPUT, empty);
    cr_assert_not_null(strstr(err.msg, "empty"), "%s", err.msg);
    /* from memory: the given name is the one reported */
    expect_error(image_load_memory(text, sizeof text - 1, "textures/junk.png", &img, &err), &err,
                 GLINT_ERR_INPUT, "textures/junk.png");
    cr_assert_null(img.rgb);
}

/* A PNG header claiming 16384 x 17000 pixels (over IMAGE_MAX_PIXELS, 2^28)
 * is refused before any pixel is decoded. */
Test(image, absurd_size_is_refused)
{
    unsigned char png[33] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13,
                             'I', 'H', 'D', 'R', 0, 0, 0x40, 0x00, 0, 0, 0x42, 0x68,
                             8, 2, 0, 0, 0, 0, 0, 0, 0};
    image img = {0};
    glint_error err = {0};
    expect_error(image_load_memory(png, sizeof png, "huge.png", &img, &err), &err,
                 GLINT_ERR_INPUT, "huge.png");
    cr_assert_str_eq(err.msg, "huge.png: image 16384x17000 is too large (limit 268435456 pixels)");
    cr_assert_null(img.rgb);
}

Test(image, unsupported_output_extension_is_an_error)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    const char *names[] = {"out.gif", "out.tif", "out", "out.png.bak"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        const char *path = in_dir(names[i]);
        glint_error err = {0};
        expect_error(write_rgb8(path, 7, 5, rgb, &err), &err, GLINT_ERR_INPUT, path);
    }
    /* a dot in a folder name is not an extension */
    cr_assert_eq(mkdir(in_dir("a.png"), 0755), 0);
    const char *path = in_dir("a.png/out");
    glint_error err = {0};
    expect_error(write_rgb8(path, 7, 5, rgb, &err), &err, GLINT_ERR_INPUT, path);
    rmdir(in_dir("a.png"));
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 0, "files left: %s", listing);
}

/* ---- the atomic writer -------------------------------------------------- */

Test(image, write_into_missing_folder_fails_and_leaves_nothing)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    const char *path = in_dir("missing/out.png");
    glint_error err = {0};
    expect_error(write_rgb8(path, 7, 5, rgb, &err), &err, GLINT_ERR_IO, path);
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 0, "files left: %s", listing);
}

/* A folder in the target's place is refused before anything is created. */
Test(image, a_folder_as_target_is_refused_and_left_alone)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    const char *path = in_dir("busy.png");
    cr_assert_eq(mkdir(path, 0755), 0);
    glint_error err = {0};
    expect_error(write_rgb8(path, 7, 5, rgb, &err), &err, GLINT_ERR_INPUT, path);
    cr_assert_not_null(strstr(err.msg, "is a directory"), "%s", err.msg);
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 1, "files left: %s", listing);
    cr_assert_str_eq(listing, "busy.png ");
    struct stat st;
    cr_assert_eq(stat(path, &st), 0);
    cr_assert(S_ISDIR(st.st_mode));
}

/* Writing over an existing file replaces it whole. */
Test(image, existing_file_is_replaced)
{
    static uint8_t big[64 * 64 * 3];
    memset(big, 200, sizeof big);
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    const char *path = in_dir("out.png");
    glint_error err = {0};
    cr_assert_eq(write_rgb8(path, 64, 64, big, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(write_rgb8(path, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    image img = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    expect_pixels(&img, 7, 5, rgb);
    image_free(&img);
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 1, "files left: %s", listing);
}

/* ---- 8-bit transfer ----------------------------------------------------- */

Test(image, quantize_and_decode_tables)
{
    const float in[8] = {0.0f, 0.25f, 1.0f, 1.5f, -1.0f, NAN, INFINITY, 0.6f / 255.0f};
    uint8_t out[8];
    image_quantize(in, 8, GLINT_TRANSFER_NONE, out);
    const uint8_t want[8] = {0, 64, 255, 255, 0, 0, 255, 1}; /* 63.75 -> 64, 0.6 -> 1 */
    for (int i = 0; i < 8; i++)
        cr_assert_eq(out[i], want[i], "value %g: %d, want %d", (double)in[i], out[i], want[i]);
    /* sRGB: 0.5 -> 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357 -> 187.52 -> 188;
     * 0.001 on the linear segment -> 12.92e-3 * 255 = 3.29 -> 3 */
    const float lin[4] = {0.0f, 0.5f, 1.0f, 0.001f};
    uint8_t enc[4];
    image_quantize(lin, 4, GLINT_TRANSFER_SRGB, enc);
    cr_assert_eq(enc[0], 0);
    cr_assert_eq(enc[1], 188);
    cr_assert_eq(enc[2], 255);
    cr_assert_eq(enc[3], 3);

    float none[256], srgb[256];
    image_decode_table(GLINT_TRANSFER_NONE, none);
    image_decode_table(GLINT_TRANSFER_SRGB, srgb);
    cr_assert_float_eq(none[51], 0.2f, 1e-7);
    cr_assert_eq(srgb[0], 0.0f);
    cr_assert_float_eq(srgb[255], 1.0f, 1e-6);
    cr_assert_float_eq(srgb[188], pow((188 / 255.0 + 0.055) / 1.055, 2.4), 1e-6);
    /* decoding then quantising returns every level */
    uint8_t back[256];
    image_quantize(srgb, 256, GLINT_TRANSFER_SRGB, back);
    for (int i = 0; i < 256; i++)
        cr_assert_eq(back[i], i, "sRGB level %d comes back as %d", i, back[i]);
    image_quantize(none, 256, GLINT_TRANSFER_NONE, back);
    for (int i = 0; i < 256; i++)
        cr_assert_eq(back[i], i, "level %d comes back as %d", i, back[i]);
}

/* ---- every output format read back ------------------------------------ */

enum { FW = 23, FH = 9 }; /* odd sizes: no row happens to be aligned */

/* Linear values with flat runs (for run-length codes), a ramp, values over
 * 1 and tiny ones, and zeros. */
static void film_pattern(float rgb[FW * FH * 3], float alpha[FW * FH])
{
    for (int y = 0; y < FH; y++)
        for (int x = 0; x < FW; x++) {
            float *p = rgb + (y * FW + x) * 3;
            p[0] = (float)x / (FW - 1);
            p[1] = y < 3 ? 0.25f : y < 6 ? 7.5f : 1e-3f * (float)(x + 1);
            p[2] = (x + y) % 3 ? 0.0f : 0.6f;
            if (alpha)
                alpha[y * FW + x] = (float)(x % 5) / 4.0f;
        }
}

static image load_ok(const char *path)
{
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(img.width, FW);
    cr_assert_eq(img.height, FH);
    return img;
}

static void write_ok(const char *name, const float *rgb, const glint_write_options *o)
{
    glint_error err = {0};
    cr_assert_eq(image_write_film(in_dir(name), FW, FH, rgb, o, &err), GLINT_OK, "%s", err.msg);
}

Test(image, pfm_round_trip_is_bit_exact)
{
    float rgb[FW * FH * 3];
    film_pattern(rgb, NULL);
    write_ok("f.pfm", rgb, NULL);
    image img = load_ok(in_dir("f.pfm"));
    cr_assert_not_null(img.linear);
    cr_assert_eq(memcmp(img.linear, rgb, sizeof rgb), 0);
    image_free(&img);
}

/* Floats go out unquantised: EXR float is exact, half within its 11-bit
 * significand (relative error <= 2^-11) above half's normal range. */
Test(image, exr_round_trips_float_exactly_and_half_within_2e_11)
{
    float rgb[FW * FH * 3];
    film_pattern(rgb, NULL);
    write_ok("f.exr", rgb, &(glint_write_options){.bits = 32});
    image img = load_ok(in_dir("f.exr"));
    cr_assert_not_null(img.linear);
    cr_assert_eq(memcmp(img.linear, rgb, sizeof rgb), 0);
    image_free(&img);
    write_ok("h.exr", rgb, NULL);
    img = load_ok(in_dir("h.exr"));
    for (int i = 0; i < FW * FH * 3; i++)
        cr_assert_leq(fabsf(img.linear[i] - rgb[i]), fabsf(rgb[i]) * 0x1p-11f + 1e-7f,
                      "value %d: %g, want %g", i, (double)img.linear[i], (double)rgb[i]);
    image_free(&img);
}

/* RGBE keeps 8 bits of mantissa under a shared exponent: each channel is
 * within max(r, g, b) / 128 of the original (decoded at bucket centres),
 * and exact zeros stay zero. Linear: 0.25 reads as 0.25, not as a
 * gamma-encoded 0.533. */
Test(image, hdr_round_trip_is_linear_within_one_128th_of_the_brightest)
{
    float rgb[FW * FH * 3];
    film_pattern(rgb, NULL);
    write_ok("f.hdr", rgb, NULL);
    image img = load_ok(in_dir("f.hdr"));
    cr_assert_not_null(img.linear);
    for (int i = 0; i < FW * FH; i++) {
        const float *a = img.linear + 3 * i, *b = rgb + 3 * i;
        float m = fmaxf(b[0], fmaxf(b[1], b[2]));
        for (int k = 0; k < 3; k++) {
            cr_assert_leq(fabsf(a[k] - b[k]), m / 128.0f, "pixel %d channel %d: %g, want %g", i,
                          k, (double)a[k], (double)b[k]);
            if (b[k] == 0.0f)
                cr_assert_eq(a[k], 0.0f);
        }
    }
    cr_assert_float_eq(img.linear[1], 0.25f, 0.25f / 128.0f);
    image_free(&img);
    /* narrower than 8 pixels: flat scanlines, same rule */
    glint_error err = {0};
    cr_assert_eq(image_write_film(in_dir("n.hdr"), 4, 2, rgb, NULL, &err), GLINT_OK, "%s",
                 err.msg);
    cr_assert_eq(image_load(in_dir("n.hdr"), &img, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(img.width, 4);
    cr_assert_float_eq(img.linear[3], rgb[3], fmaxf(rgb[3], fmaxf(rgb[4], rgb[5])) / 128.0f);
    image_free(&img);
}

/* At quality 95 a smooth image comes back within 12 levels (typically 1-3);
 * quality changes the size. */
Test(image, jpeg_round_trip_within_12_levels_and_quality_matters)
{
    float rgb[FW * FH * 3];
    for (int i = 0; i < FW * FH; i++) {
        rgb[3 * i] = 0.2f + 0.02f * (float)(i % FW);
        rgb[3 * i + 1] = 0.3f + 0.05f * (float)(i / FW);
        rgb[3 * i + 2] = 0.5f;
    }
    write_ok("q95.jpg", rgb, &(glint_write_options){.quality = 95});
    image img = load_ok(in_dir("q95.jpg"));
    uint8_t want[FW * FH * 3];
    image_quantize(rgb, FW * FH * 3, GLINT_TRANSFER_NONE, want);
    for (int i = 0; i < FW * FH * 3; i++)
        cr_assert_leq(abs((int)img.rgb[i] - (int)want[i]), 12, "byte %d: %d, want %d", i,
                      img.rgb[i], want[i]);
    image_free(&img);
    write_ok("q10.jpg", rgb, &(glint_write_options){.quality = 10});
    struct stat a, b;
    cr_assert_eq(stat(in_dir("q95.jpg"), &a), 0);
    cr_assert_eq(stat(in_dir("q10.jpg"), &b), 0);
    cr_assert_lt(b.st_size, a.st_size);
}

/* 16-bit PNG and PPM hold image_quantize16's values exactly (PNG read here
 * with libspng at 16 bits; PPM checked byte by byte, big-endian). */
Test(image, sixteen_bit_png_and_ppm_are_exact)
{
    float rgb[FW * FH * 3];
    film_pattern(rgb, NULL);
    uint16_t want[FW * FH * 3];
    image_quantize16(rgb, FW * FH * 3, GLINT_TRANSFER_SRGB, want);
    glint_write_options o = {.bits = 16, .transfer = GLINT_TRANSFER_SRGB};
    write_ok("w.png", rgb, &o);
    write_ok("w.ppm", rgb, &o);
    size_t n;
    unsigned char *bytes = read_bytes(in_dir("w.png"), &n);
    spng_ctx *ctx = spng_ctx_new(0);
    cr_assert_eq(spng_set_png_buffer(ctx, bytes, n), 0);
    struct spng_ihdr ihdr;
    cr_assert_eq(spng_get_ihdr(ctx, &ihdr), 0);
    cr_assert_eq(ihdr.bit_depth, 16);
    cr_assert_eq(ihdr.color_type, SPNG_COLOR_TYPE_TRUECOLOR);
    static uint8_t px[FW * FH * 6];
    cr_assert_eq(spng_decode_image(ctx, px, sizeof px, SPNG_FMT_PNG, 0), 0);
    spng_ctx_free(ctx);
    for (int i = 0; i < FW * FH * 3; i++) { /* SPNG_FMT_PNG: host-order samples */
        uint16_t v;
        memcpy(&v, px + 2 * i, 2);
        cr_assert_eq(v, want[i], "sample %d: %d, want %d", i, v, want[i]);
    }
    bytes = read_bytes(in_dir("w.ppm"), &n);
    char header[32];
    int h = snprintf(header, sizeof header, "P6\n%d %d\n65535\n", FW, FH);
    cr_assert_eq(n, (size_t)h + sizeof want);
    cr_assert_eq(memcmp(bytes, header, (size_t)h), 0);
    for (int i = 0; i < FW * FH * 3; i++)
        cr_assert_eq(bytes[h + 2 * i] << 8 | bytes[h + 2 * i + 1], want[i]);
    /* and read as a texture, scaled to 8 bits */
    image img = load_ok(in_dir("w.ppm"));
    cr_assert_eq(img.rgb[0], (want[0] * 255 + 32767) / 65535);
    image_free(&img);
}

/* With an alpha plane PNG becomes RGBA (alpha linear, 8 bits) and EXR gets
 * an A channel; RGB is unchanged. */
Test(image, alpha_plane_makes_rgba_png)
{
    float rgb[FW * FH * 3], alpha[FW * FH];
    film_pattern(rgb, alpha);
    write_ok("a.png", rgb, &(glint_write_options){.alpha = alpha});
    size_t n;
    unsigned char *bytes = read_bytes(in_dir("a.png"), &n);
    spng_ctx *ctx = spng_ctx_new(0);
    cr_assert_eq(spng_set_png_buffer(ctx, bytes, n), 0);
    struct spng_ihdr ihdr;
    cr_assert_eq(spng_get_ihdr(ctx, &ihdr), 0);
    cr_assert_eq(ihdr.color_type, SPNG_COLOR_TYPE_TRUECOLOR_ALPHA);
    static uint8_t px[FW * FH * 4];
    cr_assert_eq(spng_decode_image(ctx, px, sizeof px, SPNG_FMT_RGBA8, 0), 0);
    spng_ctx_free(ctx);
    uint8_t want[FW * FH * 3], wa[FW * FH];
    image_quantize(rgb, FW * FH * 3, GLINT_TRANSFER_NONE, want);
    image_quantize(alpha, FW * FH, GLINT_TRANSFER_NONE, wa);
    for (int i = 0; i < FW * FH; i++) {
        for (int k = 0; k < 3; k++)
            cr_assert_eq(px[4 * i + k], want[3 * i + k]);
        cr_assert_eq(px[4 * i + 3], wa[i], "alpha %d: %d, want %d", i, px[4 * i + 3], wa[i]);
    }
    /* EXR with alpha still reads back its RGB exactly */
    write_ok("a.exr", rgb, &(glint_write_options){.alpha = alpha, .bits = 32});
    image img = load_ok(in_dir("a.exr"));
    cr_assert_eq(memcmp(img.linear, rgb, sizeof rgb), 0);
    image_free(&img);
    bytes = read_bytes(in_dir("a.exr"), &n);
    bool has_a = false; /* the channel list names "A", pixel type 2 (float) */
    for (size_t i = 0; i + 6 <= n && !has_a; i++)
        has_a = memcmp(bytes + i, "\0A\0\2\0\0\0", 7) == 0;
    cr_assert(has_a, "no float A channel in the header");
    /* PPM has no alpha: the plane is ignored */
    write_ok("a.ppm", rgb, &(glint_write_options){.alpha = alpha});
    img = load_ok(in_dir("a.ppm"));
    cr_assert_eq(memcmp(img.rgb, want, sizeof want), 0);
    image_free(&img);
}

Test(image, format_option_wins_over_the_extension)
{
    float rgb[FW * FH * 3];
    film_pattern(rgb, NULL);
    write_ok("x.png", rgb, &(glint_write_options){.format = GLINT_FORMAT_PPM});
    size_t n;
    unsigned char *bytes = read_bytes(in_dir("x.png"), &n);
    cr_assert_eq(memcmp(bytes, "P6\n", 3), 0);
    glint_format f;
    glint_error err = {0};
    cr_assert_eq(image_format_parse("JPEG", &f, &err), GLINT_OK);
    cr_assert_eq(f, GLINT_FORMAT_JPEG);
    cr_assert_eq(image_format_parse(".exr", &f, &err), GLINT_OK);
    cr_assert_eq(f, GLINT_FORMAT_EXR);
    cr_assert_eq(image_format_parse("gif", &f, &err), GLINT_ERR_INPUT);
    cr_assert_str_eq(err.msg, "unknown image format 'gif' (use png, ppm, jpg, hdr, pfm or exr)");
}

Test(image, impossible_options_are_refused_before_writing)
{
    static const struct {
        const char *name;
        glint_write_options o;
        const char *msg;
    } cases[] = {
        {"a.jpg", {.bits = 16}, "16 bits per channel is not possible in .jpg"},
        {"a.png", {.bits = 32}, "32 bits per channel is not possible in .png"},
        {"a.exr", {.bits = 8}, "8 bits per channel is not possible in .exr"},
        {"a.hdr", {.bits = 16}, "16 bits per channel is not possible in .hdr"},
        {"a.jpg", {.quality = 101}, "JPEG quality must be 1 to 100 (got 101)"},
        {"a.png", {.transfer = (glint_transfer)7}, "unknown transfer function 7"},
        {"a.png", {.format = (glint_format)42}, "unknown format code 42"},
    };
    float rgb[FW * FH * 3];
    film_pattern(rgb, NULL);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        glint_error err = {0};
        const char *path = in_dir(cases[i].name);
        expect_error(image_write_check(path, &cases[i].o, &err), &err, GLINT_ERR_INPUT, path);
        cr_assert_not_null(strstr(err.msg, cases[i].msg), "%s", err.msg);
        expect_error(image_write_film(path, FW, FH, rgb, &cases[i].o, &err), &err,
                     GLINT_ERR_INPUT, path);
    }
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 0, "files left: %s", listing);
}

/* ---- decoder errors ----------------------------------------------------- */

/* Each format cut short says so, naming the file. */
Test(image, truncated_files_say_file_is_truncated)
{
    float rgb[FW * FH * 3];
    film_pattern(rgb, NULL);
    const char *names[] = {"t.png", "t.jpg", "t.hdr", "t.pfm", "t.ppm", "t.exr"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        write_ok(names[i], rgb, NULL);
        size_t n;
        unsigned char *bytes = read_bytes(in_dir(names[i]), &n);
        char cut[64];
        snprintf(cut, sizeof cut, "cut-%s", names[i]);
        write_bytes(in_dir(cut), bytes, n * 3 / 4);
        image img = {0};
        glint_error err = {0};
        const char *path = in_dir(cut);
        expect_error(image_load(path, &img, &err), &err, GLINT_ERR_INPUT, path);
        char want[600];
        snprintf(want, sizeof want, "%s: file is truncated", path);
        cr_expect_str_eq(err.msg, want, "%s", names[i]);
        cr_assert_null(img.rgb);
        cr_assert_null(img.linear);
    }
}

/* Headers claiming 30000x30000 pixels are refused from the header alone,
 * before any pixel memory is asked for. */
Test(image, decompression_bombs_are_refused_by_their_header)
{
    const char *want = "bomb: image 30000x30000 is too large (limit 268435456 pixels)";
    image img = {0};
    glint_error err = {0};
    /* PNG: signature and IHDR with a correct CRC, nothing else */
    uint8_t png[33] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                       0, 0, 0x75, 0x30, 0, 0, 0x75, 0x30, 8, 2, 0, 0, 0};
    bytebuf b = {0};
    cr_assert(bytes_append(&b, png, 29));
    uint32_t crc = 0xffffffffu; /* CRC-32 of type and data (PNG annex D) */
    for (int i = 12; i < 29; i++) {
        crc ^= png[i];
        for (int k = 0; k < 8; k++)
            crc = crc & 1 ? 0xedb88320u ^ (crc >> 1) : crc >> 1;
    }
    crc ^= 0xffffffffu;
    uint8_t c[4] = {(uint8_t)(crc >> 24), (uint8_t)(crc >> 16), (uint8_t)(crc >> 8), (uint8_t)crc};
    cr_assert(bytes_append(&b, c, 4));
    cr_assert_eq(image_load_memory(b.data, b.len, "bomb", &img, &err), GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, want);
    bytes_free(&b);
    /* JPEG: a real file whose frame header (SOF0) is made to claim it */
    float rgb[FW * FH * 3];
    film_pattern(rgb, NULL);
    write_ok("small.jpg", rgb, NULL);
    size_t n;
    unsigned char *jpg = read_bytes(in_dir("small.jpg"), &n);
    size_t sof = 2;
    while (sof + 9 < n && !(jpg[sof] == 0xff && jpg[sof + 1] == 0xc0))
        sof++;
    cr_assert_lt(sof + 9, n, "no SOF0 marker");
    jpg[sof + 5] = jpg[sof + 7] = 0x75; /* height and width: 0x7530 = 30000 */
    jpg[sof + 6] = jpg[sof + 8] = 0x30;
    cr_assert_eq(image_load_memory(jpg, n, "bomb", &img, &err), GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, want);
    const char hdr[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 30000 +X 30000\n";
    cr_assert_eq(image_load_memory(hdr, sizeof hdr - 1, "bomb", &img, &err), GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, want);
    const char pfm[] = "PF\n30000 30000\n-1.0\n";
    cr_assert_eq(image_load_memory(pfm, sizeof pfm - 1, "bomb", &img, &err), GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, want);
    const char ppm[] = "P6\n30000 30000\n255\n";
    cr_assert_eq(image_load_memory(ppm, sizeof ppm - 1, "bomb", &img, &err), GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, want);
    cr_assert_null(img.rgb);
    cr_assert_null(img.linear);
}

Test(image, not_an_image_says_which_formats_are_read)
{
    const char text[] = "hello, world\n";
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load_memory(text, sizeof text - 1, "t.png", &img, &err), GLINT_ERR_INPUT);
    cr_assert_str_eq(err.msg, "t.png: not an image glint reads (PNG, JPEG, HDR, EXR, PFM, PPM, "
                              "BMP, TGA, GIF)");
}

/* A FIFO would block a plain open for ever: it is refused at once. */
Test(image, a_fifo_is_not_a_regular_file)
{
    const char *path = in_dir("pipe.png");
    cr_assert_eq(mkfifo(path, 0600), 0);
    image img = {0};
    glint_error err = {0};
    expect_error(image_load(path, &img, &err), &err, GLINT_ERR_INPUT, path);
    cr_assert_not_null(strstr(err.msg, "not a regular file"), "%s", err.msg);
    unlink(path);
}

/* ---- the atomic writer -------------------------------------------------- */

static mode_t mode_of(const char *path)
{
    struct stat st;
    cr_assert_eq(lstat(path, &st), 0, "%s", path);
    return st.st_mode;
}

/* A symbolic link (absolute, relative, chained) stays a link; the file it
 * names gets the image; nothing else appears. */
Test(image, writes_go_through_symbolic_links)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    char real[512];
    snprintf(real, sizeof real, "%s", in_dir("real.png"));
    write_bytes(real, "old", 3);
    cr_assert_eq(symlink(real, in_dir("abs.png")), 0);
    cr_assert_eq(symlink("abs.png", in_dir("rel.png")), 0);
    glint_error err = {0};
    cr_assert_eq(write_rgb8(in_dir("rel.png"), 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    cr_assert(S_ISLNK(mode_of(in_dir("rel.png"))));
    cr_assert(S_ISLNK(mode_of(in_dir("abs.png"))));
    cr_assert(S_ISREG(mode_of(real)));
    image img = {0};
    cr_assert_eq(image_load(real, &img, &err), GLINT_OK, "%s", err.msg);
    expect_pixels(&img, 7, 5, rgb);
    image_free(&img);
    /* a dangling link: the file it names is created */
    cr_assert_eq(symlink("new.png", in_dir("dangling.png")), 0);
    cr_assert_eq(write_rgb8(in_dir("dangling.png"), 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    cr_assert(S_ISLNK(mode_of(in_dir("dangling.png"))));
    cr_assert(S_ISREG(mode_of(in_dir("new.png"))));
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 5, "files: %s", listing);
}

Test(image, an_existing_file_keeps_its_mode)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    const char *path = in_dir("private.png");
    write_bytes(path, "old", 3);
    cr_assert_eq(chmod(path, 0600), 0);
    glint_error err = {0};
    cr_assert_eq(write_rgb8(path, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(mode_of(path) & 07777, 0600);
    cr_assert_eq(chmod(path, 0640), 0);
    cr_assert_eq(write_rgb8(path, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(mode_of(path) & 07777, 0640);
    /* a new file gets 0666 less the umask */
    mode_t mask = umask(022);
    cr_assert_eq(write_rgb8(in_dir("fresh.png"), 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    umask(mask);
    cr_assert_eq(mode_of(in_dir("fresh.png")) & 07777, 0644);
}

/* A file with a second hard link is replaced under the name written (the
 * write is atomic: a new file is renamed over it); the other name keeps
 * the old contents, as README.md says. */
Test(image, a_hard_linked_file_is_replaced_under_its_name_only)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    const char *path = in_dir("linked.png"), *other = in_dir("other.png");
    write_bytes(path, "old", 3);
    cr_assert_eq(link(path, other), 0);
    glint_error err = {0};
    cr_assert_eq(write_rgb8(path, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    size_t n;
    unsigned char *bytes = read_bytes(other, &n);
    cr_expect(n == 3 && memcmp(bytes, "old", 3) == 0, "the other name is left alone");
    image img;
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    cr_expect_eq(img.width, 7);
    image_free(&img);
    unlink(other);
}

/* Like cp, a file without write permission is not replaced, even by root. */
Test(image, a_read_only_file_is_refused_and_kept)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    const char *path = in_dir("locked.png");
    write_bytes(path, "old", 3);
    cr_assert_eq(chmod(path, 0444), 0);
    glint_error err = {0};
    expect_error(write_rgb8(path, 7, 5, rgb, &err), &err, GLINT_ERR_INPUT, path);
    char want[600];
    snprintf(want, sizeof want, "%s: file is read-only (mode 0444)", path);
    cr_assert_str_eq(err.msg, want);
    expect_error(image_write_check(path, NULL, &err), &err, GLINT_ERR_INPUT, path);
    size_t n;
    unsigned char *bytes = read_bytes(path, &n);
    cr_assert(n == 3 && memcmp(bytes, "old", 3) == 0);
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 1, "files: %s", listing);
}

/* The write itself fails (a file size limit stands in for a full disk):
 * the old file is untouched and no temporary file is left. */
Test(image, a_failed_write_leaves_the_old_file_and_no_temporary)
{
    static uint8_t big[64 * 64 * 3];
    for (size_t i = 0; i < sizeof big; i++)
        big[i] = (uint8_t)(i * 7919 % 251);
    const char *path = in_dir("keep.png");
    write_bytes(path, "old", 3);
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit lim = {256, 256};
    cr_assert_eq(setrlimit(RLIMIT_FSIZE, &lim), 0);
    glint_error err = {0};
    expect_error(write_rgb8(path, 64, 64, big, &err), &err, GLINT_ERR_IO, path);
    cr_assert_not_null(strstr(err.msg, "File too large"), "%s", err.msg);
    size_t n;
    unsigned char *bytes = read_bytes(path, &n);
    cr_assert(n == 3 && memcmp(bytes, "old", 3) == 0);
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 1, "files left: %s", listing);
}

/* Devices are written directly and their errors reported. */
Test(image, dev_full_fails_with_no_space)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    glint_error err = {0};
    expect_error(write_rgb8("/dev/full", 7, 5, rgb, &err), &err, GLINT_ERR_IO, "/dev/full");
    cr_assert_not_null(strstr(err.msg, "No space left on device"), "%s", err.msg);
    cr_assert_eq(symlink("/dev/full", in_dir("full.png")), 0);
    expect_error(write_rgb8(in_dir("full.png"), 7, 5, rgb, &err), &err, GLINT_ERR_IO,
                 in_dir("full.png"));
    cr_assert(S_ISLNK(mode_of(in_dir("full.png"))));
    cr_assert_eq(write_rgb8("/dev/null", 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
}

/* The temporary name is short, so a name near NAME_MAX (255) works; one
 * over it is refused by the check before anything is written. */
Test(image, long_output_names)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    char name[300];
    memset(name, 'n', 242);
    strcpy(name + 242, ".png"); /* 246 bytes */
    glint_error err = {0};
    cr_assert_eq(write_rgb8(in_dir(name), 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
    memset(name, 'n', 252);
    strcpy(name + 252, ".png"); /* 256 bytes */
    const char *path = in_dir(name);
    expect_error(image_write_check(path, NULL, &err), &err, GLINT_ERR_INPUT, path);
    cr_assert_not_null(strstr(err.msg, "file name is too long"), "%s", err.msg);
    char listing[600];
    cr_assert_eq(list_dir(listing, sizeof listing), 1, "files: %s", listing);
}

/* ---- checks before a render --------------------------------------------- */

Test(image, output_checks_name_the_problem)
{
    glint_error err = {0};
    cr_assert_eq(mkdir(in_dir("sub"), 0755), 0);
    const char *sub = in_dir("sub");
    expect_error(image_write_check(sub, NULL, &err), &err, GLINT_ERR_INPUT, sub);
    cr_assert(strstr(err.msg, "is a directory"), "%s", err.msg);
    const char *missing = in_dir("nope/x.png");
    expect_error(image_write_check(missing, NULL, &err), &err, GLINT_ERR_INPUT, missing);
    cr_assert(strstr(err.msg, "does not exist"), "%s", err.msg);
    const char *gif = in_dir("x.gif");
    expect_error(image_write_check(gif, NULL, &err), &err, GLINT_ERR_INPUT, gif);
    write_bytes(in_dir("file"), "x", 1);
    const char *under_file = in_dir("file/x.png");
    expect_error(image_write_check(under_file, NULL, &err), &err, GLINT_ERR_INPUT, under_file);
    cr_assert_eq(image_write_check(in_dir("ok.png"), NULL, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(image_write_check("-", NULL, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(image_write_check("/dev/null", NULL, &err), GLINT_OK, "%s", err.msg);
    /* the checks leave nothing behind */
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 2, "files: %s", listing);
}

/* A folder without write permission (root ignores the bits, so the test
 * only runs where they bind). */
Test(image, a_read_only_folder_is_refused)
{
    cr_assert_eq(mkdir(in_dir("ro"), 0555), 0);
    const char *path = in_dir("ro/x.png");
    glint_error err = {0};
    int fd = open(in_dir("ro/probe"), O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd >= 0) {
        close(fd);
        unlink(in_dir("ro/probe"));
        rmdir(in_dir("ro"));
        cr_skip_test("permission bits do not bind here (running as root)");
    }
    expect_error(image_write_check(path, NULL, &err), &err, GLINT_ERR_INPUT, path);
    cr_assert(strstr(err.msg, "Permission denied"), "%s", err.msg);
    rmdir(in_dir("ro"));
}

/* ---- inputs found by fuzzing (fuzz/fuzz_texture.c) ---------------------- */

/* A 34-byte run-length TGA declaring 8248x22571 pixels (under the pixel
 * limit) kept stb_image decoding for seconds: a header claiming more pixels
 * than its bytes can encode is refused at once. */
Test(image, fuzz_tiny_tga_claiming_186_megapixels_is_truncated)
{
    static const uint8_t tga[34] = {
        0x00, 0x00, 0x0a, 0x00, 0x00, 0xa4, 0x29, 0x75, 0x39, 0x2d, 0x59, 0x20,
        0x38, 0x20, 0x2b, 0x58, 0x20, 0x38, 0x0a, 0x8c, 0xcc, 0x50, 0x66, 0x0a,
        0x90, 0xdc, 0xa0, 0x44, 0xb0, 0x54, 0x18, 0x64, 0x28, 0xec};
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load_memory(tga, sizeof tga, "t.tga", &img, &err), GLINT_ERR_INPUT);
    cr_assert_str_eq(err.msg, "t.tga: file is truncated");
    /* the same for a Radiance header over a few bytes of runs */
    const char hdr[] = "#?RADIANCE\n\n-Y 8000 +X 8000\n\x02\x02\x1f\x40\xff\x00";
    cr_assert_eq(image_load_memory(hdr, sizeof hdr - 1, "t.hdr", &img, &err), GLINT_ERR_INPUT);
    cr_assert_str_eq(err.msg, "t.hdr: file is truncated");
}

/* An OpenEXR file with channels G, R and one named "\xc0": OpenEXR 3.1
 * crashed (a NULL destination) when the unused channel was left unbound.
 * Every channel is decoded, the unused ones into scratch; R and G come
 * through and B stays 0. */
Test(image, fuzz_exr_with_an_unknown_channel_decodes)
{
    static const uint8_t exr[441] = {
        0x76, 0x2f, 0x31, 0x01, 0x02, 0x00, 0x00, 0x00, 0x74, 0x79, 0x70, 0x65,
        0x00, 0x73, 0x74, 0x72, 0x69, 0x6e, 0x67, 0x00, 0x0d, 0x00, 0x00, 0x00,
        0x73, 0x63, 0x61, 0x6e, 0x6c, 0x69, 0x6e, 0x65, 0x69, 0x6d, 0x61, 0x67,
        0x65, 0x6e, 0x61, 0x6d, 0x65, 0x00, 0x73, 0x74, 0x72, 0x69, 0x6e, 0x67,
        0x00, 0x03, 0x00, 0x00, 0x00, 0x72, 0x67, 0x62, 0x63, 0x6f, 0x6d, 0x70,
        0x72, 0x65, 0x73, 0x73, 0x69, 0x6f, 0x6e, 0x00, 0x63, 0x6f, 0x6d, 0x70,
        0x72, 0x65, 0x73, 0x73, 0x69, 0x6f, 0x6e, 0x00, 0x01, 0x00, 0x00, 0x00,
        0x03, 0x64, 0x61, 0x74, 0x61, 0x57, 0x69, 0x6e, 0x64, 0x6f, 0x77, 0x00,
        0x62, 0x6f, 0x78, 0x32, 0x69, 0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0f, 0x00, 0x00, 0x00, 0x0b, 0x00,
        0x00, 0x00, 0x64, 0x69, 0x73, 0x70, 0x6c, 0x61, 0x79, 0x57, 0x69, 0x6e,
        0x64, 0x6f, 0x77, 0x00, 0x62, 0x6f, 0x78, 0x32, 0x69, 0x00, 0x10, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0f, 0x00,
        0x00, 0x00, 0x0b, 0x00, 0x00, 0x00, 0x6c, 0x69, 0x6e, 0x65, 0x4f, 0x72,
        0x64, 0x65, 0x72, 0x00, 0x6c, 0x69, 0x6e, 0x65, 0x4f, 0x72, 0x64, 0x65,
        0x72, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x70, 0x69, 0x78, 0x65, 0x6c,
        0x41, 0x73, 0x70, 0x65, 0x63, 0x74, 0x52, 0x61, 0x74, 0x69, 0x6f, 0x00,
        0x66, 0x6c, 0x6f, 0x61, 0x74, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x80, 0x3f, 0x73, 0x63, 0x72, 0x65, 0x65, 0x6e, 0x57, 0x69, 0x6e, 0x64,
        0x6f, 0x77, 0x43, 0x65, 0x6e, 0x74, 0x65, 0x72, 0x00, 0x76, 0x32, 0x66,
        0x00, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x73, 0x63, 0x72, 0x65, 0x65, 0x6e, 0x57, 0x69, 0x6e, 0x64, 0x6f,
        0x77, 0x57, 0x69, 0x64, 0x74, 0x68, 0x00, 0x66, 0x6c, 0x6f, 0x61, 0x74,
        0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x63, 0x68, 0x61,
        0x6e, 0x6e, 0x65, 0x6c, 0x73, 0x00, 0x63, 0x68, 0x6c, 0x69, 0x73, 0x74,
        0x00, 0x37, 0x00, 0x00, 0x00, 0xc0, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01,
        0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x47,
        0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00,
        0x00, 0x01, 0x00, 0x00, 0x00, 0x52, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01,
        0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x71, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x40, 0x00, 0x00, 0x00, 0x78, 0x9c, 0x63, 0x68, 0x20, 0x12, 0x30,
        0x40, 0xc1, 0xa8, 0xfa, 0x51, 0xf5, 0x68, 0xea, 0xf7, 0x00, 0xb1, 0x0b,
        0x94, 0xae, 0x40, 0x53, 0xe6, 0xb3, 0xa6, 0xa5, 0xa9, 0xa9, 0x11, 0x08,
        0x1a, 0x20, 0xd0, 0x75, 0x90, 0xa9, 0x6f, 0x44, 0x52, 0x0b, 0xa2, 0xb7,
        0xd0, 0x58, 0xfd, 0x61, 0x34, 0xf5, 0xb6, 0x14, 0xaa, 0x47, 0xf7, 0x6f,
        0xfb, 0x10, 0x53, 0x0f, 0x00, 0x68, 0x7f, 0x0f, 0xda,
    };
    image img = {0};
    glint_error err = {0};
    glint_rc rc = image_load_memory(exr, sizeof exr, "t.exr", &img, &err);
    cr_assert_eq(rc, GLINT_OK, "%s", err.msg);
    cr_expect_eq(img.width, 16);
    cr_expect_eq(img.height, 12);
    cr_assert_not_null(img.linear);
    float blue = 0.0f;
    for (int i = 0; i < img.width * img.height; i++)
        blue = fmaxf(blue, fabsf(img.linear[3 * i + 2]));
    cr_expect_eq(blue, 0.0f, "no B channel");
    image_free(&img);
}

/* A 29-byte PNG (a header and nothing else) declaring 16x5570572 pixels:
 * 267 MB were allocated and cleared before the missing data was noticed,
 * which took the fuzzer past its time limit under AddressSanitizer. The
 * pixels a PNG of n bytes can hold (deflate at most 1032:1, 8 pixels a
 * byte) are checked from the header first. */
Test(image, fuzz_png_header_without_data_is_truncated_before_allocating)
{
    static const uint8_t png[29] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
        0x52, 0x00, 0x00, 0x00, 0x10, 0x00, 0x55, 0x00, 0x0c, 0x08, 0x02, 0x00, 0x00, 0x00};
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load_memory(png, sizeof png, "t.png", &img, &err), GLINT_ERR_INPUT);
    cr_assert_str_eq(err.msg, "t.png: file is truncated");
    cr_assert_null(img.rgb);
}

/* Ctrl-C or kill while the temporary file existed left a .glint-* file
 * beside the target. A child writes 4 MB over and over and is killed at
 * once each time: the signals wait until the temporary file is renamed or
 * removed, so only the target is ever left. (Before, nearly every kill
 * landed while the temporary file was being written.) */
Test(image, a_signal_during_a_write_leaves_no_temporary_file)
{
    const size_t n = 4u << 20;
    uint8_t *data = malloc(n);
    cr_assert_not_null(data);
    memset(data, 0x5a, n);
    const char *target = in_dir("big.bin");
    const int signals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
    for (int round = 0; round < 12; round++) {
        int ready[2];
        cr_assert_eq(pipe(ready), 0);
        pid_t pid = fork();
        cr_assert_geq(pid, 0);
        if (pid == 0) {
            struct rlimit no_core = {0, 0};
            setrlimit(RLIMIT_CORE, &no_core);
            glint_error err = {0};
            for (int i = 0;; i++) {
                if (file_write(target, data, n, &err) != GLINT_OK)
                    _exit(3);
                if (i == 0 && write(ready[1], "x", 1) != 1)
                    _exit(4);
            }
        }
        close(ready[1]);
        char c;
        cr_assert_eq(read(ready[0], &c, 1), 1, "the child wrote once");
        close(ready[0]);
        int sig = signals[round % 4];
        kill(pid, sig);
        int status;
        cr_assert_eq(waitpid(pid, &status, 0), pid);
        cr_assert(WIFSIGNALED(status) && WTERMSIG(status) == sig, "status %d", status);
        char names[512];
        int count = list_dir(names, sizeof names);
        cr_assert_eq(count, 1, "round %d left: %s", round, names);
        cr_assert_str_eq(names, "big.bin ");
    }
    remove(target);
    free(data);
}

/* A 245-byte JPEG declaring 2576x20534 pixels whose coded data stops at
 * an end-of-image marker: libjpeg filled 53 million pixels with grey, and
 * the fuzzer ran out of time. Huffman-coded JPEG spends at least a bit on
 * each 8x8 block, so the header alone shows the file is short; and a
 * marker met inside the coded data is truncation too (a real file cut in
 * half and closed with an end-of-image marker). */
Test(image, fuzz_jpeg_ending_early_at_a_marker_is_truncated)
{
    static const uint8_t jpg[245] = {
        0xff, 0xd8, 0xff, 0xe0, 0x00, 0x10, 0x4a, 0x46, 0x49, 0x46, 0x00, 0x01,
        0x01, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0xff, 0xdb, 0x00, 0x43,
        0x00, 0x08, 0x06, 0x23, 0x3f, 0x41, 0x0a, 0x0a, 0x2d, 0x59, 0x36, 0x20,
        0x2b, 0x58, 0x20, 0x34, 0x0a, 0xff, 0xc0, 0x40, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0x00, 0x80, 0x1c, 0x1c, 0x20,
        0x24, 0x2e, 0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0x00, 0x80,
        0x1c, 0x1c, 0x20, 0x24, 0x2e, 0x27, 0x20, 0x22, 0x2c, 0x23, 0x1c, 0x1c,
        0x28, 0x37, 0x29, 0x2c, 0x30, 0x31, 0x34, 0x34, 0x34, 0x1f, 0x27, 0x39,
        0x3d, 0x38, 0x32, 0x3c, 0x2e, 0x33, 0x34, 0x32, 0xff, 0xdb, 0x00, 0x43,
        0x01, 0x09, 0x09, 0x09, 0x0c, 0x0b, 0x0c, 0x18, 0x0d, 0x0d, 0x18, 0x32,
        0x21, 0x1c, 0x21, 0x32, 0x32, 0x32, 0x32, 0x32, 0x32, 0x32, 0x32, 0x30,
        0x30, 0x30, 0x30, 0x30, 0x30, 0x30, 0x30, 0x30, 0x30, 0x30, 0x30, 0x30,
        0x38, 0x32, 0x38, 0x39, 0x34, 0x33, 0x34, 0x30, 0x33, 0x33, 0x35, 0x34,
        0x30, 0x36, 0x32, 0x31, 0x31, 0x39, 0x39, 0x50, 0x35, 0x20, 0x20, 0x32,
        0x32, 0x32, 0x32, 0x32, 0x32, 0xff, 0xc0, 0x00, 0x11, 0x08, 0x50, 0x36,
        0x0a, 0x10, 0x03, 0x01, 0x22, 0x00, 0x02, 0x11, 0x01, 0x03, 0x11, 0x01,
        0x07, 0x08, 0xc3, 0xc4, 0xc5, 0xc6, 0xc7, 0xc8, 0xc9, 0xca, 0xd2, 0xd3,
        0xd4, 0xd5, 0xd6, 0xd7, 0xd8, 0xf6, 0xf7, 0xf8, 0xf9, 0xfa, 0xff, 0xda,
        0x00, 0x0c, 0x03, 0x01, 0x00, 0x02, 0x11, 0x03, 0x11, 0x00, 0x3f, 0x00,
        0xc0, 0x6a, 0x6a, 0x6a, 0x6a, 0x6a, 0x6a, 0x6a, 0x6a, 0x6a, 0x6a, 0x6a,
        0xaf, 0xe2, 0x7f, 0xff, 0xd9,
    };
    image img = {0};
    glint_error err = {0};
    cr_assert_eq(image_load_memory(jpg, sizeof jpg, "t.jpg", &img, &err), GLINT_ERR_INPUT);
    cr_assert_str_eq(err.msg, "t.jpg: file is truncated");
    cr_assert_null(img.rgb);

    float rgb[FW * FH * 3];
    film_pattern(rgb, NULL);
    write_ok("whole.jpg", rgb, NULL);
    size_t n;
    unsigned char *bytes = read_bytes(in_dir("whole.jpg"), &n);
    bytes[n / 2] = 0xff; /* cut in the coded data and closed */
    bytes[n / 2 + 1] = 0xd9;
    cr_assert_eq(image_load_memory(bytes, n / 2 + 2, "half.jpg", &img, &err), GLINT_ERR_INPUT);
    cr_expect_str_eq(err.msg, "half.jpg: file is truncated");
    cr_assert_null(img.rgb);
}
