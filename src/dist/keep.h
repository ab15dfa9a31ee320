/* keep: rank 0's resume file for one image, rewritten as tiles come in
 * (keep.c says when). The record's done flags change under the caller's
 * lock as tiles finish; a write copies them under it, and writes the
 * pixels of the tiles final in the copy, which no longer change. */
#ifndef GLINT_DIST_KEEP_H
#define GLINT_DIST_KEEP_H

#include <pthread.h>
#include <stdbool.h>

#include "glint.h"

typedef struct dist_keep {
    glint_resume *rec;
    const char *path;    /* NULL: nothing is kept (standard output) */
    unsigned char *snap; /* the done flags as last written */
    int tiles;           /* final tiles in the file (or before the render) */
    double next;         /* no write before this time (cli_now) */
    bool wrote, warned;  /* the file was written; a failure was reported */
} dist_keep;

glint_rc dist_keep_init(dist_keep *k, glint_resume *rec, const char *path, glint_error *err);
void dist_keep_free(dist_keep *k);
/* Rewrites the file when its time has come and tiles (final now) is more
 * than it holds; a failure is a warning on stderr, once. */
void dist_keep_update(dist_keep *k, int tiles, pthread_mutex_t *lock);
/* Writes the file now. */
glint_rc dist_keep_write(dist_keep *k, int tiles, pthread_mutex_t *lock, glint_error *err);

#endif
