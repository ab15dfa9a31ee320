#include "render.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "core/error.h"
#include "io/image.h"
#include "render/progressive.h"
#include "scene/settings.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "trace/whitted.h"

typedef struct job {
    const scene *scene;
    const glint_settings *settings;
    const glint_callbacks *cb;
    const render_work *work;
    glint_film *film;
    camera_frame frame;
    float decode[256];
    int grid; /* samples per pixel = grid * grid */
    int tx0, ty0, tiles_x; /* a region's first tile and its width in tiles */
    int items;             /* tiles to render */
    atomic_int next_item;
    atomic_int cancelled;
    double start;
    pthread_mutex_t lock; /* serialises callbacks and the counts below */
    uint64_t samples_done, samples_total;
    uint64_t secondary_rays, shadow_rays;
} job;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int render_tile_count(int width, int height)
{
    return ((width + RENDER_TILE - 1) / RENDER_TILE) * ((height + RENDER_TILE - 1) / RENDER_TILE);
}

glint_rect render_tile_rect(int width, int height, int tile)
{
    int tiles_x = (width + RENDER_TILE - 1) / RENDER_TILE;
    int x0 = (tile % tiles_x) * RENDER_TILE, y0 = (tile / tiles_x) * RENDER_TILE;
    return (glint_rect){x0, y0, x0 + RENDER_TILE < width ? x0 + RENDER_TILE : width,
                        y0 + RENDER_TILE < height ? y0 + RENDER_TILE : height};
}

/* The pixels of work item i. */
static glint_rect item_rect(const job *j, int i)
{
    const glint_settings *s = j->settings;
    if (j->work->tiles)
        return render_tile_rect(s->width, s->height, j->work->tiles[i]);
    int tiles_x = (s->width + RENDER_TILE - 1) / RENDER_TILE;
    glint_rect r = render_tile_rect(s->width, s->height,
                                    (j->ty0 + i / j->tiles_x) * tiles_x + j->tx0 + i % j->tiles_x);
    const glint_rect *g = &j->work->region;
    r.x0 = r.x0 > g->x0 ? r.x0 : g->x0;
    r.y0 = r.y0 > g->y0 ? r.y0 : g->y0;
    r.x1 = r.x1 < g->x1 ? r.x1 : g->x1;
    r.y1 = r.y1 < g->y1 ? r.y1 : g->y1;
    return r;
}

/* Counts the finished tile and tells the front end, in one critical
 * section so that the counts each callback sees only grow. */
static void tile_finished(job *j, const trace_ctx *ctx, const trace_ctx *before, glint_rect r,
                          uint64_t samples)
{
    pthread_mutex_lock(&j->lock);
    j->samples_done += samples;
    j->secondary_rays += ctx->secondary_rays - before->secondary_rays;
    j->shadow_rays += ctx->shadow_rays - before->shadow_rays;
    const glint_callbacks *cb = j->cb;
    if (cb && cb->tile_done)
        cb->tile_done(cb->user, j->film, r.x0, r.y0, r.x1, r.y1);
    if (cb && cb->progress) {
        glint_progress p = {100.0 * (double)j->samples_done / (double)j->samples_total,
                            j->samples_done, j->samples_total,
                            j->samples_done + j->secondary_rays + j->shadow_rays,
                            now_seconds() - j->start};
        cb->progress(cb->user, &p);
    }
    pthread_mutex_unlock(&j->lock);
}

/* The N x N regular grid: sample k = b * N + a at ((a + 0.5) / N,
 * (b + 0.5) / N) of the pixel, so 2 x 2 gives the quarter points 0.25 and
 * 0.75. Samples are added in the order of k, so a sum built in several
 * passes (progressive.h) is the same float as one built at once. */
vec3 render_samples(const camera_frame *f, int n, trace_ctx *ctx, int x, int y, int k0, int k1,
                    vec3 sum)
{
    float inv_n = 1.0f / (float)n;
    for (int k = k0; k < k1; k++) {
        int a = k % n, b = k / n;
        trace_begin_sample(ctx, (uint32_t)x, (uint32_t)y, (uint32_t)k);
        ray ry = camera_ray(f, (float)x + ((float)a + 0.5f) * inv_n,
                            (float)y + ((float)b + 0.5f) * inv_n);
        sum = v3_add(sum, whitted_trace(ctx, &ry, 0));
    }
    return sum;
}

static void render_tile(job *j, trace_ctx *ctx, int item, glint_rect r)
{
    trace_ctx before = *ctx;
    int n = j->grid;
    const render_work *w = j->work;
    if (w->accum) {
        uint64_t traced = progressive_tile(w->accum, item, w->upto, &j->frame, n, ctx, r);
        tile_finished(j, ctx, &before, r, traced);
        return;
    }
    float inv_count = 1.0f / (float)(n * n);
    for (int y = r.y0; y < r.y1; y++)
        for (int x = r.x0; x < r.x1; x++) {
            vec3 sum = render_samples(&j->frame, n, ctx, x, y, 0, n * n, v3s(0.0f));
            size_t at = (size_t)(y - w->film_y0) * (size_t)j->film->width + (size_t)(x - w->film_x0);
            float *px = j->film->rgb + at * 3;
            px[0] = sum.x * inv_count;
            px[1] = sum.y * inv_count;
            px[2] = sum.z * inv_count;
        }
    tile_finished(j, ctx, &before, r,
                  (uint64_t)(r.x1 - r.x0) * (uint64_t)(r.y1 - r.y0) * (uint64_t)(n * n));
}

static void *worker(void *arg)
{
    job *j = arg;
    trace_ctx ctx = {.scene = j->scene, .decode = j->decode, .max_depth = j->settings->max_depth,
                     .bailout = (float)j->settings->adc_bailout, .weight = 1.0f};
    const glint_callbacks *cb = j->cb;
    for (;;) {
        if (atomic_load(&j->cancelled))
            break;
        if (cb && cb->cancelled && cb->cancelled(cb->user)) {
            atomic_store(&j->cancelled, 1);
            break;
        }
        int i = atomic_fetch_add(&j->next_item, 1);
        if (i >= j->items)
            break;
        render_tile(j, &ctx, i, item_rect(j, i));
    }
    return NULL;
}

/* Fills in the work's tiles and their sample count. */
static void job_plan(job *j)
{
    const render_work *w = j->work;
    uint64_t spp = (uint64_t)(j->grid * j->grid), pixels = 0;
    if (w->tiles) {
        j->items = w->ntiles;
        for (int i = 0; i < w->ntiles; i++) {
            glint_rect r = item_rect(j, i);
            pixels += (uint64_t)(r.x1 - r.x0) * (uint64_t)(r.y1 - r.y0);
        }
    } else {
        const glint_rect *g = &w->region;
        j->tx0 = g->x0 / RENDER_TILE;
        j->ty0 = g->y0 / RENDER_TILE;
        j->tiles_x = (g->x1 - 1) / RENDER_TILE + 1 - j->tx0;
        j->items = j->tiles_x * ((g->y1 - 1) / RENDER_TILE + 1 - j->ty0);
        pixels = (uint64_t)(g->x1 - g->x0) * (uint64_t)(g->y1 - g->y0);
    }
    j->samples_total = w->accum ? progressive_samples_left(w->accum, w->upto) : pixels * spp;
}

/* Runs the job on settings.threads threads, the calling one included. */
static void job_run(job *j)
{
    int nthreads = j->settings->threads > 0 ? j->settings->threads : settings_default_threads();
    if (nthreads > j->items)
        nthreads = j->items > 0 ? j->items : 1;
    pthread_t *th = calloc((size_t)nthreads, sizeof *th);
    int started = 0;
    if (th)
        for (; started < nthreads - 1; started++)
            if (pthread_create(&th[started], NULL, worker, j) != 0)
                break;
    worker(j);
    for (int i = 0; i < started; i++)
        pthread_join(th[i], NULL);
    free(th);
}

glint_rc render_run(const struct glint_scene *sc, const glint_settings *settings,
                    const glint_callbacks *cb, const render_work *work, glint_film *film,
                    glint_stats *stats, glint_error *err)
{
    glint_rc rc = settings_check(settings, err);
    if (rc != GLINT_OK)
        return rc;
    if (!sc->built)
        return err_set(err, GLINT_ERR_INPUT, "scene was not built (objects were added since)");
    job *j = calloc(1, sizeof *j);
    if (!j)
        return err_nomem(err);
    j->start = now_seconds();
    j->scene = sc;
    j->settings = settings;
    j->cb = cb;
    j->work = work;
    j->film = film;
    j->frame = camera_frame_make(&sc->camera, settings->width, settings->height);
    image_decode_table(settings->transfer, j->decode);
    j->grid = settings_grid_side(settings->samples);
    job_plan(j);
    atomic_init(&j->next_item, 0);
    atomic_init(&j->cancelled, 0);
    pthread_mutex_init(&j->lock, NULL);
    job_run(j);
    if (atomic_load(&j->cancelled))
        rc = err_set(err, GLINT_ERR_CANCELLED, "render cancelled");
    if (stats) {
        stats->primary_rays = j->samples_done;
        stats->secondary_rays = j->secondary_rays;
        stats->shadow_rays = j->shadow_rays;
        stats->seconds = now_seconds() - j->start;
    }
    pthread_mutex_destroy(&j->lock);
    free(j);
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
