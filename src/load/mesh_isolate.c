#include "mesh_isolate.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "core/error.h"

#if defined(__SANITIZE_ADDRESS__)
#define HAVE_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HAVE_ASAN 1
#endif
#endif

/* What the child's message starts with. */
enum { REPLY_MESH = 'M', REPLY_ERROR = 'E', REPLY_NOMEM = 'N' };

static bool write_all(int fd, const void *buf, size_t n)
{
    const char *p = buf;
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return false;
        p += w;
        n -= (size_t)w;
    }
    return true;
}

static void child_limits(const mesh_limits *lim)
{
    struct rlimit none = {0, 0};
    setrlimit(RLIMIT_CORE, &none);
    rlim_t cpu = lim->seconds;
    struct rlimit cpu_lim = {cpu, cpu + 1};
    setrlimit(RLIMIT_CPU, &cpu_lim);
#ifndef HAVE_ASAN
    rlim_t mem = (rlim_t)lim->memory_mib << 20;
    struct rlimit mem_lim = {mem, mem};
    setrlimit(RLIMIT_AS, &mem_lim);
#endif
    int null = open("/dev/null", O_RDWR);
    if (null >= 0 && !getenv("GLINT_MESH_DEBUG")) {
        dup2(null, STDIN_FILENO);
        dup2(null, STDOUT_FILENO);
        dup2(null, STDERR_FILENO);
    }
}

static void reply_error(int fd, char kind, const char *msg)
{
    char buf[sizeof ((glint_error *)0)->msg + 1];
    size_t n = strnlen(msg, sizeof buf - 1);
    buf[0] = kind;
    memcpy(buf + 1, msg, n);
    write_all(fd, buf, n + 1);
}

static _Noreturn void child(int fd, const char *name, const void *data, size_t size,
                            const mesh_assimp_opts *opts, const mesh_limits *lim)
{
    child_limits(lim);
    mesh_data md;
    glint_error e = {0};
    glint_rc rc = mesh_assimp_read(name, data, size, opts, &md, &e);
    if (rc == GLINT_OK) {
        size_t n = mesh_data_wire_size(&md, SIZE_MAX - 1);
        uint8_t *buf = n ? malloc(n + 1) : NULL;
        if (buf) {
            buf[0] = REPLY_MESH;
            mesh_data_encode(&md, buf + 1);
            write_all(fd, buf, n + 1);
            _exit(0);
        }
        rc = GLINT_ERR_NOMEM;
    }
    if (rc == GLINT_ERR_NOMEM)
        reply_error(fd, REPLY_NOMEM, "");
    else
        reply_error(fd, REPLY_ERROR, e.msg);
    _exit(0);
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef struct inbox {
    uint8_t *buf;
    size_t n, cap, max;
    bool timed_out, overflow, nomem;
} inbox;

/* Reads the child's reply until end of file or the deadline. */
static void receive(int fd, double deadline, inbox *in)
{
    for (;;) {
        double left = deadline - now();
        if (left <= 0) {
            in->timed_out = true;
            return;
        }
        struct pollfd p = {fd, POLLIN, 0};
        int r = poll(&p, 1, left > 3600 ? 3600 * 1000 : (int)(left * 1000) + 1);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0)
            return;
        if (r == 0)
            continue;
        if (in->n == in->cap) {
            size_t cap = in->cap ? 2 * in->cap : 1 << 16;
            if (in->cap > in->max / 2)
                cap = in->max;
            if (cap <= in->cap) {
                in->overflow = true;
                return;
            }
            uint8_t *b = realloc(in->buf, cap);
            if (!b) {
                in->nomem = true;
                return;
            }
            in->buf = b;
            in->cap = cap;
        }
        ssize_t got = read(fd, in->buf + in->n, in->cap - in->n);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            return;
        in->n += (size_t)got;
    }
}

static glint_rc judge(const char *name, const inbox *in, int status, bool waited,
                      const mesh_limits *lim, mesh_data *out, glint_error *err)
{
    if (in->nomem)
        return err_nomem(err);
    if (in->timed_out)
        return err_set(err, GLINT_ERR_INPUT,
                       "%s: the importer did not finish within %u s (GLINT_MESH_SECONDS raises "
                       "the limit)",
                       name, 2 * lim->seconds);
    if (in->n > 0 && in->buf[0] == REPLY_MESH && !in->overflow)
        return mesh_data_decode(in->buf + 1, in->n - 1, name, out, err);
    /* a mesh bigger than the memory limit, made in memory the child had
     * free when it started, is over the limit all the same */
    if (in->overflow || (in->n > 0 && in->buf[0] == REPLY_NOMEM))
        return err_set(err, GLINT_ERR_INPUT,
                       "%s: the importer ran out of its %llu MiB of memory (GLINT_MESH_MEMORY "
                       "raises the limit)",
                       name, (unsigned long long)lim->memory_mib);
    if (in->n > 1 && in->buf[0] == REPLY_ERROR) {
        size_t n = in->n - 1 < sizeof err->msg - 1 ? in->n - 1 : sizeof err->msg - 1;
        char msg[sizeof err->msg];
        memcpy(msg, in->buf + 1, n);
        msg[n] = 0;
        for (size_t i = 0; i < n; i++)
            if (msg[i] == '\n' || msg[i] == '\r')
                msg[i] = ' ';
        return err_set(err, GLINT_ERR_INPUT, "%s", msg);
    }
    if (waited && WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU)
        return err_set(err, GLINT_ERR_INPUT,
                       "%s: the importer used more than %u s of CPU time (GLINT_MESH_SECONDS "
                       "raises the limit)",
                       name, lim->seconds);
    return err_set(err, GLINT_ERR_INPUT, "%s: the importer failed (truncated or corrupt file?)",
                   name);
}

glint_rc mesh_isolate_read(const char *name, const void *data, size_t size,
                           const mesh_assimp_opts *opts, const mesh_limits *lim,
                           pthread_mutex_t *lock, mesh_data *out, glint_error *err)
{
    memset(out, 0, sizeof *out);
    int fds[2];
    if (pipe(fds) != 0) {
        pthread_mutex_unlock(lock);
        return err_set(err, GLINT_ERR_IO, "%s: cannot start the importer: %s", name,
                       strerror(errno));
    }
    fcntl(fds[0], F_SETFD, FD_CLOEXEC);
    fcntl(fds[1], F_SETFD, FD_CLOEXEC);
    pid_t pid = fork();
    if (pid != 0)
        pthread_mutex_unlock(lock);
    if (pid < 0) {
        int e = errno;
        close(fds[0]);
        close(fds[1]);
        return err_set(err, GLINT_ERR_IO, "%s: cannot start the importer: %s", name, strerror(e));
    }
    if (pid == 0) {
        close(fds[0]);
        child(fds[1], name, data, size, opts, lim);
    }
    close(fds[1]);
    inbox in = {.max = lim->memory_mib > (SIZE_MAX >> 21) ? SIZE_MAX / 2
                                                           : (size_t)(lim->memory_mib << 20)};
    receive(fds[0], now() + 2.0 * lim->seconds + 1.0, &in);
    close(fds[0]);
    if (in.timed_out || in.overflow)
        kill(pid, SIGKILL);
    int status = 0;
    pid_t w;
    while ((w = waitpid(pid, &status, 0)) < 0 && errno == EINTR)
        ;
    glint_rc rc = judge(name, &in, status, w == pid, lim, out, err);
    free(in.buf);
    return rc;
}
