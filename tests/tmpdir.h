/* tmpdir: a fresh folder under /tmp for a test suite's files, made by
 * tmpdir_make and removed with what the tests put in it (files and empty
 * folders) by tmpdir_remove. Include once per test file. */
#ifndef GLINT_TESTS_TMPDIR_H
#define GLINT_TESTS_TMPDIR_H

#include <criterion/criterion.h>
#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static char dir[64];

static void tmpdir_make(const char *name)
{
    snprintf(dir, sizeof dir, "/tmp/glint-test-%s-XXXXXX", name);
    cr_assert_not_null(mkdtemp(dir));
}

static void tmpdir_remove(void)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    char path[512];
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (unlink(path) != 0)
            rmdir(path);
    }
    closedir(d);
    rmdir(dir);
}

/* Writes text to dir/name; where, into path (room bytes) unless NULL. */
static inline void tmpdir_write(const char *name, const char *text, char *path, size_t room)
{
    char own[512];
    if (!path)
        path = own, room = sizeof own;
    snprintf(path, room, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f, "%s", path);
    cr_assert_geq(fputs(text, f), 0, "%s", path);
    fclose(f);
}

#endif
