/* Image files (src/io/image.h): PNG and PPM written by the project's
 * writer read back exactly; BMP and JPEG written here with stb_image_write
 * (the library's, linked from libstb: src/io/image.c only includes the
 * header, so no implementation is defined here either) read back through
 * the project's loader, BMP exactly and JPEG within 12 levels on a smooth
 * image; failures give GLINT_ERR_* codes with messages that start with the
 * file's name; the atomic writer leaves no temporary file behind; and the
 * 8-bit transfer tables.
 *
 * Every test works in its own mkdtemp directory, removed afterwards. */
#include <criterion/criterion.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stb_image_write.h>

#include "io/image.h"
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
    cr_assert_eq(image_write(path, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
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
    cr_assert_eq(image_write(path, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
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
    cr_assert_eq(image_write(good, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
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
    cr_assert_not_null(strstr(err.msg, "16384x17000 is out of range"), "%s", err.msg);
    cr_assert_null(img.rgb);
}

Test(image, unsupported_output_extension_is_an_error)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    const char *names[] = {"out.gif", "out.jpg", "out", "out.png.bak"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        const char *path = in_dir(names[i]);
        glint_error err = {0};
        expect_error(image_write(path, 7, 5, rgb, &err), &err, GLINT_ERR_INPUT, path);
    }
    /* a dot in a folder name is not an extension */
    cr_assert_eq(mkdir(in_dir("a.png"), 0755), 0);
    const char *path = in_dir("a.png/out");
    glint_error err = {0};
    expect_error(image_write(path, 7, 5, rgb, &err), &err, GLINT_ERR_INPUT, path);
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
    expect_error(image_write(path, 7, 5, rgb, &err), &err, GLINT_ERR_IO, path);
    char listing[256];
    cr_assert_eq(list_dir(listing, sizeof listing), 0, "files left: %s", listing);
}

/* The temporary file is made and written, but the rename onto a folder
 * fails: it must be removed, and the folder left as it was. */
Test(image, failed_rename_removes_the_temporary_file)
{
    uint8_t rgb[7 * 5 * 3];
    test_pattern(rgb);
    const char *path = in_dir("busy.png");
    cr_assert_eq(mkdir(path, 0755), 0);
    glint_error err = {0};
    expect_error(image_write(path, 7, 5, rgb, &err), &err, GLINT_ERR_IO, path);
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
    cr_assert_eq(image_write(path, 64, 64, big, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(image_write(path, 7, 5, rgb, &err), GLINT_OK, "%s", err.msg);
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
