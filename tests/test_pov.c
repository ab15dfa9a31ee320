/* glint against POV-Ray on a scene lit by a spot light and an area light
 * (bench/lights.yaml and bench/lights.pov, which explains how the two
 * models correspond). Both render it at 160x120 with 2x2 samples; the mean
 * absolute difference over every channel, in 8-bit levels, is printed and
 * must stay within MEAN_TOLERANCE (area-light noise, which neither renderer
 * shares with the other, and the renderers' different jitter and
 * anti-aliasing account for it). Skipped when povray is not installed
 * (scripts/install-deps bench installs it). */
#include <criterion/criterion.h>
#include <criterion/logging.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "glint.h"
#include "io/image.h"
#include "film.h"
#include "tmpdir.h"

#define W 160
#define H 120
#define MEAN_TOLERANCE 2.0

static void setup(void) { tmpdir_make("pov"); }

TestSuite(pov, .init = setup, .fini = tmpdir_remove);

Test(pov, spot_and_area_light_match_povray)
{
    if (system("command -v povray >/dev/null 2>&1") != 0)
        cr_skip_test("povray is not installed");
    char out[512], cmd[1400];
    snprintf(out, sizeof out, "%s/pov.png", dir);
    snprintf(cmd, sizeof cmd,
             "cd '%s' && povray +Ibench/lights.pov +W%d +H%d +AM1 +A0.0 +R2 -J -D +WT1 "
             "'+O%s' >/dev/null 2>&1",
             GLINT_SOURCE_DIR, W, H, out);
    cr_assert_eq(system(cmd), 0, "povray failed: %s", cmd);
    image pov;
    glint_error err = {0};
    cr_assert_eq(image_load(out, &pov, &err), GLINT_OK, "%s", err.msg);
    cr_assert(pov.width == W && pov.height == H && pov.rgb);

    glint_scene *s = NULL;
    cr_assert_eq(glint_scene_load(GLINT_SOURCE_DIR "/bench/lights.yaml", &s, &err), GLINT_OK,
                 "%s", err.msg);
    glint_film film = test_render(s, W, H, 4, 0);
    size_t n = (size_t)W * H * 3;
    uint8_t *px = malloc(n);
    image_quantize(film.rgb, n, GLINT_TRANSFER_NONE, px);
    double sum = 0.0;
    int bright = 0;
    for (size_t i = 0; i < n; i++) {
        sum += fabs((double)px[i] - (double)pov.rgb[i]);
        bright += px[i] > 200;
    }
    double mean = sum / (double)n;
    cr_log_info("glint vs POV-Ray, spot + area light, %dx%d: mean difference %.3f levels", W, H,
                mean);
    fprintf(stderr, "glint vs POV-Ray (spot + area light, %dx%d): mean difference %.3f of 255\n",
            W, H, mean);
    cr_expect_gt(bright, 100, "the spot light's pool is there");
    cr_expect_leq(mean, MEAN_TOLERANCE, "mean difference %.3f levels", mean);
    free(px);
    image_free(&pov);
    glint_film_free(&film);
    glint_scene_free(s);
}
