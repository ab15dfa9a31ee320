/* options: glint-mpi's command line: glint's options through the table
 * both share (cli/cli.h), with glint-mpi's own rows; the preview window's
 * are refused. Every process parses the same argv; only rank 0 prints. */
#ifndef GLINT_DIST_OPTIONS_H
#define GLINT_DIST_OPTIONS_H

#include <stdbool.h>

#include "cli/cli.h"
#include "glint.h"

/* Parses argv into c (rank: this process's). 'glint-mpi --resume
 * OUT.resume' takes the command line the file keeps: rank 0 reads it and
 * hands it to every process; *kept is then the arguments' memory, to free
 * at the end (else NULL). Returns -1 to go on, else the exit code (0 after
 * --help or --version, 2 after a bad option). */
int dist_parse_options(int argc, char **argv, int rank, struct cli *c, char ***kept);

/* The settings for a render: the scene's, with the options' overrides. */
glint_rc dist_settings(const glint_scene *scene, const struct cli *c, glint_settings *s,
                       glint_error *err);

#endif
