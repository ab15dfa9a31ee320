#define _GNU_SOURCE /* sched_getaffinity */
#include "cpus.h"

#include <pthread.h>
#include <sched.h>
#include <stdlib.h>
#include <unistd.h>

int cpus_available(void)
{
#if defined(CPU_COUNT)
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0)
        return CPU_COUNT(&set);
#endif
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (n < 1 << 20 ? (int)n : 1 << 20) : 1;
}

int cpus_threads(int threads, int max)
{
    int n = threads > 0 ? threads : cpus_available();
    return n < max ? n : max;
}

/* Threads whose handles cpus_share keeps on its stack; more take memory,
 * and without it no more start. */
#define SHARE_ON_STACK 15

void cpus_share(int n, void *(*fn)(void *), void *arg)
{
    pthread_t local[SHARE_ON_STACK], *th = local;
    int extra = n > 1 ? n - 1 : 0;
    if (extra > SHARE_ON_STACK && !(th = malloc(sizeof *th * (size_t)extra))) {
        th = local;
        extra = SHARE_ON_STACK;
    }
    int started = 0;
    for (; started < extra; started++)
        if (pthread_create(&th[started], NULL, fn, arg) != 0)
            break;
    fn(arg);
    for (int i = 0; i < started; i++)
        pthread_join(th[i], NULL);
    if (th != local)
        free(th);
}
