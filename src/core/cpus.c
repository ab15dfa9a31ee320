#define _GNU_SOURCE /* sched_getaffinity */
#include "cpus.h"

#include <sched.h>
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
