/* rerun: the resume file beside an output (OUTPUT.resume) and the command
 * line it keeps in its note, so that 'glint --resume OUT.resume' (or
 * glint-mpi's) runs the same command again from the folder it was run in.
 * The note is the working folder, then each argument, each NUL-terminated. */
#ifndef GLINT_CLI_RERUN_H
#define GLINT_CLI_RERUN_H

#include <stdbool.h>
#include <stddef.h>

#include "cli.h"
#include "glint.h"

/* OUTPUT.resume, malloc'd; NULL for standard output ("-"). */
char *rerun_path(const char *output);

/* --resume and path already a complete image of s's size, with no resume
 * file beside it: nothing is left to render. */
bool rerun_done(const struct cli *c, const char *path, const glint_settings *s);

/* Keeps c's working folder and arguments in r's note. */
glint_rc rerun_note_set(glint_resume *r, const struct cli *c, glint_error *err);

/* --resume with a scene named *.resume: the command line comes from it. */
bool rerun_wanted(const struct cli *c);

/* The note of the resume file path, checked to hold a command line:
 * *note (malloc'd) and *len. */
glint_rc rerun_note_read(const char *path, char **note, size_t *len, glint_error *err);

/* The command line in a note read from path: its arguments (argv[0]
 * first, a NULL after the last, all in one allocation to free with
 * free(*argv)), after changing to the folder it was run from. */
glint_rc rerun_args(const char *path, const char *note, size_t len, int *argc, char ***argv,
                    glint_error *err);

/* 'PROGRAM --resume OUT.resume' (c->scene_path): parses the command line
 * in the note read from it (rc: how the reading went, err its message)
 * into c, with --resume. Returns -1 to go on, *kept then holding the
 * arguments c points into (free it at the end), else the exit code, the
 * message printed when the program speaks. */
int rerun_parse(const cli_program *p, struct cli *c, glint_rc rc, const char *note, size_t len,
                glint_error *err, char ***kept);

/* The record a render of scene with settings s goes into: with --resume
 * and rpath there, read from it and checked against them (*resumed set),
 * else fresh; either way with c's command line in its note. */
glint_rc rerun_open(const struct cli *c, const glint_scene *scene, const glint_settings *s,
                    const char *rpath, glint_resume *rec, bool *resumed, glint_error *err);

/* Percent of the image's pixels in final tiles. */
double rerun_percent(const glint_resume *r);

/* Interrupted by the signal caught: keeps the finished tiles in rpath
 * (none for standard output, rpath NULL) and, when say, tells how to go on.
 * Returns the exit code, 128 + the signal. */
int rerun_keep(const struct cli *c, const glint_resume *rec, const char *rpath, bool say);

#endif
