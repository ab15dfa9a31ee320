/* Pieces both sides of a job use: clocks, a batch's bounds and packing. */
#include "job.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

double dist_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
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

void tile_clock_start(tile_clock *c)
{
    c->n = 0;
    c->start = dist_now();
}

/* Called under the render's callback lock, so never twice at once. */
double tile_clock_tick(tile_clock *c)
{
    double t = dist_now();
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
        c->last[i] = c->start;
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

size_t dist_batch_floats(const glint_settings *s, int first, int count)
{
    size_t n = 0;
    for (int t = first; t < first + count; t++) {
        glint_rect r = tile_rect(s, t);
        n += (size_t)(r.x1 - r.x0) * (size_t)(r.y1 - r.y0) * 3;
    }
    return n;
}

void dist_batch_pack(const glint_settings *s, int first, int count, const glint_film *box,
                     glint_rect bounds, float *out)
{
    for (int t = first; t < first + count; t++) {
        glint_rect r = tile_rect(s, t);
        size_t row = (size_t)(r.x1 - r.x0) * 3;
        for (int y = r.y0; y < r.y1; y++) {
            size_t at = ((size_t)(y - bounds.y0) * (size_t)box->width + (size_t)(r.x0 - bounds.x0)) * 3;
            memcpy(out, box->rgb + at, row * sizeof *out);
            out += row;
        }
    }
}

void dist_batch_unpack(const glint_settings *s, int first, int count, const float *in,
                       glint_film *image)
{
    for (int t = first; t < first + count; t++) {
        glint_rect r = tile_rect(s, t);
        size_t row = (size_t)(r.x1 - r.x0) * 3;
        for (int y = r.y0; y < r.y1; y++) {
            memcpy(image->rgb + ((size_t)y * (size_t)image->width + (size_t)r.x0) * 3, in,
                   row * sizeof *in);
            in += row;
        }
    }
}
