/* One image across the processes of a job: rank 0 coordinates (coord.c)
 * and writes it, the others render what they are sent (worker.c). */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

#include "job.h"
#include "report.h"

/* Tells every other rank there is nothing (more) to render. */
static void end_all(const dist_job *job)
{
    int end[2] = {0, 0};
    for (int r = 1; r < job->size; r++)
        MPI_Send(end, 2, MPI_INT, r, TAG_WORK, MPI_COMM_WORLD);
}

glint_rc dist_image_once(const dist_job *job, const char *path, dist_rank *ranks, double *costs,
                         int *owner, double *seconds, glint_error *err)
{
    glint_film film = {0};
    glint_rc rc = dist_coordinate(job, &film, ranks, costs, owner, seconds, err);
    if (rc == GLINT_OK) {
        glint_write_options w = job->opt->write;
        w.transfer = job->settings.transfer;
        rc = glint_film_write(&film, path, &w, err);
    }
    glint_film_free(&film);
    return rc;
}

/* Rank 0's part: the render, then the image, the statistics and costs. */
static glint_rc lead(const dist_job *job, glint_error *err)
{
    const dist_options *o = job->opt;
    const glint_settings *s = &job->settings;
    if (o->resume && glint_output_complete(o->output, s->width, s->height)) {
        end_all(job);
        return GLINT_OK;
    }
    dist_rank *ranks = calloc((size_t)job->size, sizeof *ranks);
    double *costs = o->tile_costs ? calloc((size_t)job->ntiles, sizeof *costs) : NULL;
    int *owner = o->tile_costs ? calloc((size_t)job->ntiles, sizeof *owner) : NULL;
    double seconds = 0;
    glint_rc rc = GLINT_OK;
    if (!ranks || (o->tile_costs && (!costs || !owner))) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        rc = GLINT_ERR_NOMEM;
        end_all(job);
    }
    if (rc == GLINT_OK)
        rc = dist_image_once(job, o->output, ranks, costs, owner, &seconds, err);
    if (rc == GLINT_OK && o->tile_costs)
        rc = dist_write_costs(o->tile_costs, job, costs, owner, err);
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
