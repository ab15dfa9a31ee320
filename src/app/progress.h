/* progress: a one-line progress bar on a terminal, fed by the renderer's
 * progress callback. */
#ifndef GLINT_APP_PROGRESS_H
#define GLINT_APP_PROGRESS_H

#include <stdio.h>

typedef struct progress {
    FILE *out;
    int last_percent;
    double start;
    int frame, frames; /* in a sequence: frame k (from 1) of frames; else 0 */
} progress;

void progress_begin(progress *p, FILE *out);
/* The next render is frame k of a sequence of n (the bar then shows the
 * sequence's share done and its time left). */
void progress_frame(progress *p, int k, int n);
void progress_update(progress *p, double percent); /* 0 to 100, of the current render */
void progress_end(progress *p);

#endif
