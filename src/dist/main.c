/* glint-mpi: glint's command line, rendering one image with the processes
 * of an MPI job (mpirun, srun). Every process loads the scene itself (a
 * shared file system, as on clusters); rank 0 hands out the tiles, renders
 * some itself and writes the image, which is byte for byte the one glint
 * writes. Problems before the render (options, output name, scene) are
 * agreed on by all processes and reported once, by rank 0. The protocol is
 * in job.h; README.md, "Rendering on a cluster", tells what happens when a
 * process fails. A job stopped by a signal keeps its tiles (job.h) and
 * each process exits with 128 + the signal, as glint does. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/heap.h"
#include "cli/signals.h"
#include "job.h"
#include "options.h"

/* Each process's result before the render becomes the job's: the failure
 * of the lowest rank that failed, its message carried to rank 0. */
static glint_rc agree(const dist_job *job, glint_rc rc, glint_error *err)
{
    int mine = rc != GLINT_OK ? job->rank : job->size, first = job->size;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == job->size)
        return GLINT_OK;
    struct {
        int rc;
        char msg[sizeof err->msg];
    } m = {(int)rc, {0}};
    memcpy(m.msg, err->msg, sizeof m.msg);
    if (first != 0 && job->rank == first)
        MPI_Send(&m, (int)sizeof m, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
    else if (first != 0 && job->rank == 0)
        MPI_Recv(&m, (int)sizeof m, MPI_BYTE, first, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    MPI_Bcast(&m, (int)sizeof m, MPI_BYTE, 0, MPI_COMM_WORLD);
    memcpy(err->msg, m.msg, sizeof err->msg);
    err->msg[sizeof err->msg - 1] = '\0';
    return (glint_rc)m.rc;
}

/* The frames of --frames or --frame against the scene's animation; the
 * message says which option. */
static glint_rc frames_of(dist_job *job, glint_error *err)
{
    glint_animation anim;
    glint_rc rc = glint_scene_animation(job->scene, &anim, err);
    if (rc == GLINT_OK)
        rc = glint_frames_parse(job->opt->frames, anim.frames, &job->first, &job->last, err);
    if (rc != GLINT_OK) {
        char msg[900];
        snprintf(msg, sizeof msg, "%.899s", err->msg);
        snprintf(err->msg, sizeof err->msg, "--frame%s: %.900s",
                 job->opt->one_frame ? "" : "s", msg);
    }
    return rc;
}

/* The output name (rank 0, which writes it; the first frame's for a
 * sequence), the scene, the settings and the frames. */
static glint_rc prepare(dist_job *job, glint_error *err)
{
    const struct cli *o = job->opt;
    char path[4096];
    glint_load_options lo = {o->threads > 0 ? o->threads : 0}; /* -t bounds every thread */
    glint_rc rc = GLINT_OK;
    if (o->frames)
        rc = glint_frame_path(o->output, 1, path, sizeof path, err);
    if (rc == GLINT_OK && job->rank == 0)
        rc = glint_output_check(o->frames ? path : o->output, &o->write, err);
    if (rc == GLINT_OK) {
        heap_ready(o->scene_path, o->threads, 0);
        rc = o->scene_path ? glint_scene_load_with(o->scene_path, &lo, &job->scene, err)
                           : glint_scene_builtin_with(&lo, &job->scene, err);
        heap_settle();
    }
    if (rc == GLINT_OK)
        rc = dist_settings(job->scene, o, &job->settings, err);
    if (rc == GLINT_OK)
        rc = glint_tile_count(&job->settings, &job->ntiles, err);
    if (rc == GLINT_OK && o->frames)
        rc = frames_of(job, err);
    return rc;
}

int main(int argc, char **argv)
{
    int provided;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    dist_job job = {0};
    MPI_Comm_rank(MPI_COMM_WORLD, &job.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &job.size);
    struct cli o;
    char **kept = NULL;
    int code = dist_parse_options(argc, argv, job.rank, &o, &kept);
    if (code >= 0) {
        MPI_Finalize();
        return code;
    }
    job.opt = &o;
    glint_error err = {0};
    glint_rc rc = agree(&job, prepare(&job, &err), &err);
    if (rc == GLINT_OK) {
        signals_install();
        rc = job.first > 0 ? dist_frames(&job, &err) : dist_image(&job, &err);
    }
    if (signals_caught()) {
        /* every process is stopping (mpirun passes the signal on, or ends
         * the job when one process leaves): no more messages */
        glint_scene_free(job.scene);
        free(kept);
        return signals_exit_code(signals_caught());
    }
    /* the job's result is rank 0's: a rank's failure reached it as an answer */
    int final = (int)rc;
    MPI_Bcast(&final, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (job.rank == 0 && rc != GLINT_OK)
        fprintf(stderr, "glint-mpi: %s\n", err.msg);
    glint_scene_free(job.scene);
    free(kept);
    MPI_Finalize();
    return glint_exit_code((glint_rc)final);
}
