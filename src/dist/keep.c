/* Rank 0 keeps the image's final tiles in OUTPUT.resume while they come in,
 * so that a job that is killed loses only the tiles since the last write.
 * The file is glint's resume file (glint_resume_write: written beside its
 * name, then renamed), rewritten when tiles were added, at most every
 * KEEP_SECONDS and so that writing takes at most 1/KEEP_SHARE of the time
 * (the file grows with the image). The first write comes with the first
 * tiles, when it is small. */
#include "keep.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

#define KEEP_SECONDS 5.0
#define KEEP_SHARE 20.0

glint_rc dist_keep_init(dist_keep *k, glint_resume *rec, const char *path, glint_error *err)
{
    *k = (dist_keep){.rec = rec, .path = path};
    if (!path)
        return GLINT_OK;
    k->snap = malloc((size_t)rec->ntiles);
    if (!k->snap) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        return err->code = GLINT_ERR_NOMEM;
    }
    k->tiles = glint_resume_done(rec);
    return GLINT_OK;
}

void dist_keep_free(dist_keep *k)
{
    free(k->snap);
    k->snap = NULL;
}

glint_rc dist_keep_write(dist_keep *k, int tiles, pthread_mutex_t *lock, glint_error *err)
{
    if (!k->path)
        return GLINT_OK;
    /* the flags as they stand; the pixels of a final tile no longer change */
    pthread_mutex_lock(lock);
    memcpy(k->snap, k->rec->done, (size_t)k->rec->ntiles);
    pthread_mutex_unlock(lock);
    glint_resume view = *k->rec;
    view.done = k->snap;
    double t0 = cli_now();
    glint_rc rc = glint_resume_write(&view, k->path, err);
    double took = cli_now() - t0;
    k->next = cli_now() + (KEEP_SHARE * took > KEEP_SECONDS ? KEEP_SHARE * took : KEEP_SECONDS);
    if (rc == GLINT_OK) {
        k->tiles = tiles;
        k->wrote = true;
    }
    return rc;
}

void dist_keep_update(dist_keep *k, int tiles, pthread_mutex_t *lock)
{
    if (!k->path || tiles <= k->tiles || cli_now() < k->next)
        return;
    glint_error err = {0};
    if (dist_keep_write(k, tiles, lock, &err) != GLINT_OK && !k->warned) {
        fprintf(stderr, "glint-mpi: warning: cannot keep the tiles so far: %s\n", err.msg);
        k->warned = true;
    }
}
