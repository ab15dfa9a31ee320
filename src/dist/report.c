#include "report.h"

#include <errno.h>
#include <string.h>
#include <unistd.h>

progress_mode dist_progress_mode(const struct cli *o)
{
    /* Under mpirun, rank 0's standard output is a terminal when mpirun's is
     * but its standard error is a pipe to mpirun, which passes it on. */
    return progress_choose(o->quiet, o->progress, isatty(STDERR_FILENO) || isatty(STDOUT_FILENO));
}

/* How the settings sample a pixel, as glint --stats says it. */
static void sampling(const glint_settings *s, char *how, size_t n)
{
    if (s->sampler == GLINT_SAMPLER_ADAPTIVE)
        snprintf(how, n, "adaptive sampling (threshold %g, max_depth %d)", s->threshold,
                 s->adaptive_depth);
    else
        snprintf(how, n, "%d samples/pixel%s", s->samples,
                 s->sampler == GLINT_SAMPLER_JITTER ? " (jittered)" : "");
}

void dist_print_stats(FILE *out, const dist_job *job, const dist_rank *ranks, double seconds,
                      const char *unit, int images)
{
    const glint_settings *s = &job->settings;
    uint64_t primary = 0, secondary = 0, shadow = 0;
    double busy = 0;
    for (int r = 0; r < job->size; r++) {
        primary += ranks[r].primary;
        secondary += ranks[r].secondary;
        shadow += ranks[r].shadow;
        busy += ranks[r].busy;
    }
    uint64_t total = primary + secondary + shadow;
    double pixels = (double)s->width * (double)s->height * (images > 0 ? images : 1);
    char how[96];
    sampling(s, how, sizeof how);
    fprintf(out,
            "image:   %dx%d, %s, depth %d, %d process%s x %d thread%s\n"
            "rays:    %llu (%llu primary, %llu secondary, %llu shadow)\n"
            "samples: %.2f per pixel on average\n"
            "time:    %.3f s\n"
            "speed:   %.2f Mrays/s\n",
            s->width, s->height, how, s->max_depth, job->size, job->size == 1 ? "" : "es",
            s->threads, s->threads == 1 ? "" : "s", (unsigned long long)total,
            (unsigned long long)primary, (unsigned long long)secondary,
            (unsigned long long)shadow, (double)primary / pixels, seconds,
            seconds > 0 ? (double)total / seconds * 1e-6 : 0.0);
    if (job->first > 0)
        fprintf(out, "frames:  %d rendered\n", images);
    for (int r = 0; r < job->size; r++)
        fprintf(out, "rank %d:  %d %s in %d batches, busy %.3f s, efficiency %.1f%%\n", r,
                ranks[r].tiles, unit, ranks[r].batches, ranks[r].busy,
                seconds > 0 ? 100.0 * ranks[r].busy / seconds : 0.0);
    fprintf(out, "all:     efficiency %.1f%% (busy time / (processes x time))\n",
            seconds > 0 ? 100.0 * busy / (seconds * job->size) : 0.0);
}

glint_rc dist_write_costs(const char *path, const dist_job *job, const double *costs,
                          const int *owner, glint_error *err)
{
    const glint_settings *s = &job->settings;
    FILE *f = fopen(path, "w");
    if (!f) {
        snprintf(err->msg, sizeof err->msg, "%s: cannot write the tile costs: %s", path,
                 strerror(errno));
        return GLINT_ERR_IO;
    }
    fprintf(f, "# glint tile costs: %dx%d, %d-pixel tiles, %d tiles, %d samples/pixel, depth %d\n",
            s->width, s->height, DIST_TILE, job->ntiles, s->samples, s->max_depth);
    fprintf(f, "# %d process%s x %d thread%s; seconds: CPU time of the thread that rendered the tile\n", job->size,
            job->size == 1 ? "" : "es", s->threads, s->threads == 1 ? "" : "s");
    fprintf(f, "# tile x0 y0 x1 y1 seconds rank\n");
    for (int t = 0; t < job->ntiles; t++) {
        glint_rect r;
        glint_tile_rect(s, t, &r, err);
        fprintf(f, "%d %d %d %d %d %.9f %d\n", t, r.x0, r.y0, r.x1, r.y1, costs[t], owner[t]);
    }
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        snprintf(err->msg, sizeof err->msg, "%s: cannot write the tile costs: %s", path,
                 strerror(errno));
        return GLINT_ERR_IO;
    }
    return GLINT_OK;
}
