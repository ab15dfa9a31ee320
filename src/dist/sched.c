#include "sched.h"

void sched_init(sched *s, int ntiles, int ranks, int min_batch, int max_batch)
{
    s->ntiles = ntiles;
    s->next = 0;
    s->ranks = ranks < 1 ? 1 : ranks;
    s->min_batch = min_batch < 1 ? 1 : min_batch;
    s->max_batch = max_batch < s->min_batch ? s->min_batch : max_batch;
}

int sched_take(sched *s, int *first)
{
    int left = s->ntiles - s->next;
    if (left <= 0)
        return 0;
    int n = (left + SCHED_FACTOR * s->ranks - 1) / (SCHED_FACTOR * s->ranks);
    if (n < s->min_batch)
        n = s->min_batch;
    if (n > s->max_batch)
        n = s->max_batch;
    if (n > left)
        n = left;
    *first = s->next;
    s->next += n;
    return n;
}

int sched_min_batch(int threads)
{
    return threads < 1 ? 4 : 4 * threads;
}
