/* signals: Ctrl-C (SIGINT) and SIGTERM while glint works. The first asks
 * the work to stop: the render's cancel callback polls signals_caught, the
 * render stops within one tile, and glint keeps what it has (a resume
 * file) and exits with 128 + the signal (130, 143). A second one exits at
 * once, with the same code, unless the process that sent the first sent it
 * within half a second (timeout(1) sends its signal twice). The flag is the one piece of process-wide state
 * in glint (and in each process of glint-mpi), as a signal handler can
 * reach nothing else. */
#ifndef GLINT_CLI_SIGNALS_H
#define GLINT_CLI_SIGNALS_H

void signals_install(void);
/* The signal caught since signals_install, or 0. */
int signals_caught(void);
/* 128 + sig: the shell's convention for a process ended by sig. */
int signals_exit_code(int sig);

#endif
