#include "file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include "core/error.h"

/* Links followed before giving up, as the kernel does (ELOOP at 40). */
#define FILE_MAX_LINKS 40

/* ---- where a path leads ------------------------------------------------- */

typedef struct target {
    char *path;  /* the file a chain of symbolic links ends at (malloc'd) */
    bool direct; /* the chain passes through /proc or /dev/fd: write in place */
} target;

static bool is_magic(const char *p)
{
    return strncmp(p, "/proc/", 6) == 0 || strncmp(p, "/dev/fd/", 8) == 0;
}

/* The folder part of p ("." when there is none), malloc'd. */
static char *folder_of(const char *p)
{
    const char *slash = strrchr(p, '/');
    if (!slash)
        return strdup(".");
    if (slash == p)
        return strdup("/");
    return strndup(p, (size_t)(slash - p));
}

/* Follows the symbolic links from path to the name that is not one (which
 * may not exist yet). Returns 0 or an errno value. */
static int resolve(const char *path, target *t)
{
    *t = (target){strdup(path), false};
    if (!t->path)
        return ENOMEM;
    for (int hops = 0;; hops++) {
        struct stat st;
        if (lstat(t->path, &st) != 0 || !S_ISLNK(st.st_mode))
            return 0;
        if (hops == FILE_MAX_LINKS)
            return ELOOP;
        if (is_magic(t->path)) {
            t->direct = true;
            return 0;
        }
        size_t cap = (size_t)st.st_size + 1 > 256 ? (size_t)st.st_size + 1 : 256;
        char *link = malloc(cap);
        if (!link)
            return ENOMEM;
        ssize_t n = readlink(t->path, link, cap);
        if (n < 0 || (size_t)n >= cap) {
            free(link);
            return n < 0 ? errno : ENAMETOOLONG;
        }
        link[n] = '\0';
        char *next;
        if (link[0] == '/') {
            next = link;
        } else { /* relative to the link's own folder */
            char *dir = folder_of(t->path);
            next = dir ? malloc(strlen(dir) + (size_t)n + 2) : NULL;
            if (next)
                sprintf(next, "%s/%s", dir, link);
            free(dir);
            free(link);
            if (!next)
                return ENOMEM;
        }
        free(t->path);
        t->path = next;
    }
}

/* ---- writing ------------------------------------------------------------ */

/* The pieces at most this many at a time, of at most 1 GiB in all. */
#define FILE_PIECES_AT_ONCE 64
#define FILE_WRITE_MAX ((size_t)1 << 30)

static glint_rc write_all(int fd, const struct iovec *iov, int n, const char *path,
                          glint_error *err)
{
    int i = 0;
    size_t skip = 0; /* of iov[i], written already */
    for (;;) {
        while (i < n && iov[i].iov_len == skip)
            i++, skip = 0;
        if (i == n)
            return GLINT_OK;
        struct iovec v[FILE_PIECES_AT_ONCE];
        int k = 0;
        size_t total = 0;
        for (int j = i; j < n && k < FILE_PIECES_AT_ONCE && total < FILE_WRITE_MAX; j++) {
            size_t off = j == i ? skip : 0, len = iov[j].iov_len - off;
            len = len < FILE_WRITE_MAX - total ? len : FILE_WRITE_MAX - total;
            v[k++] = (struct iovec){(char *)iov[j].iov_base + off, len};
            total += len;
        }
        ssize_t w = writev(fd, v, k);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return err_set(err, GLINT_ERR_IO, "%s: cannot write: %s", path,
                           w < 0 ? strerror(errno) : "nothing written");
        for (size_t left = (size_t)w; left > 0;) {
            size_t rest = iov[i].iov_len - skip;
            if (left < rest) {
                skip += left;
                break;
            }
            left -= rest;
            i++, skip = 0;
        }
    }
}

/* A device, FIFO, terminal or a file behind /proc: opened and written as
 * it is; closing reports late errors (NFS, full disks). */
static glint_rc write_direct(const char *path, bool truncate, const struct iovec *iov, int n,
                             glint_error *err)
{
    int fd = open(path, O_WRONLY | O_NOCTTY | O_CLOEXEC | (truncate ? O_TRUNC : 0));
    if (fd < 0)
        return err_set(err, GLINT_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    glint_rc rc = write_all(fd, iov, n, path, err);
    if (close(fd) != 0 && rc == GLINT_OK)
        rc = err_set(err, GLINT_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    return rc;
}

/* While a temporary file exists, the signals that end a program by
 * default (Ctrl-C, kill, a closed terminal) wait: they arrive once it is
 * renamed or removed, so an interrupted write leaves no .glint-* behind.
 * Blocked for the calling thread, which is the one the kernel picks when
 * the others block them too (glint's render threads are done by then). */
static void hold_signals(sigset_t *saved)
{
    sigset_t s;
    sigemptyset(&s);
    sigaddset(&s, SIGINT);
    sigaddset(&s, SIGTERM);
    sigaddset(&s, SIGHUP);
    sigaddset(&s, SIGQUIT);
    pthread_sigmask(SIG_BLOCK, &s, saved);
}

static void release_signals(const sigset_t *saved) { pthread_sigmask(SIG_SETMASK, saved, NULL); }

/* Creates dir/.glint-XXXXXXXX (8 random letters: short, so any name the
 * folder accepts still works) with the given mode. */
static int create_temp(const char *dir, mode_t mode, char **tmp)
{
    static const char letters[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    *tmp = malloc(strlen(dir) + 20);
    if (!*tmp) {
        errno = ENOMEM;
        return -1;
    }
    for (int tries = 0; tries < 32; tries++) {
        unsigned char r[8];
        if (getrandom(r, sizeof r, 0) != (ssize_t)sizeof r)
            for (size_t i = 0; i < sizeof r; i++) /* no entropy: pid and a count will do */
                r[i] = (unsigned char)(getpid() * 31 + tries * 7 + (int)i);
        char name[9];
        for (int i = 0; i < 8; i++)
            name[i] = letters[r[i] % 36];
        name[8] = '\0';
        sprintf(*tmp, "%s/.glint-%s", dir, name);
        int fd = open(*tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
        if (fd >= 0 || errno != EEXIST)
            return fd;
    }
    return -1;
}

/* Refuses targets that must not be replaced; fills *old when one exists. */
static glint_rc check_existing(const char *shown, const char *path, struct stat *old, bool *exists,
                               glint_error *err)
{
    *exists = false;
    if (lstat(path, old) != 0)
        return errno == ENOENT ? GLINT_OK
                               : err_set(err, GLINT_ERR_INPUT, "%s: %s", shown, strerror(errno));
    *exists = true;
    if (S_ISDIR(old->st_mode))
        return err_set(err, GLINT_ERR_INPUT, "%s: is a directory", shown);
    if (S_ISREG(old->st_mode) && (old->st_mode & 0222) == 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: file is read-only (mode %04o)", shown,
                       (unsigned)(old->st_mode & 07777));
    if (access(path, W_OK) != 0)
        return err_set(err, GLINT_ERR_INPUT, "%s: cannot write: %s", shown, strerror(errno));
    return GLINT_OK;
}

/* The file at path's pages dropped from the page cache (advice only: it
 * stays as it is on disk, and a dirty page is written, not dropped). The
 * file is about to be replaced; its pages, freed now rather than at the
 * rename, are at hand for the new file's. On a virtual machine whose host
 * takes back the memory a guest leaves free, a page not touched for a
 * while costs a fault in the host: bench row 8's 2.3 MB PNG, written over
 * the last run's right after POV-Ray, took 0.6-4.1 ms to write and 1.7-2.4
 * to rename into place, against 0.5 and 1.3 with its pages dropped first
 * (which takes 0.3-0.4 ms; 5 runs each). */
static void drop_cached(const char *path)
{
#if defined(POSIX_FADV_DONTNEED)
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0)
        return;
    (void)posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
    close(fd);
#else
    (void)path;
#endif
}

static glint_rc replace(const char *shown, const char *path, const struct iovec *iov, int n,
                        glint_error *err)
{
    struct stat old;
    bool exists;
    glint_rc rc = check_existing(shown, path, &old, &exists, err);
    if (rc != GLINT_OK)
        return rc;
    char *dir = folder_of(path), *tmp = NULL;
    if (!dir)
        return err_nomem(err);
    if (exists && S_ISREG(old.st_mode))
        drop_cached(path);
    /* a new file gets 0666 less the umask, as creat() would give it */
    sigset_t saved;
    hold_signals(&saved);
    int fd = create_temp(dir, exists ? 0600 : 0666, &tmp);
    if (fd < 0) {
        rc = !tmp ? err_nomem(err)
                  : err_set(err, GLINT_ERR_IO, "%s: cannot write in folder '%s': %s", shown, dir,
                            strerror(errno));
        release_signals(&saved);
        goto out;
    }
    rc = write_all(fd, iov, n, shown, err);
    if (rc == GLINT_OK && exists) {
        if (fchown(fd, old.st_uid, old.st_gid) != 0) {
            /* not ours to give away: the file becomes the writer's */
        }
        if (fchmod(fd, old.st_mode & 07777) != 0)
            rc = err_set(err, GLINT_ERR_IO, "%s: cannot set mode: %s", shown, strerror(errno));
    }
    if (rc == GLINT_OK && fsync(fd) != 0)
        rc = err_set(err, GLINT_ERR_IO, "%s: cannot write: %s", shown, strerror(errno));
    if (close(fd) != 0 && rc == GLINT_OK)
        rc = err_set(err, GLINT_ERR_IO, "%s: cannot write: %s", shown, strerror(errno));
    if (rc == GLINT_OK && rename(tmp, path) != 0)
        rc = err_set(err, GLINT_ERR_IO, "%s: cannot write: %s", shown, strerror(errno));
    if (rc != GLINT_OK)
        unlink(tmp);
    release_signals(&saved);
    if (rc != GLINT_OK)
        goto out;
    /* make the rename itself durable; a failure here loses nothing now */
    int dfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);
        close(dfd);
    }
out:
    free(tmp);
    free(dir);
    return rc;
}

glint_rc file_write_pieces(const char *path, const struct iovec *iov, int n, glint_error *err)
{
    if (strcmp(path, "-") == 0)
        return write_all(STDOUT_FILENO, iov, n, "standard output", err);
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
        return write_direct(path, false, iov, n, err);
    target t;
    int e = resolve(path, &t);
    glint_rc rc;
    if (e)
        rc = e == ENOMEM ? err_nomem(err)
                         : err_set(err, GLINT_ERR_IO, "%s: cannot write: %s", path, strerror(e));
    else if (t.direct)
        rc = write_direct(path, true, iov, n, err);
    else
        rc = replace(path, t.path, iov, n, err);
    free(t.path);
    return rc;
}

glint_rc file_write(const char *path, const void *data, size_t n, glint_error *err)
{
    struct iovec one = {(void *)data, n};
    return file_write_pieces(path, &one, 1, err);
}

/* ---- checking before a render ------------------------------------------- */

static glint_rc check_folder(const char *shown, const char *path, glint_error *err)
{
    char *dir = folder_of(path), *tmp = NULL;
    if (!dir)
        return err_nomem(err);
    glint_rc rc = GLINT_OK;
    struct stat st;
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    long name_max = pathconf(dir, _PC_NAME_MAX);
    if (stat(dir, &st) != 0) {
        rc = errno == ENOENT
                 ? err_set(err, GLINT_ERR_INPUT, "%s: folder '%s' does not exist", shown, dir)
                 : err_set(err, GLINT_ERR_INPUT, "%s: folder '%s': %s", shown, dir,
                           strerror(errno));
    } else if (!S_ISDIR(st.st_mode)) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: '%s' is not a folder", shown, dir);
    } else if (strlen(base) > (size_t)(name_max > 0 ? name_max : NAME_MAX)) {
        rc = err_set(err, GLINT_ERR_INPUT, "%s: file name is too long (over %ld bytes)", shown,
                     name_max > 0 ? name_max : (long)NAME_MAX);
    } else {
        /* the one reliable test of writability (permissions, read-only
         * mounts, ACLs, root): create the temporary file the write will */
        sigset_t saved;
        hold_signals(&saved);
        int fd = create_temp(dir, 0600, &tmp);
        if (fd < 0) {
            rc = err_set(err, GLINT_ERR_INPUT, "%s: cannot write in folder '%s': %s", shown, dir,
                         strerror(errno));
        } else {
            close(fd);
            unlink(tmp);
        }
        release_signals(&saved);
    }
    free(tmp);
    free(dir);
    return rc;
}

glint_rc file_check_output(const char *path, glint_error *err)
{
    if (strcmp(path, "-") == 0)
        return GLINT_OK;
    if (path[0] == '\0')
        return err_set(err, GLINT_ERR_INPUT, "output file name is empty");
    struct stat st;
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode))
            return err_set(err, GLINT_ERR_INPUT, "%s: is a directory", path);
        if (!S_ISREG(st.st_mode))
            return access(path, W_OK) == 0
                       ? GLINT_OK
                       : err_set(err, GLINT_ERR_INPUT, "%s: cannot write: %s", path,
                                 strerror(errno));
    } else if (errno == ENAMETOOLONG) {
        return err_set(err, GLINT_ERR_INPUT, "%s: file name is too long", path);
    } else if (errno != ENOENT) {
        return err_set(err, GLINT_ERR_INPUT, "%s: %s", path, strerror(errno));
    }
    target t;
    int e = resolve(path, &t);
    if (e) {
        free(t.path);
        return e == ENOMEM ? err_nomem(err)
                           : err_set(err, GLINT_ERR_INPUT, "%s: %s", path, strerror(e));
    }
    glint_rc rc = GLINT_OK;
    if (!t.direct) {
        struct stat old;
        bool exists;
        rc = check_existing(path, t.path, &old, &exists, err);
        if (rc == GLINT_OK)
            rc = check_folder(path, t.path, err);
    }
    free(t.path);
    return rc;
}
