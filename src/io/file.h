/* file: writing output files so that the user's files are safe.
 *
 * A regular file is replaced atomically: the bytes (already encoded in
 * memory) go to a temporary file with a short random name in the target's
 * folder, which is flushed to disk and renamed over the target, so the
 * target is always either the old file or the whole new one; on failure the
 * temporary file is removed. Ctrl-C, SIGTERM, SIGHUP and SIGQUIT wait while
 * the temporary file exists (blocked in the calling thread), so an
 * interrupted program leaves none behind. Symbolic links are followed: the file they
 * point to is replaced and the links stay. An existing file keeps its mode
 * (and, when allowed, its owner); a read-only file (no write bit) is refused,
 * as cp refuses it. A file with several hard links is replaced under the
 * name given: the other names keep the old contents.
 *
 * Anything else that exists (a device such as /dev/full, a FIFO, a terminal,
 * /dev/stdout) is written directly, and every write error is reported.
 * "-" is standard output. */
#ifndef GLINT_IO_FILE_H
#define GLINT_IO_FILE_H

#include <stddef.h>
#include <sys/uio.h>
#include "glint.h"

/* Writes n bytes as the whole content of path (rules above). Errors are
 * GLINT_ERR_IO (with the system's reason), GLINT_ERR_INPUT for a target
 * that must not be written (a directory, a read-only file), GLINT_ERR_NOMEM. */
glint_rc file_write(const char *path, const void *data, size_t n, glint_error *err);
/* The same with the content in n pieces, written in order (writev). */
glint_rc file_write_pieces(const char *path, const struct iovec *iov, int n, glint_error *err);

/* Whether file_write(path) can succeed, checked without writing anything
 * the user sees: the target is not a directory or read-only, its folder
 * exists and a file can be created there (a temporary probe, removed at
 * once), the name is not too long. Errors are GLINT_ERR_INPUT, one line
 * starting with path. */
glint_rc file_check_output(const char *path, glint_error *err);

#endif
