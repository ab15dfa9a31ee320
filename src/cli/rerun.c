#include "rerun.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "signals.h"

char *rerun_path(const char *output)
{
    if (strcmp(output, "-") == 0)
        return NULL;
    size_t n = strlen(output);
    char *p = malloc(n + 8);
    if (p)
        snprintf(p, n + 8, "%s.resume", output);
    return p;
}

glint_rc rerun_note_set(glint_resume *r, const struct cli *c, glint_error *err)
{
    char cwd[4096];
    if (!getcwd(cwd, sizeof cwd))
        cwd[0] = '\0';
    size_t len = strlen(cwd) + 1;
    for (int i = 0; i < c->argc; i++)
        len += strlen(c->argv[i]) + 1;
    char *note = malloc(len), *at = note;
    if (!note) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        return err->code = GLINT_ERR_NOMEM;
    }
    at = stpcpy(at, cwd) + 1;
    for (int i = 0; i < c->argc; i++)
        at = stpcpy(at, c->argv[i]) + 1;
    glint_rc rc = glint_resume_set_note(r, note, len, err);
    free(note);
    return rc;
}

bool rerun_wanted(const struct cli *c)
{
    const char *p = c->scene_path;
    size_t n = p ? strlen(p) : 0;
    return c->resume && n >= 7 && strcmp(p + n - 7, ".resume") == 0;
}

/* Strings in the note: the folder and at least argv[0]. */
static int note_strings(const char *note, size_t len)
{
    int n = 0;
    for (size_t i = 0; i < len; i++)
        n += note[i] == '\0';
    return len > 0 && note[len - 1] == '\0' ? n : 0;
}

glint_rc rerun_note_read(const char *path, char **note, size_t *len, glint_error *err)
{
    glint_resume r;
    glint_rc rc = glint_resume_read(path, &r, err);
    if (rc != GLINT_OK)
        return rc;
    if (note_strings(r.note, r.note_len) < 2) {
        glint_resume_free(&r);
        snprintf(err->msg, sizeof err->msg, "%s: resume file keeps no command line", path);
        return err->code = GLINT_ERR_INPUT;
    }
    *note = r.note; /* taken over from the record */
    *len = r.note_len;
    r.note = NULL;
    r.note_len = 0;
    glint_resume_free(&r);
    return GLINT_OK;
}

glint_rc rerun_args(const char *path, const char *note, size_t len, int *argc, char ***argv,
                    glint_error *err)
{
    int n = note_strings(note, len);
    if (n < 2) {
        snprintf(err->msg, sizeof err->msg, "%s: resume file keeps no command line", path);
        return err->code = GLINT_ERR_INPUT;
    }
    /* pointers first, then the strings, in one block */
    char **v = malloc((size_t)n * sizeof *v + len);
    if (!v) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        return err->code = GLINT_ERR_NOMEM;
    }
    char *text = (char *)(v + n);
    memcpy(text, note, len);
    if (*text && chdir(text) != 0) {
        snprintf(err->msg, sizeof err->msg, "%s: cannot return to the folder '%s': %s", path, text,
                 strerror(errno));
        free(v);
        return err->code = GLINT_ERR_INPUT;
    }
    char *at = text + strlen(text) + 1;
    for (int i = 0; i < n - 1; i++, at += strlen(at) + 1)
        v[i] = at;
    v[n - 1] = NULL;
    *argc = n - 1;
    *argv = v;
    return GLINT_OK;
}

glint_rc rerun_open(const struct cli *c, const glint_scene *scene, const glint_settings *s,
                    const char *rpath, glint_resume *rec, bool *resumed, glint_error *err)
{
    *resumed = false;
    if (c->resume && rpath && access(rpath, F_OK) == 0) {
        glint_rc rc = glint_resume_read(rpath, rec, err);
        if (rc != GLINT_OK)
            return rc;
        rc = glint_resume_check(rec, scene, s, err);
        if (rc != GLINT_OK) {
            char msg[sizeof err->msg];
            snprintf(msg, sizeof msg, "%s", err->msg);
            snprintf(err->msg, sizeof err->msg, "%.500s: %.500s", rpath, msg);
            glint_resume_free(rec);
            return rc;
        }
        *resumed = true;
        return rerun_note_set(rec, c, err);
    }
    if (c->resume && !c->quiet && !c->frames)
        fprintf(stderr, "%s: no resume file %s; rendering from the start\n", c->program->name,
                rpath ? rpath : "for standard output");
    glint_rc rc = glint_resume_init(rec, scene, s, err);
    if (rc == GLINT_OK)
        rc = rerun_note_set(rec, c, err);
    return rc;
}

double rerun_percent(const glint_resume *r)
{
    uint64_t done = 0;
    for (int i = 0; i < r->ntiles; i++) {
        glint_rect t;
        if (r->done[i] && glint_tile_rect(&r->settings, i, &t, NULL) == GLINT_OK)
            done += (uint64_t)(t.x1 - t.x0) * (uint64_t)(t.y1 - t.y0);
    }
    return 100.0 * (double)done / ((double)r->settings.width * (double)r->settings.height);
}

int rerun_keep(const struct cli *c, const glint_resume *rec, const char *rpath, bool say)
{
    const char *name = c->program->name;
    int code = signals_exit_code(signals_caught());
    if (!rpath) {
        if (say)
            fprintf(stderr, "%s: interrupted; nothing kept (the output is standard output)\n",
                    name);
        return code;
    }
    glint_error err = {0};
    if (glint_resume_write(rec, rpath, &err) != GLINT_OK) {
        if (say)
            fprintf(stderr, "%s: interrupted; cannot keep the render: %s\n", name, err.msg);
        return code;
    }
    if (say)
        fprintf(stderr, "%s: interrupted at %d%%; kept in %s (continue with: %s --resume %s)\n",
                name, (int)rerun_percent(rec), rpath, name, rpath);
    return code;
}

bool rerun_done(const struct cli *c, const char *path, const glint_settings *s)
{
    if (!c->resume || strcmp(path, "-") == 0)
        return false;
    char *rpath = rerun_path(path);
    bool kept = !rpath || access(rpath, F_OK) == 0;
    free(rpath);
    return !kept && glint_output_complete(path, s->width, s->height);
}

int rerun_parse(const cli_program *p, struct cli *c, glint_rc rc, const char *note, size_t len,
                glint_error *err, char ***kept)
{
    int argc;
    char **argv;
    if (rc == GLINT_OK)
        rc = rerun_args(c->scene_path, note, len, &argc, &argv, err);
    if (rc != GLINT_OK) {
        if (p->speak)
            fprintf(stderr, "%s: %s\n", p->name, err->msg);
        return glint_exit_code(rc);
    }
    int code = cli_parse(p, argc, argv, c);
    c->resume = true;
    if (code >= 0) {
        free(argv);
        return code;
    }
    *kept = argv; /* c points into it */
    return -1;
}
