/* cli: how glint runs the parsed command line (cli/cli.h, shared with
 * glint-mpi): loading the scene with the options on top (setup.c), a batch
 * render to a file (batch.c), with its resume files, and the preview
 * window (preview.c). */
#ifndef GLINT_APP_CLI_H
#define GLINT_APP_CLI_H

#include "cli/cli.h"
#include "glint.h"

/* Loads the scene the command line names (or the built-in one) and applies
 * the options that override its settings. *load_seconds (may be NULL) is
 * the wall time it took. */
glint_rc cli_load(const struct cli *c, glint_scene **scene, glint_settings *s,
                  double *load_seconds, glint_error *err);

/* One line on stderr for a scene that will render but probably not as
 * meant: nothing in it, or nothing lighting it. path NULL: built-in. */
void cli_warn(const glint_scene *scene, const char *path);

/* The batch render: glint's default. Returns the exit code. */
int batch_main(const struct cli *c);

/* The preview window (-p), or the benchmark (--preview-bench). Falls back
 * to batch_main without a display. Returns the exit code. */
int preview_main(const struct cli *c);

#endif
