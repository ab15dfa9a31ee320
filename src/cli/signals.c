#include "signals.h"

#include <signal.h>
#include <string.h>
#include <unistd.h>

static volatile sig_atomic_t caught;

static void on_signal(int sig)
{
    if (caught) {
        /* the second: leave now, ending the progress line first */
        (void)!write(STDERR_FILENO, "\n", 1);
        _exit(signals_exit_code(sig));
    }
    caught = sig;
}

void signals_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    /* a SIGINT ignored from the start (a shell's background job) stays ignored */
    struct sigaction old;
    if (sigaction(SIGINT, NULL, &old) == 0 && old.sa_handler != SIG_IGN)
        sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

int signals_caught(void) { return (int)caught; }

int signals_exit_code(int sig) { return 128 + sig; }
