/* progress: a one-line progress bar on a terminal, fed by the renderer's
 * progress callback. */
#ifndef GLINT_APP_PROGRESS_H
#define GLINT_APP_PROGRESS_H

#include <stdio.h>

typedef struct progress {
    FILE *out;
    int last_percent;
    double start;
} progress;

void progress_begin(progress *p, FILE *out);
void progress_update(progress *p, double percent); /* 0 to 100 */
void progress_end(progress *p);

#endif
