/* The preview window for real, under a private Xvfb (tests/xvfb-preview.sh):
 * the window's pixels are the PNG the same run writes, which is the batch
 * image byte for byte; a scripted left-drag orbits the camera and changes
 * the picture, P prints the camera as YAML, Esc closes the window with no
 * render thread left; without a display -p renders to the file. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "glint.h"
#include "io/image.h"
#include "tmpdir.h"
#include "glint_run.h"

static void setup(void) { tmpdir_make("preview"); }

TestSuite(preview, .init = setup, .fini = tmpdir_remove, .timeout = 240);

static void drive(const char *mode, const char *args)
{
    const char *bin = getenv("GLINT_BIN");
    cr_assert_not_null(bin, "GLINT_BIN must name the glint binary");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "'%s/tests/xvfb-preview.sh' %s '%s' '%s%s%s' %s", GLINT_SOURCE_DIR,
             mode, dir, bin[0] == '/' ? "" : GLINT_SOURCE_DIR, bin[0] == '/' ? "" : "/", bin, args);
    cr_assert_eq(system(cmd), 0, "%s", cmd);
}

static image load(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    image img;
    glint_error err = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    return img;
}

/* The window's rectangle, from the screenshot's folder. */
static void geometry(int *x, int *y, int *w, int *h)
{
    size_t n;
    char *g = (char *)dir_read("geometry", &n);
    cr_assert_eq(sscanf(g, "%d %d %d %d", x, y, w, h), 4, "geometry: %s", g);
    free(g);
}

/* Pixels of the screenshot inside the window that differ from img. */
static long window_differs(const image *screen, const image *img)
{
    int x0, y0, w, h;
    geometry(&x0, &y0, &w, &h);
    cr_assert(w == img->width && h == img->height, "window %dx%d, image %dx%d", w, h,
              img->width, img->height);
    cr_assert(x0 >= 0 && y0 >= 0 && x0 + w <= screen->width && y0 + h <= screen->height);
    long diff = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            diff += memcmp(screen->rgb + ((size_t)(y0 + y) * screen->width + (size_t)(x0 + x)) * 3,
                           img->rgb + ((size_t)y * img->width + (size_t)x) * 3, 3) != 0;
    return diff;
}

static int exit_code(void)
{
    size_t n;
    char *c = (char *)dir_read("code", &n);
    int code = atoi(c);
    free(c);
    return code;
}

Test(preview, window_shows_the_written_image_which_is_the_batch_image)
{
    drive("final", "-r 160x120 -s 4 -o shot.png");
    cr_assert_eq(exit_code(), 0);
    image screen = load("screen1.ppm"), shot = load("shot.png");
    long diff = window_differs(&screen, &shot);
    cr_expect_eq(diff, 0, "%ld window pixels differ from the written PNG", diff);
    char out[4096];
    cr_assert_eq(glint_run("", "-q -r 160x120 -s 4 -o batch.png", out, sizeof out), 0, "%s", out);
    cr_expect(dir_same("shot.png", "batch.png"), "the preview's final image is not the batch image");
    image_free(&screen);
    image_free(&shot);
}

Test(preview, scripted_orbit_changes_the_picture_and_closes_cleanly)
{
    drive("orbit", "-r 160x120 -s 1 -o o.png");
    cr_expect_eq(exit_code(), 0);
    image a = load("screen1.ppm"), b = load("screen2.ppm");
    int x0, y0, w, h;
    geometry(&x0, &y0, &w, &h);
    image before = {w, h, malloc((size_t)w * (size_t)h * 3), NULL};
    for (int y = 0; y < h; y++)
        memcpy(before.rgb + (size_t)y * (size_t)w * 3,
               a.rgb + ((size_t)(y0 + y) * (size_t)a.width + (size_t)x0) * 3, (size_t)w * 3);
    long diff = window_differs(&b, &before);
    cr_expect_gt(diff, w * h / 10, "only %ld of %d pixels changed after the orbit", diff, w * h);
    size_t n;
    char *log = (char *)dir_read("log", &n), *out = (char *)dir_read("out", &n);
    cr_expect(strstr(out, "camera:\n  eye: ["), "P prints the camera: %s", out);
    cr_expect(!strstr(out, "eye: [0, 0, 0]"), "the orbit moved the eye: %s", out);
    int t0 = -1, t1 = -2;
    const char *t = strstr(log, "preview: threads ");
    cr_assert_not_null(t, "%s", log);
    cr_expect_eq(sscanf(t, "preview: threads %d before the render thread, %d after it", &t0, &t1), 2);
    cr_expect_eq(t0, t1, "a thread outlived the window: %s", log);
    free(log);
    free(out);
    image_free(&a);
    image_free(&b);
    image_free(&before);
}

/* The window's pixels in a screenshot, as an image of their own. */
static image crop(const image *screen)
{
    int x0, y0, w, h;
    geometry(&x0, &y0, &w, &h);
    image out = {w, h, malloc((size_t)w * (size_t)h * 3), NULL};
    for (int y = 0; y < h; y++)
        memcpy(out.rgb + (size_t)y * (size_t)w * 3,
               screen->rgb + ((size_t)(y0 + y) * (size_t)screen->width + (size_t)x0) * 3,
               (size_t)w * 3);
    return out;
}

Test(preview, reloads_when_an_included_file_changes_and_keeps_the_image_on_errors)
{
    dir_put("scene.yaml", "image: {width: 96, height: 64}\n"
                          "camera: {eye: [0, 1, 6], look_at: [0, 0.5, 0], fov: 50}\n"
                          "include: parts.yaml\n"
                          "lights: [{type: point, position: [4, 6, 5]}]\n");
    dir_put("parts.yaml", "objects: [{type: sphere, center: [0, 0.5, 0], radius: 1, "
                          "material: {color: [0.9, 0.1, 0.1]}}]\n");
    dir_put("blue.yaml", "objects: [{type: sphere, center: [0, 0.5, 0], radius: 1, "
                         "material: {color: [0.1, 0.1, 0.9]}}]\n");
    dir_put("wrong.yaml", "objects: [{type: sphere, center: [0, 0.5, 0], radius: -1}]\n");
    const char *args = "EDIT1='cp blue.yaml parts.yaml' EDIT2='cp wrong.yaml parts.yaml'";
    const char *bin = getenv("GLINT_BIN");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s '%s/tests/xvfb-preview.sh' watch '%s' '%s%s%s' scene.yaml -o w.png",
             args, GLINT_SOURCE_DIR, dir, bin[0] == '/' ? "" : GLINT_SOURCE_DIR,
             bin[0] == '/' ? "" : "/", bin);
    cr_assert_eq(system(cmd), 0, "%s", cmd);
    cr_expect_eq(exit_code(), 0);
    image s1 = load("screen1.ppm"), s2 = load("screen2.ppm"), s3 = load("screen3.ppm");
    image red = crop(&s1), blue = crop(&s2);
    int w = red.width, h = red.height;
    cr_expect_gt(window_differs(&s2, &red), w * h / 20, "the colour change shows");
    cr_expect_eq(window_differs(&s3, &blue), 0, "a scene with errors keeps the last image");
    /* the centre pixel went from red to blue */
    const unsigned char *c1 = red.rgb + ((size_t)(h / 2) * (size_t)w + (size_t)(w / 2)) * 3;
    const unsigned char *c2 = blue.rgb + ((size_t)(h / 2) * (size_t)w + (size_t)(w / 2)) * 3;
    cr_expect(c1[0] > c1[2] && c2[2] > c2[0], "centre %d,%d,%d then %d,%d,%d", c1[0], c1[1], c1[2],
              c2[0], c2[1], c2[2]);
    size_t n;
    char *log = (char *)dir_read("log", &n);
    cr_expect(strstr(log, "glint: reloaded scene.yaml\n"), "%s", log);
    cr_expect(strstr(log, "glint: parts.yaml:1:"), "the error names the file: %s", log);
    cr_expect(strstr(log, "radius must be > 0"), "%s", log);
    free(log);
    image_free(&s1);
    image_free(&s2);
    image_free(&s3);
    image_free(&red);
    image_free(&blue);
}

Test(preview, without_a_display_renders_to_the_file)
{
    char out[4096];
    cr_assert_eq(glint_run("env -u DISPLAY -u WAYLAND_DISPLAY", "-p -r 32x24 -o nd.png", out,
                           sizeof out), 0, "%s", out);
    cr_expect(strstr(out, "glint: no display for the preview window (DISPLAY and WAYLAND_DISPLAY "
                          "are unset or empty); rendering to nd.png\n"), "%s", out);
    cr_expect(dir_has("nd.png"));
    /* An empty DISPLAY names no display either. */
    cr_assert_eq(glint_run("env -u WAYLAND_DISPLAY DISPLAY=", "-p -r 32x24 -o ne.png", out,
                           sizeof out), 0, "%s", out);
    cr_expect(strstr(out, "rendering to ne.png\n"), "%s", out);
    cr_expect(dir_has("ne.png"));
}
