/* A frame sequence across the processes of a job. With at least as many
 * frames to render as processes, each process renders whole frames and
 * writes each one as it is done (a shared file system), rank 0 handing
 * them out one at a time and rendering frames too; so a job stopped at any
 * point leaves every finished frame on disk for --resume. With fewer
 * frames than processes, the frames are rendered one after another, each
 * shared out in tiles as a single image is. Frame numbering, names and
 * completeness are the library's (glint_frame_path, glint_output_complete).
 * As with glint, each frame goes through a resume record: a process stopped
 * by a signal keeps the frame it was rendering in its own FRAME.resume, and
 * --resume continues it and skips the frames already complete. */
#include <mpi.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli/rerun.h"
#include "cli/signals.h"
#include "job.h"
#include "report.h"

typedef struct frames {
    const dist_job *job;
    const int *todo; /* frame numbers to render */
    int n, next;
    pthread_mutex_t lock; /* next, rc, err, ranks[0] */
    glint_rc rc;
    glint_error err;
    dist_rank *ranks;
    atomic_int done;
    atomic_bool local_done;
} frames;

static int on_cancel(void *user)
{
    (void)user;
    return signals_caught() != 0;
}

/* Renders the scene as it stands into path through a resume record, as
 * glint does: continued from path.resume with --resume, kept there when a
 * signal stops it (GLINT_ERR_CANCELLED). */
static glint_rc render_resumable(const dist_job *job, const char *path, glint_stats *st,
                                 glint_error *err)
{
    glint_resume rec = {0};
    bool resumed = false;
    char *rpath = rerun_path(path);
    glint_rc rc = rpath ? GLINT_OK : GLINT_ERR_NOMEM;
    if (rc == GLINT_OK)
        rc = rerun_open(job->opt, job->scene, &job->settings, rpath, &rec, &resumed, err);
    glint_callbacks cb = {.cancelled = on_cancel};
    if (rc == GLINT_OK)
        rc = glint_resume_render(job->scene, &job->settings, &cb, &rec, st, err);
    if (rc == GLINT_ERR_CANCELLED && signals_caught()) {
        rerun_keep(job->opt, &rec, rpath, false);
    } else if (rc == GLINT_OK) {
        glint_write_options w = job->opt->write;
        w.transfer = job->settings.transfer;
        w.threads = job->settings.threads;
        rc = glint_film_write(&rec.film, path, &w, err);
        if (rc == GLINT_OK && resumed)
            unlink(rpath);
    } else if (!rpath) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
    }
    glint_resume_free(&rec);
    free(rpath);
    return rc;
}

/* Renders frame into its file; the counts go to acc. */
static glint_rc render_frame(const dist_job *job, int frame, dist_rank *acc, glint_error *err)
{
    char path[4096];
    glint_rc rc = glint_frame_path(job->opt->output, frame, path, sizeof path, err);
    if (rc == GLINT_OK)
        rc = glint_scene_set_frame(job->scene, frame, err);
    glint_stats st = {0};
    double t0 = cli_now();
    if (rc == GLINT_OK)
        rc = render_resumable(job, path, &st, err);
    acc->busy += cli_now() - t0;
    acc->tiles += rc == GLINT_OK;
    acc->batches++;
    acc->primary += st.primary_rays;
    acc->secondary += st.secondary_rays;
    acc->shadow += st.shadow_rays;
    return rc;
}

static int take_frame(frames *f)
{
    pthread_mutex_lock(&f->lock);
    int frame = f->rc == GLINT_OK && f->next < f->n ? f->todo[f->next++] : 0;
    pthread_mutex_unlock(&f->lock);
    return frame;
}

static void fail(frames *f, glint_rc rc, const char *msg)
{
    pthread_mutex_lock(&f->lock);
    if (f->rc == GLINT_OK) {
        f->rc = rc;
        snprintf(f->err.msg, sizeof f->err.msg, "%s", msg);
    }
    pthread_mutex_unlock(&f->lock);
}

static void *local_main(void *arg)
{
    frames *f = arg;
    int frame;
    while ((frame = take_frame(f)) > 0) {
        dist_rank mine = {0};
        glint_error err = {0};
        glint_rc rc = render_frame(f->job, frame, &mine, &err);
        pthread_mutex_lock(&f->lock);
        dist_rank *r = &f->ranks[0];
        r->busy += mine.busy;
        r->tiles += mine.tiles;
        r->batches += mine.batches;
        r->primary += mine.primary;
        r->secondary += mine.secondary;
        r->shadow += mine.shadow;
        pthread_mutex_unlock(&f->lock);
        if (rc != GLINT_OK)
            fail(f, rc, err.msg);
        else
            atomic_fetch_add(&f->done, 1);
    }
    atomic_store(&f->local_done, true);
    return NULL;
}

/* Sends rank its next frame, or 0: nothing more. */
static bool give(frames *f, int rank)
{
    int work[2] = {take_frame(f), 1};
    if (work[0] == 0)
        work[1] = 0;
    MPI_Send(work, 2, MPI_INT, rank, TAG_WORK, MPI_COMM_WORLD);
    return work[1] > 0;
}

/* One answer in: the frame written, or a failure with its message. */
static void take_in(frames *f, int rank)
{
    struct {
        dist_result h;
        char msg[sizeof f->err.msg];
    } m;
    MPI_Recv(&m, (int)sizeof m, MPI_BYTE, rank, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (m.h.rc != GLINT_OK) {
        m.msg[sizeof m.msg - 1] = '\0';
        fail(f, (glint_rc)m.h.rc, m.msg);
        return;
    }
    dist_rank *r = &f->ranks[rank];
    r->busy += m.h.busy;
    r->tiles++;
    r->batches++;
    r->primary += m.h.primary;
    r->secondary += m.h.secondary;
    r->shadow += m.h.shadow;
    atomic_fetch_add(&f->done, 1);
}

/* The bar: the share of the frames done. */
static void report(frames *f, progress *bar, double start)
{
    pthread_mutex_lock(&f->lock);
    uint64_t rays = 0;
    for (int r = 0; r < f->job->size; r++)
        rays += f->ranks[r].primary + f->ranks[r].secondary + f->ranks[r].shadow;
    pthread_mutex_unlock(&f->lock);
    int done = atomic_load(&f->done);
    glint_progress p = {.percent = 100.0 * done / f->n, .samples_done = (uint64_t)done,
                        .samples_total = (uint64_t)f->n, .rays = rays,
                        .seconds = cli_now() - start};
    progress_update(bar, &p);
}

/* Rank 0: hands out frames, renders some, until every rank is done or a
 * signal stops the job. */
static glint_rc lead_frames(frames *f, glint_error *err)
{
    int size = f->job->size, busy = 0;
    pthread_t local;
    bool started = pthread_create(&local, NULL, local_main, f) == 0;
    if (!started) {
        fail(f, GLINT_ERR_NOMEM, "cannot start a render thread");
        atomic_store(&f->local_done, true);
    }
    for (int r = 1; r < size; r++)
        busy += give(f, r);
    progress bar;
    progress_begin(&bar, stderr, dist_progress_mode(f->job->opt), "glint-mpi");
    double start = cli_now();
    while ((busy > 0 || !atomic_load(&f->local_done)) && !signals_caught()) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &flag, &st);
        if (flag) {
            take_in(f, st.MPI_SOURCE);
            busy -= !give(f, st.MPI_SOURCE);
        } else {
            report(f, &bar, start);
            nanosleep(&(struct timespec){0, 1000000}, NULL);
        }
    }
    if (started)
        pthread_join(local, NULL);
    if (!signals_caught())
        report(f, &bar, start);
    progress_end(&bar);
    if (signals_caught()) {
        fprintf(stderr, "glint-mpi: interrupted; each frame in progress is kept in its .resume "
                        "file (continue with the same command and --resume)\n");
        snprintf(err->msg, sizeof err->msg, "interrupted");
        return err->code = GLINT_ERR_CANCELLED;
    }
    if (f->rc != GLINT_OK)
        *err = f->err;
    return f->rc;
}

/* Every other rank: renders the frames it is sent, answering each. */
static glint_rc follow_frames(const dist_job *job, glint_error *err)
{
    glint_rc rc = GLINT_OK;
    for (;;) {
        int work[2];
        if (!dist_wait(0, TAG_WORK, NULL, NULL))
            return GLINT_ERR_CANCELLED;
        MPI_Recv(work, 2, MPI_INT, 0, TAG_WORK, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (work[1] == 0)
            break;
        dist_rank mine = {0};
        if (rc == GLINT_OK)
            rc = render_frame(job, work[0], &mine, err);
        if (signals_caught())
            return GLINT_ERR_CANCELLED; /* rank 0 is stopping too */
        struct {
            dist_result h;
            char msg[sizeof err->msg];
        } m = {{(int32_t)rc, work[0], 1, 0, mine.busy, mine.primary, mine.secondary, mine.shadow},
               {0}};
        if (rc != GLINT_OK)
            memcpy(m.msg, err->msg, sizeof m.msg);
        MPI_Send(&m, (int)sizeof m, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
    }
    return rc;
}

/* Frames fewer than processes: one after another, each in tiles. */
static glint_rc tiled_frames(const dist_job *job, const int *todo, int n, dist_rank *ranks,
                             double *seconds, glint_error *err)
{
    glint_rc rc = GLINT_OK;
    progress bar;
    progress_begin(&bar, stderr, dist_progress_mode(job->opt), "glint-mpi");
    for (int i = 0; i < n && rc == GLINT_OK; i++) {
        progress_frame(&bar, i + 1, n);
        char path[4096];
        rc = glint_frame_path(job->opt->output, todo[i], path, sizeof path, err);
        if (rc == GLINT_OK)
            rc = glint_scene_set_frame(job->scene, todo[i], err);
        /* the same on every rank: the names and frames were checked before */
        if (rc == GLINT_OK && job->rank == 0) {
            rc = dist_image_once(job, path, &bar, ranks, NULL, NULL, seconds, err);
        } else if (rc == GLINT_OK) {
            rc = dist_work(job, err);
        }
        if (signals_caught())
            return GLINT_ERR_CANCELLED; /* each process is stopping */
        int code = (int)rc;
        MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
        if (code != GLINT_OK && rc == GLINT_OK)
            rc = (glint_rc)code; /* rank 0 says why */
    }
    return rc;
}

/* Frames first..last of the options' output pattern, --resume leaving out
 * those already complete: every rank gets rank 0's list. */
static glint_rc frame_list(const dist_job *job, int **todo, int *n, glint_error *err)
{
    glint_rc rc = GLINT_OK;
    int count = 0;
    int *list = NULL;
    if (job->rank == 0) {
        list = malloc((size_t)(job->last - job->first + 1) * sizeof *list);
        if (!list) {
            snprintf(err->msg, sizeof err->msg, "out of memory");
            rc = GLINT_ERR_NOMEM;
        }
        for (int f = job->first; rc == GLINT_OK && f <= job->last; f++) {
            char path[4096];
            rc = glint_frame_path(job->opt->output, f, path, sizeof path, err);
            if (rc == GLINT_OK && !rerun_done(job->opt, path, &job->settings))
                list[count++] = f;
        }
        if (rc != GLINT_OK)
            count = -1;
    }
    MPI_Bcast(&count, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (count > 0 && job->rank != 0 && !(list = malloc((size_t)count * sizeof *list)))
        MPI_Abort(MPI_COMM_WORLD, 1); /* a few ints: the process is in no state to go on */
    if (count > 0)
        MPI_Bcast(list, count, MPI_INT, 0, MPI_COMM_WORLD);
    *todo = list;
    *n = count;
    return count < 0 ? (job->rank == 0 ? rc : GLINT_ERR_NOMEM) : GLINT_OK;
}

glint_rc dist_frames(const dist_job *job, glint_error *err)
{
    int *todo = NULL, n = 0;
    glint_rc rc = frame_list(job, &todo, &n, err);
    dist_rank *ranks = job->rank == 0 ? calloc((size_t)job->size, sizeof *ranks) : NULL;
    double t0 = cli_now(), seconds = 0;
    bool whole = n >= job->size;
    if (rc == GLINT_OK && job->rank == 0 && !ranks)
        MPI_Abort(MPI_COMM_WORLD, 1);
    if (rc == GLINT_OK && n > 0 && whole && job->rank == 0) {
        frames f = {.job = job, .todo = todo, .n = n, .ranks = ranks};
        pthread_mutex_init(&f.lock, NULL);
        atomic_init(&f.done, 0);
        atomic_init(&f.local_done, false);
        rc = lead_frames(&f, err);
        pthread_mutex_destroy(&f.lock);
        seconds = cli_now() - t0;
    } else if (rc == GLINT_OK && n > 0 && whole) {
        rc = follow_frames(job, err);
    } else if (rc == GLINT_OK && n > 0) {
        rc = tiled_frames(job, todo, n, ranks, &seconds, err);
    }
    if (rc == GLINT_OK && job->rank == 0 && job->opt->stats)
        dist_print_stats(stderr, job, ranks, seconds, whole || n == 0 ? "frames" : "tiles", n);
    free(ranks);
    free(todo);
    return rc;
}
