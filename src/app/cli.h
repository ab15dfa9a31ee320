/* cli: the parsed command line, shared by the ways glint runs: a batch
 * render to a file (batch.c), with its resume files, and the preview
 * window (preview.c). */
#ifndef GLINT_APP_CLI_H
#define GLINT_APP_CLI_H

#include <stdbool.h>
#include "glint.h"

struct cli {
    const char *output;
    const char *scene_path;
    int width, height, samples, depth, threads; /* -1: not given */
    int transfer;
    bool stats, quiet;
    bool progress;      /* --progress: plain progress lines when stderr is no terminal */
    bool resume;        /* --resume: continue from OUTPUT.resume */
    bool preview;       /* -p: the window */
    bool exit_when_done;/* --exit-when-done: close the window once the image is final */
    bool preview_bench; /* --preview-bench: a scripted camera path, frames per second */
    const char *frames; /* --frames or --frame as given, or NULL: a single image */
    bool one_frame;     /* it was --frame */
    glint_write_options write; /* format, quality, bits from the command line */
    int argc;           /* the arguments as given, kept in resume files */
    char **argv;
};

/* Loads the scene the command line names (or the built-in one) and applies
 * the options that override its settings. *load_seconds (may be NULL) is
 * the wall time it took. */
glint_rc cli_load(const struct cli *c, glint_scene **scene, glint_settings *s,
                  double *load_seconds, glint_error *err);

/* One line on stderr for a scene that will render but probably not as
 * meant: nothing in it, or nothing lighting it. path NULL: built-in. */
void cli_warn(const glint_scene *scene, const char *path);

/* Seconds on a monotonic clock. */
double cli_now(void);

/* The batch render: glint's default. Returns the exit code. */
int batch_main(const struct cli *c);

/* The preview window (-p), or the benchmark (--preview-bench). Falls back
 * to batch_main without a display. Returns the exit code. */
int preview_main(const struct cli *c);

#endif
