/* glint_run: running the glint binary (GLINT_BIN, set by `make check`)
 * from a test, in the test's folder `dir` (tmpdir.h), and looking at the
 * files it leaves there. */
#ifndef GLINT_TESTS_GLINT_RUN_H
#define GLINT_TESTS_GLINT_RUN_H

#include <criterion/criterion.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

/* Runs `env glint args` (shell fragments; env may be "") in dir; returns
 * the exit code and fills out with stdout and stderr. */
static inline int glint_run(const char *env, const char *args, char *out, size_t outlen)
{
    const char *bin = getenv("GLINT_BIN");
    cr_assert_not_null(bin, "GLINT_BIN must name the glint binary");
    char abs[512], cmd[2048];
    if (bin[0] == '/')
        snprintf(abs, sizeof abs, "%s", bin);
    else
        snprintf(abs, sizeof abs, "%s/%s", GLINT_SOURCE_DIR, bin);
    snprintf(cmd, sizeof cmd, "cd '%s' && %s '%s' %s 2>&1", dir, env, abs, args);
    FILE *p = popen(cmd, "r");
    cr_assert_not_null(p);
    size_t n = fread(out, 1, outlen - 1, p);
    out[n] = '\0';
    int status = pclose(p);
    cr_assert(WIFEXITED(status), "glint did not exit normally: %s", out);
    return WEXITSTATUS(status);
}

static inline bool dir_has(const char *name)
{
    char path[512];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &st) == 0;
}

/* The whole content of a file in dir, with a NUL after it; *len its size.
 * Free with free(). */
static inline unsigned char *dir_read(const char *name, size_t *len)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f, "%s is missing", name);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    unsigned char *data = malloc((size_t)n + 1);
    cr_assert_eq(fread(data, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    data[n] = '\0'; /* text files read as strings */
    *len = (size_t)n;
    return data;
}

static inline bool dir_same(const char *a, const char *b)
{
    size_t na, nb;
    unsigned char *da = dir_read(a, &na), *db = dir_read(b, &nb);
    bool same = na == nb && memcmp(da, db, na) == 0;
    free(da);
    free(db);
    return same;
}

static inline void dir_put(const char *name, const char *text)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f);
    fputs(text, f);
    fclose(f);
}

#endif
