/* cpus: how many CPUs this process may run on, which is what "one thread
 * per core" means everywhere (renders, builds, texture decoding, PNG
 * strips): mpirun, srun and taskset bind a process to its share of a
 * machine, and its threads should not crowd the others'. */
#ifndef GLINT_CORE_CPUS_H
#define GLINT_CORE_CPUS_H

/* The CPUs in the process's affinity mask (the online CPUs where there
 * is no mask), at least 1. */
int cpus_available(void);

/* threads when it is positive, else cpus_available(); at most max. */
int cpus_threads(int threads, int max);

/* Runs fn(arg) on n threads at once (at least one), the calling thread
 * among them, and returns when every one has returned: for work that the
 * threads take from a shared queue, so that a thread that cannot be
 * started leaves its share to the others. */
void cpus_share(int n, void *(*fn)(void *), void *arg);

#endif
