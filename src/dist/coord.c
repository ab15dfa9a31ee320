/* Rank 0: hands out batches of tiles (sched.h), renders batches of its own
 * on a thread of its own, and gathers the other ranks' pixels into the
 * image as they arrive, keeping the final tiles in the resume file
 * (keep.h) and the progress bar up to date. Only this thread calls MPI
 * (MPI_THREAD_FUNNELED). It polls for answers and sleeps briefly between
 * polls: a blocking receive spins in Open MPI and would take a core from
 * the renderers. */
#include <mpi.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/rerun.h"
#include "cli/signals.h"
#include "job.h"
#include "keep.h"
#include "sched.h"

#define POLL_NS 100000 /* 0.1 ms between polls when nothing came */

typedef struct coord {
    const dist_job *job;
    dist_gather *g;
    glint_resume *rec;
    dist_rank *ranks;
    double *costs;
    int *owner;
    sched sched;
    unsigned char *skip;  /* the tiles final before the render */
    pthread_mutex_t lock; /* sched, ranks[0], rc, err, rec->done, final, pixels */
    glint_rc rc;          /* the first failure */
    glint_error err;
    int final;            /* tiles final in rec */
    uint64_t pixels;      /* their pixels */
    atomic_bool local_done;
    int *outstanding;     /* batches each rank holds */
    dist_keep keep;
    double start;
    tile_clock clock;     /* the local renderer's */
    int *tiles;           /* the local batch */
    char *buf;            /* an answer */
    size_t cap;
} coord;

static void fail(coord *c, glint_rc rc, const char *msg)
{
    pthread_mutex_lock(&c->lock);
    if (c->rc == GLINT_OK) {
        c->rc = rc;
        snprintf(c->err.msg, sizeof c->err.msg, "%s", msg);
    }
    pthread_mutex_unlock(&c->lock);
}

/* Tiles first .. first + count - 1 are final in the record. Locked. */
static void mark(coord *c, int first, int count)
{
    const glint_settings *s = &c->job->settings;
    for (int t = first; t < first + count; t++) {
        glint_rect r;
        if (glint_tile_rect(s, t, &r, NULL) != GLINT_OK)
            continue;
        c->rec->done[t] = 1;
        c->pixels += (uint64_t)(r.x1 - r.x0) * (uint64_t)(r.y1 - r.y0);
        c->final++;
    }
}

static int take(coord *c, int *first)
{
    pthread_mutex_lock(&c->lock);
    int n = c->rc == GLINT_OK ? sched_take(&c->sched, first) : 0;
    pthread_mutex_unlock(&c->lock);
    return n;
}

static void on_local_tile(void *user, const glint_film *film, int x0, int y0, int x1, int y1)
{
    (void)film;
    (void)x1;
    (void)y1;
    coord *c = user;
    int across = (c->job->settings.width + DIST_TILE - 1) / DIST_TILE;
    int tile = (y0 / DIST_TILE) * across + x0 / DIST_TILE;
    if (c->costs) {
        c->costs[tile] = tile_clock_tick(&c->clock);
        c->owner[tile] = 0;
    }
    pthread_mutex_lock(&c->lock);
    mark(c, tile, 1);
    pthread_mutex_unlock(&c->lock);
}

static int on_local_cancel(void *user)
{
    (void)user;
    return signals_caught() != 0;
}

/* The local renderer: batches from the same scheduler, into the image. */
static void *local_main(void *arg)
{
    coord *c = arg;
    int first, n;
    while ((n = take(c, &first)) > 0) {
        for (int i = 0; i < n; i++)
            c->tiles[i] = first + i;
        glint_callbacks cb = {.user = c, .tile_done = on_local_tile, .cancelled = on_local_cancel};
        glint_stats st = {0};
        glint_error err = {0};
        tile_clock_start(&c->clock);
        double t0 = cli_now();
        glint_rc rc = glint_render_tiles(c->job->scene, &c->job->settings, c->tiles, n, &cb,
                                         &c->rec->film, &st, &err);
        pthread_mutex_lock(&c->lock);
        dist_rank *r = &c->ranks[0];
        r->busy += cli_now() - t0;
        r->tiles += n;
        r->batches++;
        r->primary += st.primary_rays;
        r->secondary += st.secondary_rays;
        r->shadow += st.shadow_rays;
        pthread_mutex_unlock(&c->lock);
        if (rc != GLINT_OK)
            fail(c, rc, err.msg);
    }
    atomic_store(&c->local_done, true);
    return NULL;
}

/* Sends rank its next batch, or when none is left and it holds none, the
 * end. */
static void give(coord *c, int rank)
{
    int work[2] = {0, 0};
    work[1] = take(c, &work[0]);
    if (work[1] > 0)
        c->outstanding[rank]++;
    else if (c->outstanding[rank] > 0)
        return;
    MPI_Send(work, 2, MPI_INT, rank, TAG_WORK, MPI_COMM_WORLD);
}

static glint_rc grow(coord *c, size_t bytes)
{
    if (bytes <= c->cap)
        return GLINT_OK;
    char *b = realloc(c->buf, bytes);
    if (!b)
        return GLINT_ERR_NOMEM;
    c->buf = b;
    c->cap = bytes;
    return GLINT_OK;
}

/* Takes in one answer: its pixels into the image, its counts into the
 * rank's. A failure stops the handing out. */
static void take_in(coord *c, int rank, const char *msg, size_t bytes)
{
    dist_result h;
    memcpy(&h, msg, sizeof h);
    const glint_settings *s = &c->job->settings;
    if (h.rc != GLINT_OK) {
        char text[sizeof c->err.msg];
        memcpy(text, msg + sizeof h, sizeof text);
        text[sizeof text - 1] = '\0';
        fail(c, (glint_rc)h.rc, text);
        return;
    }
    size_t head = sizeof h + (size_t)h.count * sizeof(double);
    if (h.first < 0 || h.count < 1 || h.first + h.count > c->job->ntiles ||
        bytes != head + dist_batch_floats(s, h.first, h.count) * sizeof(float)) {
        fail(c, GLINT_ERR_IO, "a rank's answer does not match its batch");
        return;
    }
    dist_batch_unpack(s, h.first, h.count, (const float *)(msg + head), &c->rec->film);
    if (c->costs)
        for (int i = 0; i < h.count; i++) {
            memcpy(&c->costs[h.first + i], msg + sizeof h + (size_t)i * sizeof(double),
                   sizeof(double));
            c->owner[h.first + i] = rank;
        }
    pthread_mutex_lock(&c->lock);
    mark(c, h.first, h.count);
    pthread_mutex_unlock(&c->lock);
    dist_rank *r = &c->ranks[rank];
    r->busy += h.busy;
    r->tiles += h.count;
    r->batches++;
    r->primary += h.primary;
    r->secondary += h.secondary;
    r->shadow += h.shadow;
}

/* Receives one answer if there is one; false when none had come. */
static bool poll_once(coord *c)
{
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &flag, &st);
    if (!flag)
        return false;
    int bytes = 0;
    MPI_Get_count(&st, MPI_BYTE, &bytes);
    int rank = st.MPI_SOURCE;
    if (grow(c, (size_t)bytes) != GLINT_OK) {
        fail(c, GLINT_ERR_NOMEM, "out of memory for a batch of pixels");
        grow(c, sizeof(dist_result) + sizeof c->err.msg); /* at least the header */
    }
    size_t room = c->cap < (size_t)bytes ? c->cap : (size_t)bytes;
    MPI_Recv(c->buf, (int)room, MPI_BYTE, rank, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    c->outstanding[rank]--;
    if (room == (size_t)bytes)
        take_in(c, rank, c->buf, room);
    give(c, rank);
    return true;
}

static bool any_outstanding(const coord *c)
{
    for (int r = 1; r < c->job->size; r++)
        if (c->outstanding[r] > 0)
            return true;
    return false;
}

/* The bar and the resume file, from the tiles final so far. */
static void report(coord *c)
{
    pthread_mutex_lock(&c->lock);
    int final = c->final;
    uint64_t pixels = c->pixels, rays = 0;
    for (int r = 0; r < c->job->size; r++)
        rays += c->ranks[r].primary + c->ranks[r].secondary + c->ranks[r].shadow;
    pthread_mutex_unlock(&c->lock);
    const glint_settings *s = &c->job->settings;
    uint64_t all = (uint64_t)s->width * (uint64_t)s->height;
    glint_progress p = {.percent = pixels == all ? 100.0 : 100.0 * (double)pixels / (double)all,
                        .samples_done = pixels, .samples_total = all, .rays = rays,
                        .seconds = cli_now() - c->start};
    progress_update(c->g->bar, &p);
    dist_keep_update(&c->keep, final, &c->lock);
}

/* Hands out and gathers until every rank is done, or until a signal; local
 * is the renderer thread, joined at the end. */
static void serve(coord *c, pthread_t local)
{
    for (int r = 1; r < c->job->size; r++)
        for (int d = 0; d < DIST_DEPTH && (d == 0 || c->outstanding[r] > 0); d++)
            give(c, r);
    while ((any_outstanding(c) || !atomic_load(&c->local_done)) && !signals_caught()) {
        if (!poll_once(c)) {
            report(c);
            nanosleep(&(struct timespec){0, POLL_NS}, NULL);
        }
    }
    pthread_join(local, NULL);
    if (!signals_caught())
        report(c);
}

static glint_rc coord_init(coord *c, const dist_job *job, glint_error *err)
{
    const glint_settings *s = &job->settings;
    int threads = s->threads > 0 ? s->threads : glint_default_threads();
    sched_init(&c->sched, job->ntiles, job->size, sched_min_batch(threads), DIST_MAX_BATCH);
    c->outstanding = calloc((size_t)job->size, sizeof *c->outstanding);
    c->tiles = malloc(DIST_MAX_BATCH * sizeof *c->tiles);
    c->skip = malloc((size_t)job->ntiles);
    if (!c->outstanding || !c->tiles || !c->skip) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        return GLINT_ERR_NOMEM;
    }
    memcpy(c->skip, c->rec->done, (size_t)job->ntiles);
    sched_skip(&c->sched, c->skip);
    for (int t = 0; t < job->ntiles; t++)
        if (c->skip[t])
            mark(c, t, 1);
    glint_rc rc = tile_clock_init(&c->clock, threads, err);
    if (rc == GLINT_OK)
        rc = dist_keep_init(&c->keep, c->rec, c->g->rpath, err);
    return rc;
}

/* Interrupted: the tiles final so far go into the resume file, with a
 * word on how to go on. */
static glint_rc stop(coord *c, glint_error *err)
{
    rerun_keep(c->job->opt, c->rec, c->g->rpath, true);
    c->g->kept = c->g->rpath != NULL;
    snprintf(err->msg, sizeof err->msg, "interrupted");
    return err->code = GLINT_ERR_CANCELLED;
}

glint_rc dist_coordinate(const dist_job *job, dist_gather *g, glint_error *err)
{
    coord c = {.job = job, .g = g, .rec = g->rec, .ranks = g->ranks, .costs = g->costs,
               .owner = g->owner, .start = cli_now()};
    pthread_mutex_init(&c.lock, NULL);
    atomic_init(&c.local_done, false);
    glint_rc rc = coord_init(&c, job, err);
    pthread_t local;
    if (rc == GLINT_OK && pthread_create(&local, NULL, local_main, &c) != 0) {
        snprintf(err->msg, sizeof err->msg, "cannot start a render thread");
        rc = GLINT_ERR_NOMEM;
    }
    if (rc != GLINT_OK) {
        /* tell the other ranks there is nothing to do */
        int end[2] = {0, 0};
        for (int r = 1; r < job->size; r++)
            MPI_Send(end, 2, MPI_INT, r, TAG_WORK, MPI_COMM_WORLD);
    } else {
        serve(&c, local);
        rc = c.rc;
        if (rc != GLINT_OK)
            *err = c.err;
        if (signals_caught())
            rc = stop(&c, err);
    }
    g->seconds = cli_now() - c.start;
    g->kept = g->kept || c.keep.wrote;
    dist_keep_free(&c.keep);
    tile_clock_free(&c.clock);
    free(c.outstanding);
    free(c.tiles);
    free(c.skip);
    free(c.buf);
    pthread_mutex_destroy(&c.lock);
    return rc;
}
