/* progress: what a render shows on stderr while it runs.
 *
 * On a terminal, one line redrawn in place: a bar, percent, time elapsed,
 * the time left (only once a few percent are done, so the first guess is
 * not wild; in minutes and hours for long renders), Mrays/s, and "frame k
 * of N" for sequences. Elsewhere, with --progress, plain lines every 10
 * percent, for logs. Then the phases after rendering ("writing out.png…")
 * and the final "wrote out.png (1920x1080, 2.3 s)" line. Updates come from
 * the renderer's progress callback, which the library serialises, or from
 * glint-mpi's rank 0 as the tiles of a job come in. */
#ifndef GLINT_CLI_PROGRESS_H
#define GLINT_CLI_PROGRESS_H

#include <stdbool.h>
#include <stdio.h>
#include "glint.h"

/* Percent done before an ETA is shown. */
#define PROGRESS_ETA_AFTER 3.0

typedef enum progress_mode {
    PROGRESS_OFF,   /* -q, or stderr is not a terminal and no --progress */
    PROGRESS_BAR,   /* a terminal: one line redrawn in place */
    PROGRESS_LINES, /* --progress without a terminal: a line every 10% */
} progress_mode;

typedef struct progress {
    FILE *out;
    const char *name; /* the program, before each plain line */
    progress_mode mode;
    int frame, frames; /* frames > 1: "frame k of N" */
    double start, last_draw;
    int last_percent;
    double base; /* percent done before this run (a resumed render); set by the caller */
    bool open; /* a bar line is drawn without its newline */
} progress;

/* The mode for these options, the output being a terminal or not. */
progress_mode progress_choose(bool quiet, bool forced, bool terminal);

/* name: the program, as plain lines begin ("glint: 40% ..."). */
void progress_begin(progress *p, FILE *out, progress_mode mode, const char *name);
void progress_update(progress *p, const glint_progress *g);
/* Ends the bar's line (after the last update, or on interruption). */
/* The next render is frame k (from 1) of a sequence of n: the line shows
 * "frame k of n" and the sequence's share done and time left. */
void progress_frame(progress *p, int k, int n);
void progress_end(progress *p);
/* A phase after rendering, such as "writing out.png…", on the bar's line. */
void progress_phase(progress *p, const char *what);
/* Clears a phase left on the bar's line. */
void progress_clear(progress *p);

/* "12.3s", "4m05s", "1h02m": a duration as the bar writes it. */
void progress_duration(double seconds, char *buf, size_t size);

#endif
