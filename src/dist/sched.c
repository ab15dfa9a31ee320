#include "sched.h"

#include <stdbool.h>
#include <stddef.h>

void sched_init(sched *s, int ntiles, int ranks, int min_batch, int max_batch)
{
    s->ntiles = ntiles;
    s->next = 0;
    s->ranks = ranks < 1 ? 1 : ranks;
    s->min_batch = min_batch < 1 ? 1 : min_batch;
    s->max_batch = max_batch < s->min_batch ? s->min_batch : max_batch;
    s->skip = NULL;
    s->left = ntiles;
}

void sched_skip(sched *s, const unsigned char *skip)
{
    s->skip = skip;
    s->left = 0;
    for (int i = s->next; i < s->ntiles; i++)
        s->left += !skip[i];
}

static bool skipped(const sched *s, int tile) { return s->skip && s->skip[tile]; }

int sched_take(sched *s, int *first)
{
    while (s->next < s->ntiles && skipped(s, s->next))
        s->next++;
    int left = s->left;
    if (left <= 0 || s->next >= s->ntiles)
        return 0;
    int n = (left + SCHED_FACTOR * s->ranks - 1) / (SCHED_FACTOR * s->ranks);
    if (n < s->min_batch)
        n = s->min_batch;
    if (n > s->max_batch)
        n = s->max_batch;
    if (n > left)
        n = left;
    for (int i = 1; i < n; i++)
        if (skipped(s, s->next + i))
            n = i; /* the run ends before a skipped tile */
    *first = s->next;
    s->next += n;
    s->left -= n;
    return n;
}

int sched_min_batch(int threads)
{
    return threads < 1 ? 4 : 4 * threads;
}
