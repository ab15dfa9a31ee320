/* load_check: loading scenes inside tests. Scenes live in memory, served
 * with their includes and textures by mem_reader, so messages name short,
 * stable paths; load_path reads a scene from disk. expect_error asserts the
 * exact one-line message and GLINT_ERR_INPUT (exit code 2). Shared by the
 * loader tests. */
#ifndef GLINT_TESTS_LOAD_CHECK_H
#define GLINT_TESTS_LOAD_CHECK_H

#include <criterion/criterion.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "glint.h"
#include "core/error.h"
#include "load/assets.h"
#include "load/load.h"
#include "scene/scene.h"
#include "film.h"

#define SCENES GLINT_SOURCE_DIR "/scenes"

/* A file for mem_reader; text NULL makes it unreadable. */
typedef struct vfile {
    const char *path;
    const char *text;
} vfile;

/* Serves an embedded texture for any path ending in textures/NAME. */
/* The built-in textures, for paths ending in textures/NAME. */
static inline bool asset_for(const char *path, char **data, size_t *size)
{
    const char *at = NULL;
    for (const char *p = strstr(path, "textures/"); p; p = strstr(p + 1, "textures/"))
        at = p;
    const unsigned char *bytes;
    if (!at || !asset_find(at, &bytes, size))
        return false;
    *data = malloc(*size);
    cr_assert_not_null(*data);
    memcpy(*data, bytes, *size);
    return true;
}

static inline glint_rc mem_reader(void *user, const char *path, char **data, size_t *size,
                           glint_error *err)
{
    for (const vfile *f = user; f && f->path; f++) {
        if (strcmp(f->path, path) != 0)
            continue;
        if (!f->text)
            return err_set(err, GLINT_ERR_IO, "Permission denied");
        *size = strlen(f->text);
        *data = malloc(*size + 1);
        cr_assert_not_null(*data);
        memcpy(*data, f->text, *size + 1);
        return GLINT_OK;
    }
    if (asset_for(path, data, size))
        return GLINT_OK;
    return err_set(err, GLINT_ERR_IO, "No such file or directory");
}

/* Files from disk; the built-in textures when scenes/textures/ has not
 * been generated yet (they are the same images). */
static inline glint_rc disk_reader(void *user, const char *path, char **data, size_t *size,
                            glint_error *err)
{
    glint_rc rc = scene_read_file(user, path, data, size, err);
    if (rc != GLINT_OK && asset_for(path, data, size))
        return GLINT_OK;
    return rc;
}

/* Loads a scene file from disk, textures falling back as disk_reader says. */
static inline glint_rc load_path(const char *path, scene **out, glint_error *err)
{
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f, "%s: %s", path, strerror(errno));
    static char text[1 << 20];
    size_t n = fread(text, 1, sizeof text, f);
    fclose(f);
    cr_assert_lt(n, sizeof text);
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", path);
    *strrchr(dir, '/') = '\0';
    return scene_load_text(text, n, path, dir, disk_reader, NULL, out, err);
}

static inline scene *load_ok_with(const char *text, const vfile *files)
{
    scene *s = NULL;
    glint_error err = {0};
    glint_rc rc = scene_load_text(text, strlen(text), "scene.yaml", NULL, mem_reader,
                                  (void *)files, &s, &err);
    cr_assert_eq(rc, GLINT_OK, "%s", err.msg);
    cr_assert_not_null(s);
    return s;
}

static inline scene *load_ok(const char *text) { return load_ok_with(text, NULL); }

/* Loads text as scene.yaml (with files beside it) and checks that it fails
 * with exactly message, as bad input, and leaves *out alone. */
static inline void expect_error_with(const char *text, const vfile *files, const char *message)
{
    scene *sentinel = (scene *)&sentinel, *s = sentinel;
    glint_error err = {0};
    glint_rc rc = scene_load_text(text, strlen(text), "scene.yaml", NULL, mem_reader,
                                  (void *)files, &s, &err);
    cr_expect_eq(rc, GLINT_ERR_INPUT, "rc %d (%s) for:\n%.200s", rc, err.msg, text);
    cr_expect_eq(glint_exit_code(rc), 2);
    cr_expect_str_eq(err.msg, message, "\n got: %s\nwant: %s", err.msg, message);
    cr_expect_eq(s, sentinel, "*out must be untouched on failure");
    if (rc == GLINT_OK && s != sentinel)
        scene_free(s);
}

static inline void expect_error(const char *text, const char *message)
{
    expect_error_with(text, NULL, message);
}

static inline glint_film render(const scene *s, int w, int h, int samples)
{
    return test_render(s, w, h, samples, 2);
}

#endif
