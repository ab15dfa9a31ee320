/* One image across the processes of a job: rank 0 coordinates (coord.c),
 * keeps the tiles in OUTPUT.resume as they come in and writes the image;
 * the others render what they are sent (worker.c). */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/rerun.h"
#include "job.h"
#include "report.h"

/* Tells every other rank there is nothing (more) to render. */
static void end_all(const dist_job *job)
{
    int end[2] = {0, 0};
    for (int r = 1; r < job->size; r++)
        MPI_Send(end, 2, MPI_INT, r, TAG_WORK, MPI_COMM_WORLD);
}

/* Writes the finished image, with its phase on the progress line. */
static glint_rc write_image(const dist_job *job, const char *path, const glint_film *film,
                            progress *bar, glint_error *err)
{
    char what[600];
    snprintf(what, sizeof what, "writing %.500s\xe2\x80\xa6", path);
    progress_phase(bar, what);
    glint_write_options w = job->opt->write;
    w.transfer = job->settings.transfer;
    w.threads = job->settings.threads;
    glint_rc rc = glint_film_write(film, path, &w, err);
    progress_clear(bar);
    return rc;
}

glint_rc dist_image_once(const dist_job *job, const char *path, progress *bar, dist_rank *ranks,
                         double *costs, int *owner, double *seconds, glint_error *err)
{
    glint_resume rec = {0};
    bool resumed = false;
    char *rpath = rerun_path(path);
    glint_rc rc = GLINT_OK;
    if (!rpath && strcmp(path, "-") != 0) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        rc = GLINT_ERR_NOMEM;
    }
    if (rc == GLINT_OK)
        rc = rerun_open(job->opt, job->scene, &job->settings, rpath, &rec, &resumed, err);
    if (rc != GLINT_OK) {
        end_all(job);
        free(rpath);
        return rc;
    }
    bar->base = rerun_percent(&rec);
    dist_gather g = {.rec = &rec, .rpath = rpath, .bar = bar, .ranks = ranks, .costs = costs,
                     .owner = owner};
    rc = dist_coordinate(job, &g, err);
    progress_end(bar);
    *seconds += g.seconds;
    if (rc == GLINT_OK)
        rc = write_image(job, path, &rec.film, bar, err);
    /* the image is whole: its resume file has served (one left by another
     * run without --resume stays, as glint leaves it) */
    if (rc == GLINT_OK && rpath && (resumed || g.kept))
        unlink(rpath);
    glint_resume_free(&rec);
    free(rpath);
    return rc;
}

/* Rank 0's part: the render, then the image, the statistics and costs. */
static glint_rc lead(const dist_job *job, glint_error *err)
{
    const struct cli *o = job->opt;
    if (rerun_done(o, o->output, &job->settings)) {
        end_all(job);
        return GLINT_OK;
    }
    dist_rank *ranks = calloc((size_t)job->size, sizeof *ranks);
    double *costs = o->tile_costs ? calloc((size_t)job->ntiles, sizeof *costs) : NULL;
    int *owner = o->tile_costs ? calloc((size_t)job->ntiles, sizeof *owner) : NULL;
    double seconds = 0, t0 = cli_now();
    glint_rc rc = GLINT_OK;
    if (!ranks || (o->tile_costs && (!costs || !owner))) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        rc = GLINT_ERR_NOMEM;
        end_all(job);
    }
    progress bar;
    progress_begin(&bar, stderr, dist_progress_mode(o), "glint-mpi");
    if (rc == GLINT_OK)
        rc = dist_image_once(job, o->output, &bar, ranks, costs, owner, &seconds, err);
    if (rc == GLINT_OK && o->tile_costs)
        rc = dist_write_costs(o->tile_costs, job, costs, owner, err);
    if (rc == GLINT_OK && !o->quiet)
        fprintf(stderr, "wrote %s (%dx%d, %.1f s)\n", o->output, job->settings.width,
                job->settings.height, cli_now() - t0);
    if (rc == GLINT_OK && o->stats)
        dist_print_stats(stderr, job, ranks, seconds, "tiles", 1);
    free(ranks);
    free(costs);
    free(owner);
    return rc;
}

glint_rc dist_image(const dist_job *job, glint_error *err)
{
    return job->rank == 0 ? lead(job, err) : dist_work(job, err);
}
