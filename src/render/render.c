#include "render.h"

#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "core/cpus.h"
#include "core/error.h"
#include "io/image.h"
#include "render/progressive.h"
#include "scene/settings.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "trace/whitted.h"
#include "render/bands.h"
#include "render/sampler.h"
#include "render/tile_lists.h"

typedef struct job {
    const scene *scene;
    const glint_settings *settings;
    const glint_callbacks *cb;
    const render_work *work;
    glint_film *film;
    camera_frame frame; /* the camera when the shutter opens */
    sampler smp;
    float decode[256];
    int lattice; /* adaptive: finest lattice points per pixel side, 2^(depth + 1) */
    bool packets; /* grid and jitter: camera rays eight at a time (scene_packets_pay) */
    bool cone;    /* packets from a pinhole: each tile's objects found once (tile_cone) */
    int tx0, ty0, tiles_x; /* a region's first tile and its width in tiles */
    int items;             /* tiles to render */
    bands *bands;          /* which thread renders which (render/bands.h) */
    atomic_int next_band;  /* the band of the next thread to start */
    atomic_int cancelled;
    atomic_int nomem; /* a thread could not get its scratch memory */
    double start;
    pthread_mutex_t lock; /* serialises callbacks and the counts below */
    uint64_t samples_done, samples_total;
    uint64_t primary_rays, secondary_rays, shadow_rays;
} job;

/* A render thread's own state. */
typedef struct worker_state {
    trace_ctx ctx;
    uint64_t primary_rays;
    int ncone; /* the objects the tile's camera rays may meet, or -1: walk the tree */
    int32_t cone[TILE_LISTS_MAX];
    trace_tile_shadows shadows; /* what the shadow rays from their hits may meet */
    struct lattice_point *points; /* adaptive: one pixel's lattice */
    struct lattice_point *corners; /* adaptive: a tile's pixel corners */
} worker_state;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
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

/* A thread's ray counts, before a tile. */
typedef struct ray_counts {
    uint64_t primary, secondary, shadow;
} ray_counts;

static ray_counts counts_of(const worker_state *w)
{
    return (ray_counts){w->primary_rays, w->ctx.secondary_rays, w->ctx.shadow_rays};
}

/* Counts the finished tile and tells the front end, in one critical
 * section so that the counts each callback sees only grow. */
static void tile_finished(job *j, worker_state *w, const ray_counts *before, glint_rect r,
                          uint64_t samples)
{
    pthread_mutex_lock(&j->lock);
    j->samples_done += samples;
    j->primary_rays += w->primary_rays - before->primary;
    j->secondary_rays += w->ctx.secondary_rays - before->secondary;
    j->shadow_rays += w->ctx.shadow_rays - before->shadow;
    const glint_callbacks *cb = j->cb;
    if (cb && cb->tile_done)
        cb->tile_done(cb->user, j->film, r.x0, r.y0, r.x1, r.y1);
    if (cb && cb->progress) {
        glint_progress p = {100.0 * (double)j->samples_done / (double)j->samples_total,
                            j->samples_done, j->samples_total,
                            j->primary_rays + j->secondary_rays + j->shadow_rays,
                            now_seconds() - j->start};
        cb->progress(cb->user, &p);
    }
    pthread_mutex_unlock(&j->lock);
}

/* Traces one camera sample at image position (x, y): lens and time from s.
 * *cover gets whether it hit something (only when the film keeps alpha). */
/* id0, id1, id2: the sample's identity, which light samples hash: pixel
 * and index, or for the adaptive lattice the point's own coordinates.
 * Three numbers rather than an array, which the caller would write to
 * memory a word at a time and this would read back in wider loads that
 * wait for the writes. */
static vec3 trace_sample(const job *j, worker_state *w, float x, float y, pixel_sample s,
                         uint32_t id0, uint32_t id1, uint32_t id2, float *cover)
{
    trace_begin_sample(&w->ctx, id0, id1, id2);
    const scene *sc = j->scene;
    float t = sc->time + s.time * sc->shutter_seconds;
    camera_frame moved;
    const camera_frame *f = &j->frame;
    if (sc->camera_moves) {
        camera c = scene_camera_at(sc, t);
        moved = camera_frame_make(&c, j->settings->width, j->settings->height);
        f = &moved;
    }
    ray r;
    *cover = 0.0f;
    if (!camera_ray(f, x, y, s.lu, s.lv, &r))
        return v3s(0.0f); /* outside a fisheye's circle: black, uncovered */
    r.time = t;
    w->ctx.time = t;
    w->primary_rays++;
    if (j->film->alpha || (j->work->accum && j->settings->alpha))
        return whitted_camera(&w->ctx, &r, cover);
    return whitted_trace(&w->ctx, &r, 0);
}

/* The n pixels (x + i, y) of a row: sum[i] times scale, coverage
 * cover[i] times scale. */
static void put_pixels(const job *j, int x, int y, int n, const vec3 *sum, const float *cover,
                       float scale)
{
    const render_work *wk = j->work;
    float *rgb, *alpha;
    if (wk->accum) { /* the adaptive sampler's final progressive pass */
        size_t i = (size_t)y * (size_t)wk->accum->width + (size_t)x;
        rgb = wk->accum->sum + i * 3;
        alpha = wk->accum->cover + i;
    } else {
        size_t at = (size_t)(y - wk->film_y0) * (size_t)j->film->width + (size_t)(x - wk->film_x0);
        rgb = j->film->rgb + at * 3;
        alpha = j->film->alpha ? j->film->alpha + at : NULL;
    }
    for (int i = 0; i < n; i++) {
        vec3 c = v3_scale(sum[i], scale);
        rgb[3 * i] = c.x;
        rgb[3 * i + 1] = c.y;
        rgb[3 * i + 2] = c.z;
        if (alpha)
            alpha[i] = cover[i] * scale;
    }
}

/* Adds samples k0 <= k < k1 of pixel (x, y) (grid or jitter) to *sum and
 * their coverage to *cover, in the order of k: a sum built in several
 * progressive passes is the same float as one built at once. */
static void sample_range(const job *j, worker_state *w, int x, int y, int k0, int k1, vec3 *sum,
                         float *cover)
{
    for (int k = k0; k < k1; k++) {
        float c;
        pixel_sample s = sampler_get(&j->smp, x, y, k);
        *sum = v3_add(*sum, trace_sample(j, w, (float)x + s.fx, (float)y + s.fy, s, (uint32_t)x,
                                         (uint32_t)y, (uint32_t)k, &c));
        *cover += c;
    }
}

/* sample_range for the n <= 8 pixels (x0 + i, y) at once: sample k of
 * each is a camera ray of one packet (scene_intersect8), then shaded on
 * its own. Each ray gets the hit scene_intersect would give it, so every
 * sum is the float sample_range builds. The camera does not move (a
 * moving one has a frame per sample). */
static void sample_packet(const job *j, worker_state *w, int x0, int y, int n, int k0, int k1,
                          vec3 sum[8], float cover[8])
{
    const scene *sc = j->scene;
    bool alpha = j->film->alpha || (j->work->accum && j->settings->alpha);
    bool alike = sampler_same_in_every_pixel(&j->smp);
    for (int k = k0; k < k1; k++) {
        ray8 p;
        int active = 0;
        if (alike) {
            pixel_sample s = sampler_get(&j->smp, x0, y, k);
            active = camera_row8_on(sc->bvh.isa, &j->frame, x0, n, s.fx, (float)y + s.fy, s.lu,
                                    s.lv, sc->time + s.time * sc->shutter_seconds, &p);
        } else {
            ray rs[8];
            for (int i = 0; i < n; i++) {
                pixel_sample s = sampler_get(&j->smp, x0 + i, y, k);
                if (camera_ray(&j->frame, (float)(x0 + i) + s.fx, (float)y + s.fy, s.lu, s.lv,
                               &rs[i]))
                    active |= 1 << i;
                rs[i].time = sc->time + s.time * sc->shutter_seconds;
            }
            if (active)
                ray8_pack(&p, rs, active);
        }
        if (!active)
            continue;
        scene_hit h[8];
        int found = w->ncone >= 0 ? scene_intersect8_among(sc, &p, active, w->cone, w->ncone, h)
                                  : scene_intersect8(sc, &p, active, h);
        trace_lanes tl = {(uint32_t)x0, (uint32_t)y, (uint32_t)k, {0}};
        for (int i = 0; i < n; i++)
            tl.time[i] = p.time[i];
        vec3 v[8];
        float c[8];
        whitted_camera8(&w->ctx, &tl, &p, active, found, h, v, c);
        for (int i = 0; i < n; i++) {
            if (!(active >> i & 1)) { /* outside a fisheye's circle: black, uncovered */
                sum[i] = v3_add(sum[i], v3s(0.0f)); /* as sample_range adds it (-0 + 0) */
                continue;
            }
            w->primary_rays++;
            sum[i] = v3_add(sum[i], v[i]);
            cover[i] += alpha ? c[i] : 0.0f;
        }
    }
}

/* The tile's lists (render/tile_lists.h) where job.cone is on. */
static void tile_cone(const job *j, worker_state *w, glint_rect r)
{
    bool lit = false;
    w->ncone = j->cone ? tile_lists(j->scene, &j->frame, r, w->cone, &w->shadows, &lit) : -1;
    w->ctx.tile = lit ? &w->shadows : NULL;
}

/* grid and jitter: every sample of each pixel, averaged. */
static void render_tile_fixed(job *j, worker_state *w, glint_rect r)
{
    int count = sampler_count(&j->smp);
    float inv_count = 1.0f / (float)count;
    for (int y = r.y0; y < r.y1; y++)
        for (int x = r.x0; x < r.x1; x += j->packets ? 8 : 1) {
            int n = j->packets ? (r.x1 - x < 8 ? r.x1 - x : 8) : 1;
            vec3 sum[8];
            float cover[8];
            for (int i = 0; i < n; i++)
                sum[i] = v3s(0.0f), cover[i] = 0.0f;
            if (j->packets)
                sample_packet(j, w, x, y, n, 0, count, sum, cover);
            else
                sample_range(j, w, x, y, 0, count, &sum[0], &cover[0]);
            put_pixels(j, x, y, n, sum, cover, inv_count);
        }
}

/* ---- adaptive sampling ----------------------------------------------------
 * Like POV-Ray's adaptive method 2, made deterministic. A pixel's corners
 * (shared with its neighbours) and centre are traced; when they differ by
 * more than the threshold in display value, the pixel splits into four
 * cells, each traced at its corners (most already known) and centre, and
 * so on down to the depth limit. A cell that needs no split takes its
 * centre's value; a split one, the mean of its four. The points lie on a
 * lattice of `lattice` x `lattice` steps per pixel; at threshold 0 every
 * cell splits and the pixel is exactly the 2^depth x 2^depth grid. */

typedef struct lattice_point {
    vec3 c;
    float cover;
    float shown[3]; /* display values, for the comparison */
    bool done;
} lattice_point;

/* Traces lattice point (i, j) of pixel (x, y) into p unless done. */
static void lattice_trace(const job *j, worker_state *w, int x, int y, int i, int k,
                          lattice_point *p)
{
    if (p->done)
        return;
    int n = j->lattice;
    float fx = (float)i / (float)n, fy = (float)k / (float)n;
    const uint32_t id[3] = {(uint32_t)x * (uint32_t)n + (uint32_t)i,
                            (uint32_t)y * (uint32_t)n + (uint32_t)k, 0x80000000u};
    pixel_sample s = sampler_point(id[0], id[1], fx, fy);
    p->c = trace_sample(j, w, (float)x + fx, (float)y + fy, s, id[0], id[1], id[2], &p->cover);
    glint_transfer tf = j->settings->transfer;
    p->shown[0] = image_display_value(p->c.x, tf);
    p->shown[1] = image_display_value(p->c.y, tf);
    p->shown[2] = image_display_value(p->c.z, tf);
    p->done = true;
}

/* Whether the points differ by more than the threshold in some channel. */
static bool points_differ(const lattice_point *const *p, int n, float threshold)
{
    if (!(threshold > 0.0f))
        return true;
    for (int ch = 0; ch < 3; ch++) {
        float lo = p[0]->shown[ch], hi = lo;
        for (int i = 1; i < n; i++) {
            lo = fminf(lo, p[i]->shown[ch]);
            hi = fmaxf(hi, p[i]->shown[ch]);
        }
        if (hi - lo > threshold)
            return true;
    }
    return false;
}

/* The cell of pixel (x, y) with top-left lattice point (i, k) and side
 * size (in lattice steps), its colour into *c and coverage into *cover. */
static void adaptive_cell(const job *j, worker_state *w, int x, int y, int i, int k, int size,
                          vec3 *c, float *cover)
{
    int n = j->lattice, h = size / 2;
    lattice_point *pt = w->points;
#define AT(a, b) (&pt[(b) * (n + 1) + (a)])
    lattice_point *q[5] = {AT(i, k), AT(i + size, k), AT(i, k + size), AT(i + size, k + size),
                           AT(i + h, k + h)};
    for (int m = 0; m < 5; m++)
        lattice_trace(j, w, x, y, m == 4 ? i + h : i + (m & 1) * size,
                      m == 4 ? k + h : k + (m >> 1) * size, q[m]);
    if (h < 2 || !points_differ((const lattice_point *const *)q, 5, (float)j->settings->threshold)) {
        *c = q[4]->c;
        *cover = q[4]->cover;
        return;
    }
    vec3 sum = v3s(0.0f);
    float csum = 0.0f;
    for (int m = 0; m < 4; m++) {
        vec3 cc;
        float cv;
        adaptive_cell(j, w, x, y, i + (m & 1) * h, k + (m >> 1) * h, h, &cc, &cv);
        sum = v3_add(sum, cc);
        csum += cv;
    }
    *c = v3_scale(sum, 0.25f);
    *cover = 0.25f * csum;
#undef AT
}

static void render_tile_adaptive(job *j, worker_state *w, glint_rect r)
{
    int n = j->lattice, tw = r.x1 - r.x0 + 1;
    lattice_point *corner = w->corners;
    for (int y = r.y0; y <= r.y1; y++)
        for (int x = r.x0; x <= r.x1; x++) {
            lattice_point *p = &corner[(y - r.y0) * tw + (x - r.x0)];
            p->done = false;
            lattice_trace(j, w, x, y, 0, 0, p);
        }
    size_t npoints = (size_t)(n + 1) * (size_t)(n + 1);
    for (int y = r.y0; y < r.y1; y++)
        for (int x = r.x0; x < r.x1; x++) {
            for (size_t i = 0; i < npoints; i++)
                w->points[i].done = false;
            const lattice_point *c = &corner[(y - r.y0) * tw + (x - r.x0)];
            w->points[0] = c[0];
            w->points[n] = c[1];
            w->points[(size_t)n * (size_t)(n + 1)] = c[tw];
            w->points[npoints - 1] = c[tw + 1];
            vec3 col;
            float cover;
            adaptive_cell(j, w, x, y, 0, 0, n, &col, &cover);
            put_pixels(j, x, y, 1, &col, &cover, 1.0f);
        }
}

/* The adaptive sampler's quick look: one sample at the pixel's centre, a
 * point of its finest lattice. */
static void centre_sample(const job *j, worker_state *w, int x, int y, vec3 *sum, float *cover)
{
    int n = j->lattice, h = n / 2;
    const uint32_t id[3] = {(uint32_t)x * (uint32_t)n + (uint32_t)h,
                            (uint32_t)y * (uint32_t)n + (uint32_t)h, 0x80000000u};
    pixel_sample s = sampler_point(id[0], id[1], 0.5f, 0.5f);
    *sum = trace_sample(j, w, (float)x + 0.5f, (float)y + 0.5f, s, id[0], id[1], id[2], cover);
}

/* Samples k0 <= k < k1 of the n <= 8 pixels (x + i, y) added to the
 * accumulator's sums and coverage, camera rays eight at a time
 * (sample_packet): the same floats as sample_range pixel by pixel. */
static void accumulate_packet(const job *j, worker_state *w, int x, int y, int n, int k0, int k1)
{
    glint_accum *a = j->work->accum;
    size_t at = (size_t)y * (size_t)a->width + (size_t)x;
    vec3 sum[8];
    float cover[8];
    for (int i = 0; i < n; i++) {
        const float *px = a->sum + (at + (size_t)i) * 3;
        sum[i] = v3(px[0], px[1], px[2]);
        cover[i] = a->cover[at + (size_t)i];
    }
    sample_packet(j, w, x, y, n, k0, k1, sum, cover);
    for (int i = 0; i < n; i++) {
        float *px = a->sum + (at + (size_t)i) * 3;
        px[0] = sum[i].x, px[1] = sum[i].y, px[2] = sum[i].z;
        a->cover[at + (size_t)i] = cover[i];
    }
}

/* A progressive pass over tile `item` (render_work.accum): grid and jitter
 * add samples up to upto; the adaptive sampler cannot be split by sample
 * index, so its passes are one sample at each pixel's corner point, then,
 * at upto = settings.samples, the whole adaptive tile, kept exactly
 * (tile_div 1), so the final image is the batch image. Returns the samples
 * traced. */
static uint64_t render_tile_pass(job *j, worker_state *w, int item, glint_rect r)
{
    glint_accum *a = j->work->accum;
    int k0 = a->tile_samples[item], upto = j->work->upto;
    if (k0 >= upto)
        return 0;
    uint64_t area = (uint64_t)(r.x1 - r.x0) * (uint64_t)(r.y1 - r.y0);
    bool adaptive = j->smp.kind == GLINT_SAMPLER_ADAPTIVE;
    if (adaptive && upto >= j->settings->samples) {
        render_tile_adaptive(j, w, r); /* put_pixels writes into the accumulator */
        a->tile_samples[item] = upto;
        a->tile_div[item] = 1;
        return area;
    }
    if (!adaptive && j->packets) {
        for (int y = r.y0; y < r.y1; y++)
            for (int x = r.x0; x < r.x1; x += 8)
                accumulate_packet(j, w, x, y, r.x1 - x < 8 ? r.x1 - x : 8, k0, upto);
        a->tile_samples[item] = upto;
        a->tile_div[item] = upto;
        return area * (uint64_t)(upto - k0);
    }
    for (int y = r.y0; y < r.y1; y++)
        for (int x = r.x0; x < r.x1; x++) {
            size_t at = (size_t)y * (size_t)a->width + (size_t)x;
            float *px = a->sum + at * 3;
            vec3 sum = v3(px[0], px[1], px[2]);
            if (adaptive)
                sum = v3s(0.0f), a->cover[at] = 0.0f;
            if (adaptive)
                centre_sample(j, w, x, y, &sum, &a->cover[at]);
            else
                sample_range(j, w, x, y, k0, upto, &sum, &a->cover[at]);
            px[0] = sum.x;
            px[1] = sum.y;
            px[2] = sum.z;
        }
    a->tile_samples[item] = adaptive ? 1 : upto;
    a->tile_div[item] = a->tile_samples[item];
    return area * (uint64_t)(adaptive ? 1 : upto - k0);
}

static void render_tile(job *j, worker_state *w, int item, glint_rect r)
{
    tile_cone(j, w, r);
    ray_counts before = counts_of(w);
    if (j->work->accum) {
        tile_finished(j, w, &before, r, render_tile_pass(j, w, item, r));
        return;
    }
    uint64_t pixels = (uint64_t)(r.x1 - r.x0) * (uint64_t)(r.y1 - r.y0);
    if (j->smp.kind == GLINT_SAMPLER_ADAPTIVE)
        render_tile_adaptive(j, w, r);
    else
        render_tile_fixed(j, w, r);
    tile_finished(j, w, &before, r,
                  j->smp.kind == GLINT_SAMPLER_ADAPTIVE ? pixels
                                                         : pixels * (uint64_t)sampler_count(&j->smp));
}

static void *worker(void *arg)
{
    job *j = arg;
    int band = atomic_fetch_add(&j->next_band, 1); /* each its own */
    worker_state w = {{.scene = j->scene, .decode = j->decode,
                       .max_depth = j->settings->max_depth,
                       .bailout = (float)j->settings->adc_bailout, .weight = 1.0f},
                      0, -1, {0}, {{0}, {{0}}}, NULL, NULL};
    if (j->smp.kind == GLINT_SAMPLER_ADAPTIVE) {
        size_t side = (size_t)j->lattice + 1;
        w.points = malloc(sizeof *w.points * side * side);
        w.corners = malloc(sizeof *w.corners * (RENDER_TILE + 1) * (RENDER_TILE + 1));
        if (!w.points || !w.corners) {
            atomic_store(&j->nomem, 1);
            atomic_store(&j->cancelled, 1);
        }
    }
    const glint_callbacks *cb = j->cb;
    for (;;) {
        if (atomic_load(&j->cancelled))
            break;
        if (cb && cb->cancelled && cb->cancelled(cb->user)) {
            atomic_store(&j->cancelled, 1);
            break;
        }
        int i = bands_take(j->bands, band);
        if (i < 0)
            break;
        render_tile(j, &w, i, item_rect(j, i));
    }
    free(w.points);
    free(w.corners);
    return NULL;
}

/* Fills in the work's tiles and their sample count. */
static void job_plan(job *j)
{
    const render_work *w = j->work;
    uint64_t spp = j->smp.kind == GLINT_SAMPLER_ADAPTIVE ? 1 : (uint64_t)sampler_count(&j->smp);
    uint64_t pixels = 0;
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
    j->bands = bands_new(j->items, nthreads);
    if (!j->bands) {
        atomic_store(&j->nomem, 1);
        atomic_store(&j->cancelled, 1);
        return;
    }
    cpus_share(nthreads, worker, j); /* a band whose thread did not start goes to the others */
    bands_free(j->bands);
    j->bands = NULL;
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
    j->smp = sampler_make(settings, sc->camera.aperture > 0.0f || sc->camera_moves,
                          sc->shutter_seconds > 0.0f);
    j->lattice = 2 << settings->adaptive_depth;
    j->packets = !sc->camera_moves && scene_packets_pay(sc);
    j->cone = j->packets && j->frame.projection == CAMERA_PERSPECTIVE &&
              j->frame.lens_radius == 0.0f;
    job_plan(j);
    atomic_init(&j->cancelled, 0);
    atomic_init(&j->nomem, 0);
    atomic_init(&j->next_band, 0);
    pthread_mutex_init(&j->lock, NULL);
    job_run(j);
    if (atomic_load(&j->nomem))
        rc = err_nomem(err);
    else if (atomic_load(&j->cancelled))
        rc = err_set(err, GLINT_ERR_CANCELLED, "render cancelled");
    if (stats) {
        stats->primary_rays = j->primary_rays;
        stats->secondary_rays = j->secondary_rays;
        stats->shadow_rays = j->shadow_rays;
        stats->seconds = now_seconds() - j->start;
    }
    pthread_mutex_destroy(&j->lock);
    free(j);
    return rc;
}
