#include "signals.h"

#include <signal.h>
#include <stdbool.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* A second signal from the process that sent the first, this soon after
 * it, is the same request sent twice: timeout(1), when its time is up,
 * sends its signal to the command and then to the command's process group,
 * and the command may take the first before the second is sent. A person
 * hardly sends two so fast from one shell; a terminal's Ctrl-C comes from
 * the kernel (sender 0) and a second one always leaves at once. */
#define SIGNALS_SAME_WITHIN_NS 500000000L

static volatile sig_atomic_t caught;
static volatile pid_t first_sender; /* 0: the kernel (a terminal's Ctrl-C), or raise */
static struct timespec first_at;

static bool same_request(int sig, const siginfo_t *si)
{
    if (sig != caught || si->si_code != SI_USER || si->si_pid == 0 ||
        si->si_pid != first_sender)
        return false;
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now); /* async-signal-safe */
    long ns = (long)(now.tv_sec - first_at.tv_sec) * 1000000000L + (now.tv_nsec - first_at.tv_nsec);
    return ns < SIGNALS_SAME_WITHIN_NS;
}

static void on_signal(int sig, siginfo_t *si, void *context)
{
    (void)context;
    if (caught) {
        if (same_request(sig, si))
            return;
        /* the second: leave now, ending the progress line first */
        (void)!write(STDERR_FILENO, "\n", 1);
        _exit(signals_exit_code(sig));
    }
    first_sender = si->si_code == SI_USER ? si->si_pid : 0;
    clock_gettime(CLOCK_MONOTONIC, &first_at);
    caught = sig;
}

void signals_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_sigaction = on_signal;
    sa.sa_flags = SA_SIGINFO;
    sigemptyset(&sa.sa_mask);
    /* a SIGINT ignored from the start (a shell's background job) stays ignored */
    struct sigaction old;
    if (sigaction(SIGINT, NULL, &old) == 0 && old.sa_handler != SIG_IGN)
        sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

int signals_caught(void) { return (int)caught; }

int signals_exit_code(int sig) { return 128 + sig; }
