/* mpisim: replays glint-mpi's scheduling of one image for 2 to 1024
 * processes, from the tile costs of a real render (glint-mpi --tile-costs),
 * with a model of the network, and prints each scheme's efficiency: the
 * tiles' total cost / (processes x threads x time to the last pixel at
 * rank 0).
 *
 *   static: rank r renders tiles r, r + K, r + 2K, ... (interleaved, as
 *           OSPRay's MPI module hands out tiles) and sends each tile when
 *           it is done;
 *   dynamic: glint-mpi's scheme (src/dist/job.h): batches from the same
 *           scheduler code (src/dist/sched.c), DIST_DEPTH batches ahead,
 *           each answer earning the next; a rank waits while its answer
 *           is taken in (a blocking send), rank 0 renders too.
 *
 * The model: a message takes the latency, then its bytes cross rank 0's
 * link one message at a time at the bandwidth; rank 0 takes answers in one
 * at a time (a poll, the transfer, copying the pixels into the image at
 * the memory bandwidth), and that time is taken from its own renderer. A
 * process with T threads renders a batch's tiles on its threads in turn,
 * each tile to the first free thread.
 *
 * usage: mpisim COSTS [--threads T] [--latency SECONDS] [--bandwidth BYTES/S]
 * Without --latency/--bandwidth it prints two networks: 10 Gb/s Ethernet
 * (50 us, 1.25 GB/s) and 100 Gb/s InfiniBand (2 us, 12.5 GB/s). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dist/job.h"
#include "dist/sched.h"

#define POLL 100e-6    /* coordinator's sleep between polls (coord.c) */
#define MEM_BW 5e9     /* bytes/s copying pixels into the image */
#define HEAD_COST 2e-6 /* seconds per answer besides its bytes */
#define TILE_BYTES (16 * 16 * 3 * 4)

typedef struct net {
    const char *name;
    double latency, bandwidth;
} net;

typedef struct costs {
    int n;
    double *t;     /* seconds per tile (one thread) */
    double total;
    int width, height;
} costs;

/* ---- events -------------------------------------------------------------- */

enum { EV_WORK, EV_DONE, EV_READY, EV_RESUME, EV_GIVE, EV_LOCAL };

typedef struct event {
    double t;
    int kind, rank, first, count;
    long seq;
} event;

typedef struct heap {
    event *e;
    int n, cap;
    long seq;
} heap;

static bool before(const event *a, const event *b)
{
    return a->t < b->t || (a->t == b->t && a->seq < b->seq);
}

static void push(heap *h, event ev)
{
    if (h->n == h->cap) {
        h->cap = h->cap ? h->cap * 2 : 1024;
        h->e = realloc(h->e, (size_t)h->cap * sizeof *h->e);
        if (!h->e)
            exit(1);
    }
    ev.seq = h->seq++;
    int i = h->n++;
    while (i > 0 && before(&ev, &h->e[(i - 1) / 2])) {
        h->e[i] = h->e[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->e[i] = ev;
}

static event pop(heap *h)
{
    event top = h->e[0], last = h->e[--h->n];
    int i = 0;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= h->n)
            break;
        if (c + 1 < h->n && before(&h->e[c + 1], &h->e[c]))
            c++;
        if (!before(&h->e[c], &last))
            break;
        h->e[i] = h->e[c];
        i = c;
    }
    h->e[i] = last;
    return top;
}

/* ---- the processes ------------------------------------------------------- */

/* Time for T threads to render tiles first .. first + count - 1, each tile
 * to the first free thread. */
static double batch_time(const costs *c, int first, int count, int threads)
{
    double free_at[64] = {0}, end = 0;
    if (threads > 64)
        threads = 64;
    for (int i = first; i < first + count; i++) {
        int k = 0;
        for (int j = 1; j < threads; j++)
            if (free_at[j] < free_at[k])
                k = j;
        free_at[k] += c->t[i];
        if (free_at[k] > end)
            end = free_at[k];
    }
    return end;
}

/* Rank 0's side: the coordinator takes in one answer at a time; the time it
 * spends is taken from rank 0's renderer. */
typedef struct coord {
    double free_at;  /* coordinator busy until */
    double local_end;/* rank 0's batch ends (0: idle) */
    double last;     /* the last pixel in the image */
    double busy;     /* time spent taking answers in */
    int threads;
    net nw;
} coord;

/* Takes in an answer of bytes ready at t; returns when its transfer ended. */
static double take_in(coord *co, double t, double bytes, double *done)
{
    double start = t >= co->free_at ? t + POLL / 2 : co->free_at;
    double xfer = start + bytes / co->nw.bandwidth;
    co->free_at = xfer + bytes / MEM_BW + HEAD_COST;
    co->busy += co->free_at - start;
    if (co->local_end > start)
        co->local_end += (co->free_at - start) / co->threads;
    *done = co->free_at;
    if (co->free_at > co->last)
        co->last = co->free_at;
    return xfer;
}

static double batch_bytes(int count)
{
    return sizeof(dist_result) + count * (8.0 + TILE_BYTES);
}

typedef struct worker {
    int queue_first[DIST_DEPTH + 1], queue_count[DIST_DEPTH + 1];
    int queued;
    bool busy;
} worker;

static void start_next(heap *h, const costs *c, worker *w, int rank, double t, int threads)
{
    if (w->busy || w->queued == 0)
        return;
    int first = w->queue_first[0], count = w->queue_count[0];
    memmove(w->queue_first, w->queue_first + 1, (size_t)(w->queued - 1) * sizeof(int));
    memmove(w->queue_count, w->queue_count + 1, (size_t)(w->queued - 1) * sizeof(int));
    w->queued--;
    w->busy = true;
    push(h, (event){t + batch_time(c, first, count, threads), EV_DONE, rank, first, count, 0});
}

/* Hands rank its next batch at time t (rank 0 renders it at once). */
static void give(heap *h, sched *s, coord *co, const costs *c, int rank, double t)
{
    int first, n = sched_take(s, &first);
    if (n == 0)
        return;
    if (rank == 0) {
        co->local_end = t + batch_time(c, first, n, co->threads);
        push(h, (event){co->local_end, EV_LOCAL, 0, first, n, 0});
    } else {
        push(h, (event){t + co->nw.latency, EV_WORK, rank, first, n, 0});
    }
}

static double simulate_dynamic(const costs *c, int ranks, int threads, net nw, int *batches,
                               double *busy)
{
    heap h = {0};
    sched s;
    sched_init(&s, c->n, ranks, sched_min_batch(threads), DIST_MAX_BATCH);
    coord co = {0, 0, 0, 0, threads, nw};
    worker *w = calloc((size_t)ranks, sizeof *w);
    give(&h, &s, &co, c, 0, 0);
    for (int d = 0; d < DIST_DEPTH; d++)
        for (int r = 1; r < ranks; r++)
            give(&h, &s, &co, c, r, 0);
    double end = 0;
    *batches = 0;
    while (h.n > 0) {
        event ev = pop(&h);
        worker *me = &w[ev.rank];
        switch (ev.kind) {
        case EV_LOCAL:
            if (ev.t < co.local_end) { /* pushed back by the coordinator's work */
                ev.t = co.local_end;
                push(&h, ev);
                break;
            }
            co.local_end = 0;
            end = ev.t > end ? ev.t : end;
            (*batches)++;
            give(&h, &s, &co, c, 0, ev.t);
            break;
        case EV_WORK:
            me->queue_first[me->queued] = ev.first;
            me->queue_count[me->queued++] = ev.count;
            start_next(&h, c, me, ev.rank, ev.t, threads);
            break;
        case EV_DONE:
            push(&h, (event){ev.t + nw.latency, EV_READY, ev.rank, ev.first, ev.count, 0});
            break;
        case EV_READY: {
            double done, xfer = take_in(&co, ev.t, batch_bytes(ev.count), &done);
            push(&h, (event){xfer, EV_RESUME, ev.rank, 0, 0, 0});
            push(&h, (event){done, EV_GIVE, ev.rank, 0, 0, 0});
            (*batches)++;
            break;
        }
        case EV_RESUME:
            me->busy = false;
            start_next(&h, c, me, ev.rank, ev.t, threads);
            break;
        case EV_GIVE:
            give(&h, &s, &co, c, ev.rank, ev.t);
            break;
        }
    }
    free(w);
    free(h.e);
    *busy = co.busy;
    return end > co.last ? end : co.last;
}

static double simulate_static(const costs *c, int ranks, int threads, net nw)
{
    heap h = {0};
    coord co = {0, 0, 0, 0, threads, nw};
    double free_at[64];
    int tt = threads > 64 ? 64 : threads;
    double local_done = 0;
    for (int r = 0; r < ranks; r++) {
        for (int j = 0; j < tt; j++)
            free_at[j] = 0;
        for (int i = r; i < c->n; i += ranks) {
            int k = 0;
            for (int j = 1; j < tt; j++)
                if (free_at[j] < free_at[k])
                    k = j;
            free_at[k] += c->t[i];
            if (r == 0)
                local_done = free_at[k] > local_done ? free_at[k] : local_done;
            else
                push(&h, (event){free_at[k] + nw.latency, EV_READY, r, i, 1, 0});
        }
    }
    co.local_end = local_done;
    while (h.n > 0) {
        event ev = pop(&h);
        double done;
        take_in(&co, ev.t, batch_bytes(1), &done);
    }
    free(h.e);
    return co.local_end > co.last ? co.local_end : co.last;
}

/* ---- input and report ------------------------------------------------------ */

static int read_costs(const char *path, costs *c)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        perror(path);
        return 1;
    }
    char line[512];
    int cap = 0;
    *c = (costs){0};
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') {
            sscanf(line, "# glint tile costs: %dx%d", &c->width, &c->height);
            continue;
        }
        int t, x0, y0, x1, y1, rank;
        double s;
        if (sscanf(line, "%d %d %d %d %d %lf %d", &t, &x0, &y0, &x1, &y1, &s, &rank) != 7 ||
            t != c->n) {
            fprintf(stderr, "%s: line for tile %d is not 'tile x0 y0 x1 y1 seconds rank'\n", path, c->n);
            fclose(f);
            return 1;
        }
        if (c->n == cap) {
            cap = cap ? cap * 2 : 4096;
            c->t = realloc(c->t, (size_t)cap * sizeof *c->t);
            if (!c->t)
                exit(1);
        }
        c->t[c->n++] = s;
        c->total += s;
    }
    fclose(f);
    return c->n > 0 ? 0 : 1;
}

static void report(const costs *c, int threads, net nw)
{
    printf("\n%s: latency %.0f us, bandwidth %.2f GB/s; %d process%s threads each\n\n", nw.name,
           nw.latency * 1e6, nw.bandwidth * 1e-9, threads, threads == 1 ? "'" : "es'");
    printf("| processes | static interleaved | dynamic batches | batches | time (dynamic) | ideal time | "
           "rank 0 taking answers in |\n");
    printf("| ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for (int k = 2; k <= 1024; k *= 2) {
        int batches;
        double busy;
        double ts = simulate_static(c, k, threads, nw);
        double td = simulate_dynamic(c, k, threads, nw, &batches, &busy);
        double ideal = c->total / ((double)k * threads);
        printf("| %d | %.1f %% | %.1f %% | %d | %.4f s | %.4f s | %.0f %% of the time |\n", k,
               100 * ideal / ts, 100 * ideal / td, batches, td, ideal, 100 * busy / td);
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: mpisim COSTS [--threads T] [--latency S] [--bandwidth B/S]\n");
        return 2;
    }
    int threads = 1;
    net own = {"given network", -1, -1};
    for (int i = 2; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--threads") == 0)
            threads = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--latency") == 0)
            own.latency = atof(argv[i + 1]);
        else if (strcmp(argv[i], "--bandwidth") == 0)
            own.bandwidth = atof(argv[i + 1]);
    }
    if (threads < 1)
        threads = 1;
    costs c;
    if (read_costs(argv[1], &c) != 0)
        return 2;
    double worst = 0;
    for (int i = 0; i < c.n; i++)
        worst = c.t[i] > worst ? c.t[i] : worst;
    printf("%s: %dx%d, %d tiles, %.3f s of rendering in all (one thread), the costliest tile %.2f ms\n",
           argv[1], c.width, c.height, c.n, c.total, worst * 1e3);
    if (own.latency >= 0 || own.bandwidth > 0) {
        own.latency = own.latency < 0 ? 50e-6 : own.latency;
        own.bandwidth = own.bandwidth <= 0 ? 1.25e9 : own.bandwidth;
        report(&c, threads, own);
    } else {
        report(&c, threads, (net){"10 Gb/s Ethernet", 50e-6, 1.25e9});
        report(&c, threads, (net){"100 Gb/s InfiniBand", 2e-6, 12.5e9});
    }
    free(c.t);
    return 0;
}
