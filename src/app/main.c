/* glint command line: the first client of the library (include/glint.h).
 * The options are glint's rows of the table it shares with glint-mpi
 * (cli/options.c); README.md documents them, a stable contract. */
#include <stdio.h>
#include <stdlib.h>

#include "glint.h"
#include "cli.h"
#include "cli/heap.h"
#include "cli/rerun.h"

static const char usage_head[] =
    "usage: glint [options] [SCENE.yaml | -]\n"
    "Renders SCENE.yaml ('-': the scene from standard input, its paths relative to\n"
    "the current folder), or with no scene the built-in nine-object scene. The scene\n"
    "format: docs/scene-format.md (installed in share/doc/glint).\n"
    "\n";

static const char usage_tail[] =
    "\n"
    "Options override the scene's image settings; the rest come from the scene.\n"
    "Exit status: 0 success; 1 the render or the output failed (out of memory,\n"
    "a write error); 2 bad usage or bad input: an option, the scene or a file it\n"
    "names, an unreadable one included.\n"
    "130 or 143 after Ctrl-C or SIGTERM: the render so far is kept in OUTPUT.resume.\n";

static const cli_program glint_program = {"glint", CLI_GLINT, usage_head, usage_tail, true};

static char **kept_argv;

/* 'glint --resume OUT.resume': the command line the file keeps, with
 * --resume, run from the folder it was run in. Returns -1 to go on. */
static int resume_command(struct cli *c)
{
    if (!rerun_wanted(c))
        return -1;
    glint_error err = {0};
    char *note = NULL;
    size_t len = 0;
    glint_rc rc = rerun_note_read(c->scene_path, &note, &len, &err);
    int code = rerun_parse(&glint_program, c, rc, note, len, &err, &kept_argv);
    free(note);
    return code;
}

int main(int argc, char **argv)
{
    struct cli c;
    int code = cli_parse(&glint_program, argc, argv, &c);
    if (code < 0)
        code = resume_command(&c);
    if (code >= 0)
        return code;
    if ((c.preview || c.preview_bench) && c.frames)
        return cli_usage_error(&glint_program, "--frames and --frame render to files; they do not "
                                               "go with -p or --preview-bench");
    /* once, on this thread, before the first load; a film's size when -r gives it */
    size_t film = c.width > 0 && c.height > 0 && !c.preview && !c.preview_bench
                      ? (size_t)c.width * (size_t)c.height * 3 * sizeof(float)
                      : 0;
    heap_ready(c.scene_path, c.threads, film);
    code = c.preview || c.preview_bench ? preview_main(&c) : batch_main(&c);
    free(kept_argv); /* c pointed into it */
    return code;
}
