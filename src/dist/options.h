/* options: glint-mpi's command line, glint's options and their messages
 * (README.md) plus those that only a job of several processes has. Every
 * process parses the same argv; only rank 0 prints. */
#ifndef GLINT_DIST_OPTIONS_H
#define GLINT_DIST_OPTIONS_H

#include <stdbool.h>

#include "glint.h"

typedef struct dist_options {
    const char *output;
    const char *scene_path;  /* NULL: the built-in scene */
    const char *tile_costs;  /* --tile-costs FILE, or NULL */
    const char *frames;      /* --frames or --frame as given, or NULL: a single image */
    int width, height, samples, depth, threads; /* -1: not given */
    int transfer;                               /* -1: not given */
    bool stats, quiet, resume;
    glint_write_options write; /* format, quality, bits */
} dist_options;

/* Parses argv into o. Returns -1 to go on, else the exit code (0 after
 * --help or --version, 2 after a bad option); messages and help text are
 * printed only when speak is true. */
int dist_parse_options(int argc, char **argv, dist_options *o, bool speak);

/* The settings for a render: the scene's, with the options' overrides. */
glint_rc dist_settings(const glint_scene *scene, const dist_options *o, glint_settings *s,
                       glint_error *err);

#endif
