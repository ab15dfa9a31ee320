/* Paths written in scene files and the files they name: tidying, joining,
 * printable forms for messages, and reading through the scene_reader. */
#include "loader.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/text.h"

/* ---- paths ------------------------------------------------------------ */

/* Drops empty and "." segments and folds "name/.." pairs, in place; an
 * empty result is ".". The output never runs ahead of the input. */
static void tidy_path(char *p)
{
    bool absolute = p[0] == '/';
    char *start = p + absolute, *out = start;
    const char *in = start;
    size_t kept = 0; /* segments in the output that ".." may remove */
    while (*in) {
        const char *end = strchr(in, '/');
        size_t len = end ? (size_t)(end - in) : strlen(in);
        bool dot = len == 1 && in[0] == '.';
        bool dotdot = len == 2 && in[0] == '.' && in[1] == '.';
        if (len == 0 || dot || (dotdot && absolute && kept == 0)) {
            /* nothing to keep ("/.." is "/") */
        } else if (dotdot && kept > 0) {
            while (out > start && out[-1] != '/')
                out--;
            if (out > start)
                out--;
            kept--;
        } else {
            if (out > start)
                *out++ = '/';
            memmove(out, in, len);
            out += len;
            kept += !dotdot;
        }
        in += len + (end ? 1 : 0);
    }
    *out = '\0';
    if (!p[0])
        strcpy(p, ".");
}

/* dir joined to rel (unless rel is absolute or dir is empty), tidied. */
char *path_join(const char *dir, const char *rel)
{
    bool use_dir = dir && dir[0] && rel[0] != '/';
    size_t nd = use_dir ? strlen(dir) : 0, nr = strlen(rel);
    char *p = malloc(nd + nr + 3); /* room for "." in tidy_path */
    if (!p)
        return NULL;
    if (use_dir) {
        memcpy(p, dir, nd);
        p[nd++] = '/';
    }
    memcpy(p + nd, rel, nr + 1);
    tidy_path(p);
    return p;
}

/* The folder part of a path: "a/b.yaml" -> "a", "b.yaml" -> "", "/b" -> "/". */
char *path_dir(const char *path)
{
    const char *slash = strrchr(path, '/');
    size_t n = !slash ? 0 : slash == path ? 1 : (size_t)(slash - path);
    char *d = malloc(n + 1);
    if (d) {
        memcpy(d, path, n);
        d[n] = '\0';
    }
    return d;
}

/* A copy of a path with control bytes escaped as \xNN, so that messages
 * naming it stay on one line; NULL when out of memory. */
char *path_printable(const char *path)
{
    size_t len = strlen(path), cap = text_escape_room(len);
    char *out = malloc(cap);
    if (out)
        text_escape(path, len, len, out, cap);
    return out;
}

/* "cannot read KIND 'written' (resolved): reason", or the size-limit
 * message when reason is NULL. */
glint_rc load_cannot_read(loader *L, uint32_t at, const char *kind, const char *written,
                            const char *resolved, const char *reason)
{
    glint_rc rc;
    char *w = path_printable(written), *r = path_printable(resolved);
    if (!w || !r) {
        rc = err_nomem(L->err);
    } else {
        char also[600] = "";
        if (strcmp(written, resolved) != 0)
            snprintf(also, sizeof also, " (%s)", r);
        if (!reason)
            rc = load_fail(L, at, "%s '%s'%s is larger than the %u-byte limit", kind, w, also,
                      LOAD_MAX_FILE_BYTES);
        else
            rc = load_fail(L, at, "cannot read %s '%s'%s: %s", kind, w, also, reason);
    }
    free(w);
    free(r);
    return rc;
}

/* Reads a file named in the scene through the reader. written is the
 * path as written, resolved the path the reader gets; kind says what the
 * file is for ("include", "texture"). */
glint_rc load_named_file(loader *L, uint32_t at, const char *written, const char *resolved,
                                const char *kind, char **data, size_t *size)
{
    glint_error rerr = {0};
    *data = NULL;
    int source = -1; /* a file on disk: the scene's source */
    if (L->reader == scene_read_file && (source = scene_add_source(L->s, resolved)) < 0)
        return err_nomem(L->err);
    glint_rc rc = L->reader(L->user, resolved, data, size, &rerr);
    if (rc == GLINT_OK && *size <= LOAD_MAX_FILE_BYTES) {
        if (source >= 0)
            scene_source_read(L->s, source, *data, *size);
        return GLINT_OK;
    }
    if (rc == GLINT_OK) {
        free(*data);
        *data = NULL;
    }
    if (rc == GLINT_ERR_NOMEM)
        return err_nomem(L->err);
    return load_cannot_read(L, at, kind, written, resolved, rc == GLINT_OK ? NULL : rerr.msg);
}

