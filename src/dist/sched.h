/* sched: which tiles a process renders next, when K processes share one
 * image. Tiles go out in batches of consecutive tile numbers (neighbouring
 * pixels, so a batch's film is a few rows of tiles), from first to last,
 * with guided self-scheduling (Polychronopoulos and Kuck, 1987): a batch is
 * the tiles left divided by SCHED_FACTOR times the number of processes,
 * held between a smallest and a largest size. Early batches are big, so
 * there are few messages; late ones are small, so the processes finish
 * together. Tiles already final (a resumed render) are skipped: a batch
 * never takes one and ends before it, so a batch stays a run of
 * consecutive tiles. No MPI here: glint-mpi and the scheduler simulator in bench/
 * share this code. */
#ifndef GLINT_DIST_SCHED_H
#define GLINT_DIST_SCHED_H

/* Tile costs vary several times over an image (sky against glass), and a
 * batch is a run of neighbouring tiles, so its cost follows its region:
 * batches of 1/(16 K) of the tiles left keep one costly batch from
 * finishing late (bench/mpisim: 2 gives 69 % efficiency at 16 processes on
 * the built-in scene at 4K, 16 gives 99 %). */
#define SCHED_FACTOR 16

typedef struct sched {
    int ntiles;    /* tiles in the image */
    int next;      /* the first tile not handed out yet */
    int ranks;     /* processes taking batches */
    int min_batch; /* tiles, >= 1 */
    int max_batch; /* tiles, >= min_batch */
    const unsigned char *skip; /* NULL, or ntiles flags: non-zero, never handed out */
    int left;      /* tiles neither handed out nor skipped */
} sched;

/* A scheduler for ntiles tiles shared by ranks processes (both >= 1). */
void sched_init(sched *s, int ntiles, int ranks, int min_batch, int max_batch);

/* Leaves out the tiles whose flag is non-zero (ntiles flags, which must
 * outlive s and not change); before the first sched_take. */
void sched_skip(sched *s, const unsigned char *skip);

/* The next batch: its first tile in *first and its size as the result;
 * 0 when every tile has been handed out. */
int sched_take(sched *s, int *first);

/* The smallest batch for processes of threads render threads each: enough
 * tiles that the threads rarely wait for the batch's last tile. */
int sched_min_batch(int threads);

#endif
