#include "progress.h"

#include <math.h>

#include "cli.h"

#define BAR_WIDTH 30
#define REDRAW_SECONDS 0.1

progress_mode progress_choose(bool quiet, bool forced, bool terminal)
{
    if (quiet)
        return PROGRESS_OFF;
    if (terminal)
        return PROGRESS_BAR;
    return forced ? PROGRESS_LINES : PROGRESS_OFF;
}

void progress_begin(progress *p, FILE *out, progress_mode mode, const char *name)
{
    *p = (progress){out, name, mode, 0, 0, cli_now(), 0.0, -1, 0.0, false};
}

void progress_frame(progress *p, int k, int n)
{
    p->frame = k;
    p->frames = n;
    p->last_percent = -1;
}

void progress_duration(double s, char *buf, size_t size)
{
    if (s < 60.0)
        snprintf(buf, size, "%.1fs", s);
    else if (s < 3600.0)
        snprintf(buf, size, "%dm%02ds", (int)(s / 60.0), (int)fmod(s, 60.0));
    else
        snprintf(buf, size, "%dh%02dm", (int)(s / 3600.0), (int)fmod(s / 60.0, 60.0));
}

/* "  43%  1.2s elapsed, 1.6s left, 85.3 Mrays/s, frame 2 of 10" */
static void describe(const progress *p, const glint_progress *g, char *buf, size_t size)
{
    char elapsed[32], left[48] = "";
    progress_duration(g->seconds, elapsed, sizeof elapsed);
    /* the rate of this run: a resumed render starts part way; in a sequence,
     * the time left is the sequence's, from its share done so far */
    double done = g->percent, run = g->percent - p->base, spent = g->seconds;
    if (p->frames > 1) {
        done = (100.0 * (p->frame - 1) + g->percent) / p->frames;
        run = done;
        spent = cli_now() - p->start;
    }
    if (run >= PROGRESS_ETA_AFTER && done < 100.0) {
        char d[32];
        progress_duration(spent * (100.0 - done) / run, d, sizeof d);
        snprintf(left, sizeof left, ", %s left", d);
    }
    double mrays = g->seconds > 0 ? (double)g->rays / g->seconds * 1e-6 : 0.0;
    int n = snprintf(buf, size, "%3d%%  %s elapsed%s, %.1f Mrays/s", (int)g->percent, elapsed,
                     left, mrays);
    if (p->frames > 1 && n > 0 && (size_t)n < size)
        snprintf(buf + n, size - (size_t)n, ", frame %d of %d", p->frame, p->frames);
}

void progress_update(progress *p, const glint_progress *g)
{
    if (p->mode == PROGRESS_OFF)
        return;
    int percent = (int)g->percent;
    double t = cli_now();
    char text[160];
    if (p->mode == PROGRESS_LINES) {
        if (percent / 10 == p->last_percent / 10 && p->last_percent >= 0)
            return;
        p->last_percent = percent;
        describe(p, g, text, sizeof text);
        fprintf(p->out, "%s: %s\n", p->name, text);
        fflush(p->out);
        return;
    }
    if (percent == p->last_percent && t - p->last_draw < REDRAW_SECONDS)
        return;
    p->last_percent = percent;
    p->last_draw = t;
    describe(p, g, text, sizeof text);
    int fill = percent * BAR_WIDTH / 100;
    fputs("\r\033[K[", p->out);
    for (int i = 0; i < BAR_WIDTH; i++)
        fputc(i < fill ? '#' : '.', p->out);
    fprintf(p->out, "] %s", text);
    fflush(p->out);
    p->open = true;
}

void progress_end(progress *p)
{
    if (p->open) {
        fputc('\n', p->out);
        fflush(p->out);
        p->open = false;
    }
}

void progress_phase(progress *p, const char *what)
{
    if (p->mode == PROGRESS_OFF)
        return;
    if (p->mode == PROGRESS_BAR) {
        fprintf(p->out, "\r\033[K%s", what);
        p->open = true;
    } else {
        fprintf(p->out, "%s: %s\n", p->name, what);
    }
    fflush(p->out);
}

void progress_clear(progress *p)
{
    if (p->open && p->mode == PROGRESS_BAR) {
        fputs("\r\033[K", p->out);
        fflush(p->out);
        p->open = false;
    }
}
