/* job: what every process of a glint-mpi job shares, the messages between
 * rank 0 and the other ranks, and the pieces both sides use.
 *
 * Protocol (one image). Rank 0 coordinates and renders too. It sends each
 * other rank up to DIST_DEPTH batches ahead (TAG_WORK: first tile, count),
 * so a rank always has its next batch when it finishes one; a rank answers
 * each batch with TAG_RESULT: a dist_result header, the batch's tile costs
 * (count doubles) and its pixels (each tile's rows in turn, RGB floats), or
 * after a failure the header and a message. Each answer earns the next
 * batch; a count of 0 tells a rank that the image is done. Then rank 0
 * writes the image and broadcasts the job's result code, which every rank
 * returns. Processes are alike (same byte order and float format), as on a
 * cluster's nodes.
 *
 * Rank 0 keeps the final tiles in OUTPUT.resume as they come in (keep.c),
 * in glint's resume format, and hands out only the tiles not final in it
 * after --resume. A signal (mpirun passes SIGTERM or SIGINT to every
 * process) stops each process within a tile: rank 0 writes the resume file
 * with every tile it has, and each process exits with 128 + the signal,
 * without more messages, as the others are stopping too. */
#ifndef GLINT_DIST_JOB_H
#define GLINT_DIST_JOB_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>

#include "cli/cli.h"
#include "cli/progress.h"
#include "glint.h"

#define DIST_TILE 16          /* the side of the image's tile grid (glint.h) */
#define DIST_DEPTH 2          /* batches a rank holds: one rendering, one waiting */
#define DIST_MAX_BATCH 1024   /* tiles: about 3 MB of pixels a message */

enum { TAG_WORK = 1, TAG_RESULT = 2 };

typedef struct dist_result {
    int32_t rc; /* GLINT_OK, else a message of sizeof(glint_error.msg) follows */
    int32_t first, count;
    int32_t pad;
    double busy; /* seconds rendering the batch */
    uint64_t primary, secondary, shadow;
} dist_result;

/* What rank 0 learns about each rank. */
typedef struct dist_rank {
    int tiles, batches;
    double busy;
    uint64_t primary, secondary, shadow;
} dist_rank;

typedef struct dist_job {
    int rank, size;
    const struct cli *opt;
    glint_scene *scene;
    glint_settings settings;
    int ntiles;
    int first, last; /* frames of a sequence; 0, 0: a single image */
} dist_job;

/* The two kinds of job; every rank calls one, and rank 0 reports. */
glint_rc dist_image(const dist_job *job, glint_error *err);
glint_rc dist_frames(const dist_job *job, glint_error *err);

/* What rank 0 gathers of one image. */
typedef struct dist_gather {
    glint_resume *rec;  /* the image: its final tiles and their pixels */
    const char *rpath;  /* where they are kept as they come in; NULL: nowhere */
    progress *bar;
    dist_rank *ranks;   /* [size]: each rank's counts, added to */
    double *costs;      /* NULL, or [ntiles]: each tile's seconds */
    int *owner;         /* with costs: the rank that rendered each tile */
    double seconds;     /* the render's wall time */
    bool kept;          /* rpath was written */
} dist_gather;

/* Rank 0: one image into path, continued from path.resume with --resume
 * and kept there as the tiles come in, the other ranks working
 * (dist_work); the counts are added to ranks, costs and owner as in
 * dist_gather. GLINT_ERR_CANCELLED after a signal, the tiles kept. */
glint_rc dist_image_once(const dist_job *job, const char *path, progress *bar, dist_rank *ranks,
                         double *costs, int *owner, double *seconds, glint_error *err);

/* Rank 0: hands out the tiles not final in g->rec, renders its share and
 * gathers the others' into g->rec. */
glint_rc dist_coordinate(const dist_job *job, dist_gather *g, glint_error *err);
/* Every other rank: renders what rank 0 sends until told the image is done. */
glint_rc dist_work(const dist_job *job, glint_error *err);

/* ---- shared by both sides (batch.c) ---- */

/* Waits, polling (a blocking receive spins in Open MPI and takes a core
 * from the renderers), until a message with tag from source (or any rank,
 * -1) is there: its sender in *from and size in bytes in *bytes (either
 * may be NULL). false when a signal was caught instead. */
bool dist_wait(int source, int tag, int *from, int *bytes);

/* Times tiles as the render's callbacks report them: each tile's cost is
 * the CPU time its thread spent since its previous tile (or since the
 * batch began), the callbacks being called on the thread that rendered the
 * tile. CPU time, not wall time: other work on the machine does not count. */
typedef struct tile_clock {
    int n, cap;
    pthread_t *thread;
    double *last;
} tile_clock;

glint_rc tile_clock_init(tile_clock *c, int threads, glint_error *err);
void tile_clock_start(tile_clock *c);
double tile_clock_tick(tile_clock *c);
void tile_clock_free(tile_clock *c);

/* The smallest rectangle holding tiles first .. first + count - 1. */
glint_rect dist_batch_bounds(const glint_settings *s, int first, int count);
/* A film of w x h pixels, all zero, with coverage when settings.alpha. */
glint_rc dist_film_alloc(glint_film *f, const glint_settings *s, int w, int h, glint_error *err);
/* Pixels of the batch's tiles: floats, each tile's rows in turn (each row
 * RGB, then its coverage with settings.alpha). */
size_t dist_batch_floats(const glint_settings *s, int first, int count);
/* Copies the batch's tiles from a film of their bounds (box) into packed
 * floats, or back from packed floats into an image-sized film. */
void dist_batch_pack(const glint_settings *s, int first, int count, const glint_film *box,
                     glint_rect bounds, float *out);
void dist_batch_unpack(const glint_settings *s, int first, int count, const float *in,
                       glint_film *image);

#endif
