/* Pieces both sides of a job use: waiting for a message, clocks, a batch's
 * bounds and packing. */
#include "job.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/signals.h"

#define POLL_NS 100000 /* 0.1 ms between polls when nothing came */

bool dist_wait(int source, int tag, int *from, int *bytes)
{
    for (;;) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(source < 0 ? MPI_ANY_SOURCE : source, tag, MPI_COMM_WORLD, &flag, &st);
        if (flag) {
            if (from)
                *from = st.MPI_SOURCE;
            if (bytes)
                MPI_Get_count(&st, MPI_BYTE, bytes);
            return true;
        }
        if (signals_caught())
            return false;
        nanosleep(&(struct timespec){0, POLL_NS}, NULL);
    }
}

glint_rc tile_clock_init(tile_clock *c, int threads, glint_error *err)
{
    *c = (tile_clock){0};
    c->cap = threads < 1 ? 1 : threads;
    c->thread = calloc((size_t)c->cap, sizeof *c->thread);
    c->last = calloc((size_t)c->cap, sizeof *c->last);
    if (!c->thread || !c->last) {
        tile_clock_free(c);
        snprintf(err->msg, sizeof err->msg, "out of memory");
        err->code = GLINT_ERR_NOMEM;
        return GLINT_ERR_NOMEM;
    }
    return GLINT_OK;
}

static double thread_cpu(void);

/* Called by the thread about to render the batch, which renders too. */
void tile_clock_start(tile_clock *c)
{
    c->n = 1;
    c->thread[0] = pthread_self();
    c->last[0] = thread_cpu();
}

/* The calling thread's CPU time: a tile's cost without the time the thread
 * waited for a core (other work on the machine). */
static double thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Called under the render's callback lock, so never twice at once. */
double tile_clock_tick(tile_clock *c)
{
    double t = thread_cpu();
    pthread_t self = pthread_self();
    int i = 0;
    while (i < c->n && !pthread_equal(c->thread[i], self))
        i++;
    if (i == c->n) {
        if (c->n == c->cap) /* more threads than the settings say: share the last slot */
            i = c->cap - 1;
        else
            c->n++;
        c->thread[i] = self;
        c->last[i] = 0; /* the other render threads are made for the batch */
    }
    double cost = t - c->last[i];
    c->last[i] = t;
    return cost;
}

void tile_clock_free(tile_clock *c)
{
    free(c->thread);
    free(c->last);
    *c = (tile_clock){0};
}

static glint_rect tile_rect(const glint_settings *s, int tile)
{
    glint_rect r = {0, 0, 0, 0};
    glint_error err;
    glint_tile_rect(s, tile, &r, &err); /* settings checked and tile in range */
    return r;
}

glint_rect dist_batch_bounds(const glint_settings *s, int first, int count)
{
    glint_rect box = tile_rect(s, first);
    for (int t = first + 1; t < first + count; t++) {
        glint_rect r = tile_rect(s, t);
        box.x0 = r.x0 < box.x0 ? r.x0 : box.x0;
        box.y0 = r.y0 < box.y0 ? r.y0 : box.y0;
        box.x1 = r.x1 > box.x1 ? r.x1 : box.x1;
        box.y1 = r.y1 > box.y1 ? r.y1 : box.y1;
    }
    return box;
}

/* Floats a pixel takes in a batch: RGB, and coverage with settings.alpha. */
static size_t pixel_floats(const glint_settings *s)
{
    return s->alpha ? 4 : 3;
}

size_t dist_batch_floats(const glint_settings *s, int first, int count)
{
    size_t n = 0;
    for (int t = first; t < first + count; t++) {
        glint_rect r = tile_rect(s, t);
        n += (size_t)(r.x1 - r.x0) * (size_t)(r.y1 - r.y0) * pixel_floats(s);
    }
    return n;
}

/* Copies one row of a tile between a film (at film position (x, y)) and
 * packed floats: RGB, then coverage when the film has it. */
static float *pack_row(const glint_film *f, int x, int y, int n, float *out)
{
    size_t at = (size_t)y * (size_t)f->width + (size_t)x;
    memcpy(out, f->rgb + at * 3, (size_t)n * 3 * sizeof *out);
    out += (size_t)n * 3;
    if (f->alpha) {
        memcpy(out, f->alpha + at, (size_t)n * sizeof *out);
        out += n;
    }
    return out;
}

static const float *unpack_row(glint_film *f, int x, int y, int n, const float *in)
{
    size_t at = (size_t)y * (size_t)f->width + (size_t)x;
    memcpy(f->rgb + at * 3, in, (size_t)n * 3 * sizeof *in);
    in += (size_t)n * 3;
    if (f->alpha) {
        memcpy(f->alpha + at, in, (size_t)n * sizeof *in);
        in += n;
    }
    return in;
}

void dist_batch_pack(const glint_settings *s, int first, int count, const glint_film *box,
                     glint_rect bounds, float *out)
{
    for (int t = first; t < first + count; t++) {
        glint_rect r = tile_rect(s, t);
        for (int y = r.y0; y < r.y1; y++)
            out = pack_row(box, r.x0 - bounds.x0, y - bounds.y0, r.x1 - r.x0, out);
    }
}

void dist_batch_unpack(const glint_settings *s, int first, int count, const float *in,
                       glint_film *image)
{
    for (int t = first; t < first + count; t++) {
        glint_rect r = tile_rect(s, t);
        for (int y = r.y0; y < r.y1; y++)
            in = unpack_row(image, r.x0, y, r.x1 - r.x0, in);
    }
}

glint_rc dist_film_alloc(glint_film *f, const glint_settings *s, int w, int h, glint_error *err)
{
    glint_rc rc = glint_film_alloc(f, w, h, err);
    if (rc == GLINT_OK && s->alpha) {
        f->alpha = calloc((size_t)w * (size_t)h, sizeof *f->alpha);
        if (!f->alpha) {
            glint_film_free(f);
            snprintf(err->msg, sizeof err->msg, "out of memory for a %dx%d film's coverage", w, h);
            return GLINT_ERR_NOMEM;
        }
    }
    return rc;
}
