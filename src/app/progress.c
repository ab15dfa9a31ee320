#include "progress.h"

#include <time.h>

#define BAR_WIDTH 40

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

void progress_begin(progress *p, FILE *out)
{
    p->out = out;
    p->last_percent = -1;
    p->start = now();
    p->frame = p->frames = 0;
}

void progress_frame(progress *p, int k, int n)
{
    p->frame = k;
    p->frames = n;
    p->last_percent = -1;
}

void progress_update(progress *p, double percent_done)
{
    int percent = (int)percent_done;
    if (percent == p->last_percent)
        return;
    p->last_percent = percent;
    if (p->frames > 0) {
        /* the sequence's share done: frames before this one, and this one's part */
        fprintf(p->out, "\rframe %d of %d ", p->frame, p->frames);
        percent_done = (100.0 * (p->frame - 1) + percent_done) / p->frames;
        percent = (int)percent_done;
    }
    int fill = percent * BAR_WIDTH / 100;
    double elapsed = now() - p->start;
    double eta = percent_done > 0 ? elapsed * (100.0 - percent_done) / percent_done : 0.0;
    fprintf(p->out, "%s[", p->frames > 0 ? "" : "\r");
    for (int i = 0; i < BAR_WIDTH; i++)
        fputc(i < fill ? '#' : '.', p->out);
    fprintf(p->out, "] %3d%%  %.1fs elapsed, %.1fs left ", percent, elapsed, eta);
    fflush(p->out);
}

void progress_end(progress *p)
{
    if (p->last_percent >= 0) {
        fputc('\n', p->out);
        fflush(p->out);
    }
}
