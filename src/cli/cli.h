/* cli: the command line glint and glint-mpi share. Both front ends parse
 * argv with one table of options (options.c): each row names the option,
 * its value, its help text, the function that takes it and the programs
 * that take it; getopt_long's tables and --help are made from it. An option
 * of the other program is refused with a message saying whose it is.
 * Like app and dist, this folder is a client of the library: it includes
 * only glint.h. */
#ifndef GLINT_CLI_CLI_H
#define GLINT_CLI_CLI_H

#include <stdbool.h>
#include "glint.h"

/* Which programs take an option (cli_option.programs, cli_program.id). */
enum { CLI_GLINT = 1, CLI_MPI = 2, CLI_BOTH = CLI_GLINT | CLI_MPI };

typedef struct cli_program {
    const char *name;       /* "glint": messages start "name: ", --version prints it */
    unsigned id;            /* CLI_GLINT or CLI_MPI */
    const char *usage_head; /* --help: before the options */
    const char *usage_tail; /* --help: after them */
    bool speak;             /* print messages, help and version (glint-mpi: rank 0 alone) */
} cli_program;

struct cli {
    const cli_program *program;
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
    const char *tile_costs; /* glint-mpi's --tile-costs FILE, or NULL */
    glint_write_options write; /* format, quality, bits from the command line */
    int argc;           /* the arguments as given, kept in resume files */
    char **argv;
};

/* Parses argv into c for program p. Returns -1 to go on, else the exit
 * code: 0 after --help or --version (1 when standard output could not be
 * written), 2 after a bad option, with its message on stderr. */
int cli_parse(const cli_program *p, int argc, char **argv, struct cli *c);

/* The options that override a scene's settings, applied to s. */
void cli_settings(const struct cli *c, glint_settings *s);

/* Prints "name: message (try 'name --help')" when the program speaks;
 * returns 2, the exit code of bad usage. */
__attribute__((format(printf, 2, 3))) int cli_usage_error(const cli_program *p, const char *fmt,
                                                           ...);

/* Seconds on a monotonic clock. */
double cli_now(void);

#endif
