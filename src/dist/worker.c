/* The ranks other than 0: render the batches rank 0 sends, answer each with
 * its pixels, until told the image is done, or until a signal stops the
 * job (then without a word: rank 0 keeps what it has). */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/signals.h"
#include "job.h"

typedef struct worker {
    const dist_job *job;
    tile_clock clock;
    double *costs; /* the batch's, by tile - first */
    int first;
    char *buf;     /* the answer: header, costs, pixels */
    size_t cap;
} worker;

static void on_tile(void *user, const glint_film *film, int x0, int y0, int x1, int y1)
{
    (void)film;
    worker *w = user;
    const glint_settings *s = &w->job->settings;
    int across = (s->width + DIST_TILE - 1) / DIST_TILE;
    int tile = (y0 / DIST_TILE) * across + x0 / DIST_TILE;
    (void)x1;
    (void)y1;
    w->costs[tile - w->first] = tile_clock_tick(&w->clock);
}

static int on_cancel(void *user)
{
    (void)user;
    return signals_caught() != 0;
}

static glint_rc grow(worker *w, size_t bytes, glint_error *err)
{
    if (bytes <= w->cap)
        return GLINT_OK;
    char *b = realloc(w->buf, bytes);
    if (!b) {
        snprintf(err->msg, sizeof err->msg, "out of memory for a batch of pixels");
        return GLINT_ERR_NOMEM;
    }
    w->buf = b;
    w->cap = bytes;
    return GLINT_OK;
}

/* Renders one batch into w->buf; *bytes is the answer's size. */
static glint_rc render_batch(worker *w, int first, int count, size_t *bytes, glint_error *err)
{
    const glint_settings *s = &w->job->settings;
    size_t floats = dist_batch_floats(s, first, count);
    size_t head = sizeof(dist_result) + (size_t)count * sizeof(double);
    glint_rc rc = grow(w, head + floats * sizeof(float), err);
    if (rc != GLINT_OK)
        return rc;
    int *tiles = malloc((size_t)count * sizeof *tiles);
    glint_rect box = dist_batch_bounds(s, first, count);
    glint_film film = {0};
    rc = tiles ? dist_film_alloc(&film, s, box.x1 - box.x0, box.y1 - box.y0, err) : GLINT_ERR_NOMEM;
    if (rc == GLINT_OK) {
        for (int i = 0; i < count; i++)
            tiles[i] = first + i;
        dist_result *r = (dist_result *)w->buf;
        w->costs = (double *)(w->buf + sizeof *r);
        w->first = first;
        glint_callbacks cb = {.user = w, .tile_done = on_tile, .cancelled = on_cancel};
        glint_stats st = {0};
        tile_clock_start(&w->clock);
        double t0 = cli_now();
        rc = glint_render_tiles(w->job->scene, s, tiles, count, &cb, &film, &st, err);
        *r = (dist_result){GLINT_OK, first, count, 0, cli_now() - t0, st.primary_rays,
                           st.secondary_rays, st.shadow_rays};
        if (rc == GLINT_OK)
            dist_batch_pack(s, first, count, &film, box, (float *)(w->buf + head));
        *bytes = head + floats * sizeof(float);
    } else if (!tiles) {
        snprintf(err->msg, sizeof err->msg, "out of memory for a batch of tiles");
    }
    glint_film_free(&film);
    free(tiles);
    return rc;
}

/* After a failure every batch is answered with the failure. */
static void answer_failure(glint_rc rc, const glint_error *err, int first, int count)
{
    struct {
        dist_result r;
        char msg[sizeof err->msg];
    } m = {{(int32_t)rc, first, count, 0, 0, 0, 0, 0}, {0}};
    memcpy(m.msg, err->msg, sizeof m.msg);
    MPI_Send(&m, (int)sizeof m, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
}

glint_rc dist_work(const dist_job *job, glint_error *err)
{
    worker w = {.job = job};
    glint_rc rc = tile_clock_init(&w.clock, job->settings.threads, err);
    for (;;) {
        int work[2];
        if (!dist_wait(0, TAG_WORK, NULL, NULL))
            break;
        MPI_Recv(work, 2, MPI_INT, 0, TAG_WORK, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (work[1] == 0)
            break;
        size_t bytes = 0;
        if (rc == GLINT_OK)
            rc = render_batch(&w, work[0], work[1], &bytes, err);
        if (signals_caught())
            break;
        if (rc == GLINT_OK)
            MPI_Send(w.buf, (int)bytes, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
        else
            answer_failure(rc, err, work[0], work[1]);
    }
    tile_clock_free(&w.clock);
    free(w.buf);
    if (signals_caught()) {
        snprintf(err->msg, sizeof err->msg, "interrupted");
        rc = GLINT_ERR_CANCELLED;
    }
    return rc;
}
