/* The options of glint and glint-mpi, rows of one table (options[] below),
 * from which the getopt_long tables and --help are made. A new option is a
 * row and a function. The option set is a stable contract, documented in
 * README.md. */
#include "cli.h"

#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int cli_usage_error(const cli_program *p, const char *fmt, ...)
{
    if (!p->speak)
        return 2;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", p->name);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, " (try '%s --help')\n", p->name);
    va_end(ap);
    return 2;
}

/* Parses a whole decimal integer in [lo, hi]. */
static bool parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi)
        return false;
    *out = (int)v;
    return true;
}

static bool parse_resolution(const char *s, int *w, int *h)
{
    const char *x = strpbrk(s, "xX");
    if (!x || x == s)
        return false;
    char buf[32];
    size_t n = (size_t)(x - s);
    if (n >= sizeof buf)
        return false;
    memcpy(buf, s, n);
    buf[n] = '\0';
    return parse_int(buf, 1, INT_MAX, w) && parse_int(x + 1, 1, INT_MAX, h);
}

/* Exit code after printing to standard output: 1 when it could not be
 * written (a full disk, /dev/full, a closed pipe). */
static int flush_stdout(const cli_program *p)
{
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "%s: cannot write to standard output: %s\n", p->name, strerror(errno));
        return 1;
    }
    return 0;
}

/* ---- the options ---------------------------------------------------------- */

/* Each takes the option's value (NULL for flags) and returns -1 to go on,
 * or the exit code to stop with. */
typedef int (*option_fn)(struct cli *c, const char *arg);

static int opt_output(struct cli *c, const char *arg)
{
    c->output = arg;
    return -1;
}

static int opt_resolution(struct cli *c, const char *arg)
{
    if (!parse_resolution(arg, &c->width, &c->height))
        return cli_usage_error(c->program, "-r: expected WIDTHxHEIGHT such as 800x600, got '%s'", arg);
    return -1;
}

static int opt_spp(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 1, INT_MAX, &c->samples))
        return cli_usage_error(c->program, "-s: expected a positive whole number, got '%s'", arg);
    return -1;
}

static int opt_depth(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 0, INT_MAX, &c->depth))
        return cli_usage_error(c->program, "-d: expected a whole number >= 0, got '%s'", arg);
    return -1;
}

static int opt_threads(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 0, 1024, &c->threads))
        return cli_usage_error(c->program,
                               "-t: expected a whole number from 0 to 1024 (0: one per core), got '%s'",
                               arg);
    return -1;
}

static int opt_transfer(struct cli *c, const char *arg)
{
    if (strcmp(arg, "none") == 0)
        c->transfer = GLINT_TRANSFER_NONE;
    else if (strcmp(arg, "srgb") == 0)
        c->transfer = GLINT_TRANSFER_SRGB;
    else
        return cli_usage_error(c->program, "--transfer: expected none or srgb, got '%s'", arg);
    return -1;
}

static int opt_format(struct cli *c, const char *arg)
{
    glint_error err;
    if (glint_format_parse(arg, &c->write.format, &err) != GLINT_OK)
        return cli_usage_error(c->program, "--format: %s", err.msg);
    return -1;
}

static int opt_quality(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 1, 100, &c->write.quality))
        return cli_usage_error(c->program, "--quality: expected a whole number from 1 to 100, got '%s'", arg);
    return -1;
}

static int opt_bits(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 8, 32, &c->write.bits))
        return cli_usage_error(c->program, "--bits: expected 8, 16 or 32, got '%s'", arg);
    return -1;
}

/* --frames A:B and --frame N; the range is checked against the scene's
 * frames once it is loaded. */
static int take_frames(struct cli *c, const char *arg, bool one)
{
    if (c->frames)
        return cli_usage_error(c->program, "--frames and --frame given more than once");
    if (one && strchr(arg, ':'))
        return cli_usage_error(c->program, "--frame: expected one frame number, got '%s'", arg);
    c->frames = arg;
    c->one_frame = one;
    return -1;
}

static int opt_frames(struct cli *c, const char *arg) { return take_frames(c, arg, false); }

static int opt_frame(struct cli *c, const char *arg) { return take_frames(c, arg, true); }

static int opt_resume(struct cli *c, const char *arg)
{
    (void)arg;
    c->resume = true;
    return -1;
}

static int opt_stats(struct cli *c, const char *arg)
{
    (void)arg;
    c->stats = true;
    return -1;
}

static int opt_quiet(struct cli *c, const char *arg)
{
    (void)arg;
    c->quiet = true;
    return -1;
}

static int opt_progress(struct cli *c, const char *arg)
{
    (void)arg;
    c->progress = true;
    return -1;
}

static int opt_preview(struct cli *c, const char *arg)
{
    (void)arg;
    c->preview = true;
    return -1;
}

static int opt_exit_when_done(struct cli *c, const char *arg)
{
    (void)arg;
    c->exit_when_done = true;
    return -1;
}

static int opt_preview_bench(struct cli *c, const char *arg)
{
    (void)arg;
    c->preview_bench = true;
    return -1;
}

static int opt_tile_costs(struct cli *c, const char *arg)
{
    c->tile_costs = arg;
    return -1;
}

static int opt_help(struct cli *c, const char *arg);

static int opt_version(struct cli *c, const char *arg)
{
    (void)arg;
    if (!c->program->speak)
        return 0;
    printf("%s %s\n", c->program->name, GLINT_VERSION);
    return flush_stdout(c->program);
}

typedef struct option_row {
    const char *name;    /* the long name */
    char letter;         /* the short name, 0: none */
    const char *value;   /* NULL: a flag; else what --help calls its value */
    option_fn take;
    const char *help;    /* lines after the first are indented under it */
    unsigned programs;   /* CLI_GLINT, CLI_MPI or both */
    const char *mpi_help; /* glint-mpi's help where it says more; NULL: help */
} option_row;

/* glint's help where glint-mpi's says more about processes */
#define SAME CLI_BOTH, NULL

static const option_row options[] = {
    {"output", 'o', "FILE", opt_output,
     "output image (default glint.png); '-' for standard output\n"
     ".png .ppm .jpg .hdr .pfm .exr, by extension or --format", SAME},
    {"format", 0, "F", opt_format, "png, ppm, jpg, hdr, pfm or exr, whatever the name", SAME},
    {"quality", 0, "N", opt_quality, "JPEG quality, 1 to 100 (default 90)", SAME},
    {"bits", 0, "N", opt_bits,
     "bits per channel: PNG, PPM 8 (default) or 16;\n"
     "EXR 16 (half, default) or 32 (float)", SAME},
    {"resolution", 'r', "WxH", opt_resolution,
     "image size, 1 to 32768 a side (default: the scene's, else\n"
     "500x500); the horizontal field of view is kept", SAME},
    {"spp", 's', "N", opt_spp,
     "samples per pixel, a perfect square from 1 to 1024 on a\n"
     "grid, 4 = 2x2 (default: the scene's, else 1; the adaptive\n"
     "sampler chooses its own)", SAME},
    {"depth", 'd', "N", opt_depth,
     "reflection/refraction recursion limit, 0 to 64\n"
     "(default: the scene's, else 5)", SAME},
    {"threads", 't', "N", opt_threads,
     "threads, 0 to 1024, for everything: textures, trees,\n"
     "the render, the PNG (default 0: one per core)",
     CLI_BOTH,
     "threads per process, 0 to 1024, for everything: textures,\n"
     "trees, the render, the PNG (default 0: one per core\n"
     "the process may run on)"},
    {"transfer", 0, "T", opt_transfer,
     "none or srgb: how film values become pixels\n"
     "(default: the scene's, else none)", SAME},
    {"frames", 0, "A:B", opt_frames,
     "render frames A to B of an animated scene; the output\n"
     "name takes the number in a %d field (out-%04d.png),\n"
     "or gets -%04d before its extension",
     CLI_BOTH,
     "render frames A to B of an animated scene; the output\n"
     "name takes the number in a %d field (out-%04d.png),\n"
     "or gets -%04d before its extension; each process renders\n"
     "whole frames (tiles of each frame when there are fewer\n"
     "frames than processes)"},
    {"frame", 0, "N", opt_frame, "render frame N only (named as with --frames)", SAME},
    {"preview", 'p', NULL, opt_preview,
     "a live window with an interactive camera (H there lists\n"
     "the keys); re-renders when the scene's files change", CLI_GLINT, NULL},
    {"exit-when-done", 0, NULL, opt_exit_when_done,
     "with -p: write the output and close once the image is final", CLI_GLINT, NULL},
    {"preview-bench", 0, NULL, opt_preview_bench,
     "time the preview along a scripted camera path (fps)", CLI_GLINT, NULL},
    {"resume", 0, NULL, opt_resume,
     "continue an interrupted render from OUTPUT.resume;\n"
     "with --frames, skip frames whose output is complete and\n"
     "continue each frame that has its own .resume file;\n"
     "'glint --resume OUT.resume' reruns its command line",
     CLI_BOTH,
     "continue an interrupted render from OUTPUT.resume;\n"
     "with --frames, skip frames whose output is complete and\n"
     "continue each frame that has its own .resume file;\n"
     "'glint-mpi --resume OUT.resume' reruns its command line"},
    {"stats", 0, NULL, opt_stats,
     "print times, scene size, rays, Mrays/s and memory to stderr",
     CLI_BOTH,
     "print times, scene size, rays, Mrays/s and memory, then\n"
     "each process's tiles, busy time and efficiency to stderr"},
    {"tile-costs", 0, "FILE", opt_tile_costs,
     "write each tile's render time (a thread's CPU seconds)\n"
     "to FILE (a single image)",
     CLI_MPI, NULL},
    {"progress", 0, NULL, opt_progress,
     "progress lines on stderr even when it is not a terminal", SAME},
    {"quiet", 'q', NULL, opt_quiet, "no progress bar and no 'wrote' line", SAME},
    {"help", 'h', NULL, opt_help, "show this help", SAME},
    {"version", 'V', NULL, opt_version, "show the version", SAME},
};

#define NOPTIONS (sizeof options / sizeof options[0])
#define HELP_COLUMN 25

/* A row's help, its first line beside the option, the others under it. */
static void help_row(const option_row *o, unsigned program)
{
    const char *help = program == CLI_MPI && o->mpi_help ? o->mpi_help : o->help;
    char left[64];
    snprintf(left, sizeof left, "  %c%c%c --%s%s%s", o->letter ? '-' : ' ',
             o->letter ? o->letter : ' ', o->letter ? ',' : ' ', o->name, o->value ? " " : "",
             o->value ? o->value : "");
    printf("%-*s", HELP_COLUMN - 1, left);
    for (const char *line = help; line;) {
        const char *nl = strchr(line, '\n');
        int len = nl ? (int)(nl - line) : (int)strlen(line);
        if (line == help)
            printf(" %.*s\n", len, line);
        else
            printf("%*s%.*s\n", HELP_COLUMN, "", len, line);
        line = nl ? nl + 1 : NULL;
    }
}

static int opt_help(struct cli *c, const char *arg)
{
    (void)arg;
    const cli_program *p = c->program;
    if (!p->speak)
        return 0;
    fputs(p->usage_head, stdout);
    for (size_t i = 0; i < NOPTIONS; i++)
        if (options[i].programs & p->id)
            help_row(&options[i], p->id);
    fputs(p->usage_tail, stdout);
    return flush_stdout(p);
}

/* The option named by a getopt_long value (a letter or a row's index plus
 * 256), or NULL. */
static const option_row *option_by_key(int key)
{
    for (size_t i = 0; i < NOPTIONS; i++)
        if (key == (options[i].letter ? options[i].letter : 256 + (int)i))
            return &options[i];
    return NULL;
}

/* How an option is shown in a message: "-r" or "--resolution", as it was
 * written. */
static const char *option_shown(const option_row *o, const char *written, char *buf, size_t cap)
{
    if (o->letter && strncmp(written, "--", 2) != 0)
        snprintf(buf, cap, "-%c", o->letter);
    else
        snprintf(buf, cap, "--%s", o->name);
    return buf;
}

/* getopt_long's tables, made from options[]. */
static void option_tables(char *shorts, struct option *longs)
{
    char *s = shorts;
    *s++ = ':'; /* a missing value is ':', not '?' */
    for (size_t i = 0; i < NOPTIONS; i++) {
        const option_row *o = &options[i];
        int key = o->letter ? o->letter : 256 + (int)i;
        longs[i] = (struct option){o->name, o->value ? required_argument : no_argument, NULL, key};
        if (o->letter) {
            *s++ = o->letter;
            if (o->value)
                *s++ = ':';
        }
    }
    *s = '\0';
    longs[NOPTIONS] = (struct option){NULL, 0, NULL, 0};
}

/* The message for an option getopt_long refused: a value missing, a value
 * given to a flag, or no such option. The option is named as written
 * (optopt holds a value that is no character for a long option). */
static int option_error(const struct cli *c, int opt, char **argv)
{
    char buf[64];
    const option_row *o = option_by_key(optopt);
    const char *written = argv[optind - 1];
    if (opt == ':')
        return cli_usage_error(c->program, "%s needs a value",
                               o ? option_shown(o, written, buf, sizeof buf) : written);
    if (o && !o->value && strncmp(written, "--", 2) == 0 && strchr(written, '='))
        return cli_usage_error(c->program, "--%s takes no value (got '%s')", o->name, written);
    if (optopt > 0 && optopt < 256)
        return cli_usage_error(c->program, "unknown option -%c", optopt);
    return cli_usage_error(c->program, "unknown option %s", written);
}

/* An option of the other program: glint's preview window, or what only a
 * job of several processes has. */
static int foreign(const struct cli *c, const option_row *o, const char *written)
{
    char buf[64];
    option_shown(o, written, buf, sizeof buf);
    if (o->programs == CLI_GLINT)
        return cli_usage_error(c->program,
                               "%s: the preview window is glint's; glint-mpi renders to files",
                               buf);
    return cli_usage_error(c->program, "%s is glint-mpi's, for a job of several processes", buf);
}

int cli_parse(const cli_program *p, int argc, char **argv, struct cli *c)
{
    *c = (struct cli){.program = p, .output = "glint.png", .width = -1, .height = -1,
                      .samples = -1, .depth = -1, .threads = -1, .transfer = -1, .argc = argc,
                      .argv = argv};
    optind = 0; /* parsing may run twice: again for a resume file's arguments */
    char shorts[2 * NOPTIONS + 2];
    struct option longs[NOPTIONS + 1];
    option_tables(shorts, longs);
    opterr = 0;
    int opt;
    while ((opt = getopt_long(argc, argv, shorts, longs, NULL)) != -1) {
        const option_row *o = opt == ':' || opt == '?' ? NULL : option_by_key(opt);
        if (!o)
            return option_error(c, opt, argv);
        if (!(o->programs & p->id))
            return foreign(c, o, argv[optind - 1]);
        int code = o->take(c, optarg);
        if (code >= 0)
            return code;
    }
    if (optind < argc)
        c->scene_path = argv[optind++];
    if (optind < argc)
        return cli_usage_error(p, "more than one scene given ('%s' and '%s')", c->scene_path,
                               argv[optind]);
    return -1;
}

void cli_settings(const struct cli *c, glint_settings *s)
{
    if (c->width > 0) {
        s->width = c->width;
        s->height = c->height;
    }
    if (c->samples > 0)
        s->samples = c->samples;
    if (c->depth >= 0)
        s->max_depth = c->depth;
    if (c->threads >= 0)
        s->threads = c->threads;
    if (c->transfer >= 0)
        s->transfer = (glint_transfer)c->transfer;
}
