/* --preview-bench: the preview's frame rate along a scripted camera path,
 * a full orbit around the look-at point in 120 frames, at 640x360 and
 * 1280x720 with 1 sample per pixel. A frame is what the window does after
 * each camera step: clear the accumulating film, one progressive pass of 1
 * sample per pixel, resolve, and quantise to 8-bit pixels (the texture
 * upload to the screen is not counted). The half-resolution pass the
 * window draws while the camera moves is timed too. */
#include "preview.h"

#include <stdio.h>
#include <stdlib.h>

#define BENCH_FRAMES 120

typedef struct bench_result {
    double full_fps, half_fps, mrays;
} bench_result;

/* Frames per second along the orbit at w x h; *mrays is the rays' rate. */
static glint_rc orbit(glint_scene *scene, glint_settings s, double *fps, double *mrays,
                      glint_error *err)
{
    glint_camera start;
    glint_scene_camera(scene, &start, NULL);
    glint_accum a;
    glint_film film = {0};
    uint8_t *rgb = malloc((size_t)s.width * (size_t)s.height * 3);
    glint_rc rc = rgb ? glint_accum_alloc(&a, s.width, s.height, err) : GLINT_ERR_NOMEM;
    if (rc != GLINT_OK) {
        free(rgb);
        return rc;
    }
    rc = glint_film_alloc(&film, s.width, s.height, err);
    uint64_t rays = 0;
    double t0 = cli_now(), traced = 0;
    for (int i = 0; i < BENCH_FRAMES && rc == GLINT_OK; i++) {
        glint_camera cam = start;
        camera_orbit(&cam, 360.0 * i / BENCH_FRAMES, 0.0);
        glint_stats st;
        rc = glint_scene_set_camera(scene, &cam, err);
        glint_accum_clear(&a);
        if (rc == GLINT_OK)
            rc = glint_render_pass(scene, &s, 1, NULL, &a, &st, err);
        if (rc == GLINT_OK)
            rc = glint_accum_resolve(&a, NULL, &film, NULL, err);
        if (rc == GLINT_OK)
            rc = glint_film_quantize(&film, NULL, s.transfer, rgb, err);
        rays += st.primary_rays + st.secondary_rays + st.shadow_rays;
        traced += st.seconds;
    }
    double t = cli_now() - t0;
    *fps = BENCH_FRAMES / t;
    *mrays = traced > 0 ? (double)rays / traced * 1e-6 : 0.0;
    glint_scene_set_camera(scene, &start, NULL);
    glint_film_free(&film);
    glint_accum_free(&a);
    free(rgb);
    return rc;
}

static glint_rc bench_size(const struct cli *c, int w, int h, bench_result *r, glint_error *err)
{
    glint_scene *scene;
    glint_settings s;
    glint_rc rc = cli_load(c, &scene, &s, NULL, err);
    if (rc != GLINT_OK)
        return rc;
    s.width = w;
    s.height = h;
    s.samples = 1;
    double mrays_half;
    rc = orbit(scene, s, &r->full_fps, &r->mrays, err);
    s.width = (w + 1) / 2;
    s.height = (h + 1) / 2;
    if (rc == GLINT_OK)
        rc = orbit(scene, s, &r->half_fps, &mrays_half, err);
    glint_scene_free(scene);
    return rc;
}

int preview_bench(const struct cli *c, bool display)
{
    (void)display;
    static const int sizes[2][2] = {{640, 360}, {1280, 720}};
    int threads = c->threads > 0 ? c->threads : glint_default_threads();
    printf("preview-bench: %s, %d thread%s, an orbit of %d frames, 1 sample per pixel\n",
           c->scene_path ? c->scene_path : "built-in scene", threads, threads == 1 ? "" : "s",
           BENCH_FRAMES);
    for (int i = 0; i < 2; i++) {
        bench_result r;
        glint_error err = {0};
        glint_rc rc = bench_size(c, sizes[i][0], sizes[i][1], &r, &err);
        if (rc != GLINT_OK) {
            fprintf(stderr, "glint: %s\n", err.msg);
            return glint_exit_code(rc);
        }
        printf("  %4dx%-4d  %6.1f fps (%5.1f ms a frame, %.1f Mrays/s); moving, at half "
               "resolution: %6.1f fps\n",
               sizes[i][0], sizes[i][1], r.full_fps, 1000.0 / r.full_fps, r.mrays, r.half_fps);
    }
    fflush(stdout);
    return 0;
}
