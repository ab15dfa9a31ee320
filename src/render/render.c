#include "render.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "core/error.h"
#include "io/image.h"
#include "scene/settings.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "trace/whitted.h"

typedef struct job {
    const scene *scene;
    const glint_settings *settings;
    const glint_callbacks *cb;
    glint_film *film;
    camera_frame frame;
    float decode[256];
    int grid; /* samples per pixel = grid * grid */
    int tiles_x, tiles_total;
    atomic_int next_tile;
    atomic_int cancelled;
    pthread_mutex_t lock; /* serialises callbacks and the done count */
    int tiles_done;
    uint64_t secondary_rays, shadow_rays;
} job;

/* The N x N regular grid: sample (a, b) at ((a + 0.5) / N, (b + 0.5) / N)
 * of the pixel, so 2 x 2 gives the quarter points 0.25 and 0.75. */
static void render_tile(job *j, trace_ctx *ctx, int tile)
{
    int x0 = (tile % j->tiles_x) * RENDER_TILE, y0 = (tile / j->tiles_x) * RENDER_TILE;
    int x1 = x0 + RENDER_TILE < j->film->width ? x0 + RENDER_TILE : j->film->width;
    int y1 = y0 + RENDER_TILE < j->film->height ? y0 + RENDER_TILE : j->film->height;
    int n = j->grid;
    float inv_n = 1.0f / (float)n, inv_count = 1.0f / (float)(n * n);
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            vec3 sum = v3s(0.0f);
            for (int b = 0; b < n; b++)
                for (int a = 0; a < n; a++) {
                    ray r = camera_ray(&j->frame, (float)x + ((float)a + 0.5f) * inv_n,
                                       (float)y + ((float)b + 0.5f) * inv_n);
                    sum = v3_add(sum, whitted_trace(ctx, &r, 0));
                }
            float *px = j->film->rgb + ((size_t)y * (size_t)j->film->width + (size_t)x) * 3;
            px[0] = sum.x * inv_count;
            px[1] = sum.y * inv_count;
            px[2] = sum.z * inv_count;
        }
    pthread_mutex_lock(&j->lock);
    j->tiles_done++;
    if (j->cb && j->cb->tile_done)
        j->cb->tile_done(j->cb->user, j->film, x0, y0, x1, y1, j->tiles_done, j->tiles_total);
    pthread_mutex_unlock(&j->lock);
}

static void *worker(void *arg)
{
    job *j = arg;
    trace_ctx ctx = {j->scene, j->decode, j->settings->max_depth, 0, 0};
    for (;;) {
        if (j->cb && j->cb->cancel && *j->cb->cancel) {
            atomic_store(&j->cancelled, 1);
            break;
        }
        int t = atomic_fetch_add(&j->next_tile, 1);
        if (t >= j->tiles_total)
            break;
        render_tile(j, &ctx, t);
    }
    pthread_mutex_lock(&j->lock);
    j->secondary_rays += ctx.secondary_rays;
    j->shadow_rays += ctx.shadow_rays;
    pthread_mutex_unlock(&j->lock);
    return NULL;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

glint_rc render_run(const struct glint_scene *sc, const glint_settings *settings,
                      const glint_callbacks *cb, glint_film *film, glint_stats *stats,
                      glint_error *err)
{
    glint_rc rc = settings_check(settings, err);
    if (rc != GLINT_OK)
        return rc;
    if (!sc->built)
        return err_set(err, GLINT_ERR_INPUT, "scene was not built");

    double t0 = now_seconds();
    int w = settings->width, h = settings->height;
    film->width = w;
    film->height = h;
    film->rgb = calloc((size_t)w * (size_t)h * 3, sizeof(float));
    if (!film->rgb)
        return err_nomem(err);

    job *j = calloc(1, sizeof *j);
    if (!j) {
        render_film_free(film);
        return err_nomem(err);
    }
    j->scene = sc;
    j->settings = settings;
    j->cb = cb;
    j->film = film;
    j->frame = camera_frame_make(&sc->camera, w, h);
    image_decode_table(settings->transfer, j->decode);
    j->grid = settings_grid_side(settings->samples);
    j->tiles_x = (w + RENDER_TILE - 1) / RENDER_TILE;
    j->tiles_total = j->tiles_x * ((h + RENDER_TILE - 1) / RENDER_TILE);
    atomic_init(&j->next_tile, 0);
    atomic_init(&j->cancelled, 0);
    pthread_mutex_init(&j->lock, NULL);

    int nthreads = settings->threads > 0 ? settings->threads : settings_default_threads();
    if (nthreads > j->tiles_total)
        nthreads = j->tiles_total;
    pthread_t *th = calloc((size_t)nthreads, sizeof *th);
    int started = 0;
    if (th)
        for (; started < nthreads - 1; started++)
            if (pthread_create(&th[started], NULL, worker, j) != 0)
                break;
    worker(j); /* the calling thread works too */
    for (int i = 0; i < started; i++)
        pthread_join(th[i], NULL);
    free(th);

    if (atomic_load(&j->cancelled))
        rc = err_set(err, GLINT_ERR_CANCELLED, "render cancelled");
    if (stats) {
        int n = j->grid * j->grid;
        stats->primary_rays = (uint64_t)w * (uint64_t)h * (uint64_t)n;
        stats->secondary_rays = j->secondary_rays;
        stats->shadow_rays = j->shadow_rays;
        stats->seconds = now_seconds() - t0;
    }
    pthread_mutex_destroy(&j->lock);
    free(j);
    if (rc != GLINT_OK)
        render_film_free(film);
    return rc;
}

void render_film_free(glint_film *film)
{
    if (!film)
        return;
    free(film->rgb);
    film->rgb = NULL;
    film->width = film->height = 0;
}
