/* glint command line: the first client of the library (include/glint.h).
 * The option set is a stable contract, documented in README.md. */
#include <errno.h>
#include <getopt.h>
#include <stdarg.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "glint.h"
#include "batch.h"
#include "cli.h"

static const char usage[] =
    "usage: glint [options] [SCENE.yaml]\n"
    "Renders SCENE.yaml, or with no scene the built-in nine-object scene.\n"
    "\n"
    "  -o, --output FILE      output image (default glint.png); '-' for standard output\n"
    "                         .png .ppm .jpg .hdr .pfm .exr, by extension or --format\n"
    "      --format F         png, ppm, jpg, hdr, pfm or exr, whatever the name\n"
    "      --quality N        JPEG quality, 1 to 100 (default 90)\n"
    "      --bits N           bits per channel: PNG, PPM 8 (default) or 16;\n"
    "                         EXR 16 (half, default) or 32 (float)\n"
    "  -r, --resolution WxH   image size, overriding the scene's\n"
    "  -s, --spp N            samples per pixel, a perfect square (4 = 2x2 grid)\n"
    "  -d, --depth N          reflection/refraction recursion limit\n"
    "  -t, --threads N        render threads (default: all cores)\n"
    "      --transfer T       none (default) or srgb: how film values become pixels\n"
    "  -p, --preview          a live window with an interactive camera (H there lists\n"
    "                         the keys); re-renders when the scene's files change\n"
    "      --exit-when-done   with -p: close the window once the image is final\n"
    "      --preview-bench    time the preview along a scripted camera path (fps)\n"
    "      --resume           continue an interrupted render from OUTPUT.resume;\n"
    "                         'glint --resume OUT.resume' reruns its command line\n"
    "      --stats            print times, scene size, rays, Mrays/s and memory to stderr\n"
    "      --progress         progress lines on stderr even when it is not a terminal\n"
    "  -q, --quiet            no progress bar and no 'wrote' line\n"
    "  -h, --help             show this help\n"
    "  -V, --version          show the version\n"
    "\n"
    "Exit status: 0 success, 1 runtime failure, 2 bad usage or bad input,\n"
    "130/143 interrupted by Ctrl-C/SIGTERM (the render so far is kept in OUTPUT.resume).\n";

enum {
    OPT_STATS = 256, OPT_TRANSFER, OPT_FORMAT, OPT_QUALITY, OPT_BITS, OPT_PROGRESS, OPT_RESUME,
    OPT_EXIT_WHEN_DONE, OPT_PREVIEW_BENCH
};

static const struct option long_options[] = {
    {"output", required_argument, NULL, 'o'},
    {"resolution", required_argument, NULL, 'r'},
    {"spp", required_argument, NULL, 's'},
    {"depth", required_argument, NULL, 'd'},
    {"threads", required_argument, NULL, 't'},
    {"transfer", required_argument, NULL, OPT_TRANSFER},
    {"format", required_argument, NULL, OPT_FORMAT},
    {"quality", required_argument, NULL, OPT_QUALITY},
    {"bits", required_argument, NULL, OPT_BITS},
    {"stats", no_argument, NULL, OPT_STATS},
    {"progress", no_argument, NULL, OPT_PROGRESS},
    {"resume", no_argument, NULL, OPT_RESUME},
    {"preview", no_argument, NULL, 'p'},
    {"exit-when-done", no_argument, NULL, OPT_EXIT_WHEN_DONE},
    {"preview-bench", no_argument, NULL, OPT_PREVIEW_BENCH},
    {"quiet", no_argument, NULL, 'q'},
    {"help", no_argument, NULL, 'h'},
    {"version", no_argument, NULL, 'V'},
    {NULL, 0, NULL, 0},
};


__attribute__((format(printf, 1, 2))) static int usage_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "glint: ");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, " (try 'glint --help')\n");
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
static int flush_stdout(void)
{
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "glint: cannot write to standard output: %s\n", strerror(errno));
        return 1;
    }
    return 0;
}

/* The options without a value; false for any other. */
static bool set_flag(struct cli *c, int opt)
{
    bool *flag = opt == OPT_STATS            ? &c->stats
                 : opt == 'q'                ? &c->quiet
                 : opt == OPT_PROGRESS       ? &c->progress
                 : opt == OPT_RESUME         ? &c->resume
                 : opt == 'p'                ? &c->preview
                 : opt == OPT_EXIT_WHEN_DONE ? &c->exit_when_done
                 : opt == OPT_PREVIEW_BENCH  ? &c->preview_bench
                                             : NULL;
    if (flag)
        *flag = true;
    return flag != NULL;
}

/* Returns -1 to go on, else the exit code. */
static int parse_args(int argc, char **argv, struct cli *c)
{
    *c = (struct cli){.output = "glint.png", .width = -1, .height = -1, .samples = -1,
                      .depth = -1, .threads = -1, .transfer = -1, .argc = argc, .argv = argv};
    opterr = 0;
    optind = 0; /* parsing may run twice: again for a resume file's arguments */
    int opt;
    while ((opt = getopt_long(argc, argv, ":o:r:s:d:t:pqhV", long_options, NULL)) != -1) {
        if (set_flag(c, opt))
            continue;
        switch (opt) {
        case 'o':
            c->output = optarg;
            break;
        case 'r':
            if (!parse_resolution(optarg, &c->width, &c->height))
                return usage_error("-r: expected WIDTHxHEIGHT such as 800x600, got '%s'", optarg);
            break;
        case 's':
            if (!parse_int(optarg, 1, INT_MAX, &c->samples))
                return usage_error("-s: expected a positive whole number, got '%s'", optarg);
            break;
        case 'd':
            if (!parse_int(optarg, 0, INT_MAX, &c->depth))
                return usage_error("-d: expected a whole number >= 0, got '%s'", optarg);
            break;
        case 't':
            if (!parse_int(optarg, 1, INT_MAX, &c->threads))
                return usage_error("-t: expected a positive whole number, got '%s'", optarg);
            break;
        case OPT_TRANSFER:
            if (strcmp(optarg, "none") == 0)
                c->transfer = GLINT_TRANSFER_NONE;
            else if (strcmp(optarg, "srgb") == 0)
                c->transfer = GLINT_TRANSFER_SRGB;
            else
                return usage_error("--transfer: expected none or srgb, got '%s'", optarg);
            break;
        case OPT_FORMAT: {
            glint_error err;
            if (glint_format_parse(optarg, &c->write.format, &err) != GLINT_OK)
                return usage_error("--format: %s", err.msg);
            break;
        }
        case OPT_QUALITY:
            if (!parse_int(optarg, 1, 100, &c->write.quality))
                return usage_error("--quality: expected a whole number from 1 to 100, got '%s'",
                                   optarg);
            break;
        case OPT_BITS:
            if (!parse_int(optarg, 8, 32, &c->write.bits))
                return usage_error("--bits: expected 8, 16 or 32, got '%s'", optarg);
            break;
        case 'h':
            fputs(usage, stdout);
            return flush_stdout();
        case 'V':
            printf("glint %s\n", GLINT_VERSION);
            return flush_stdout();
        case ':':
            if (optopt)
                return usage_error("-%c needs a value", optopt);
            return usage_error("%s needs a value", argv[optind - 1]);
        default:
            if (optopt)
                return usage_error("unknown option -%c", optopt);
            return usage_error("unknown option %s", argv[optind - 1]);
        }
    }
    if (optind < argc)
        c->scene_path = argv[optind++];
    if (optind < argc)
        return usage_error("more than one scene given ('%s' and '%s')", c->scene_path,
                           argv[optind]);
    return -1;
}

static char **kept_argv;

/* 'glint --resume OUT.resume': the command line the file keeps, with
 * --resume, run from the folder it was run in. Returns -1 to go on. */
static int resume_command(struct cli *c)
{
    const char *p = c->scene_path;
    size_t n = p ? strlen(p) : 0;
    if (!c->resume || n < 7 || strcmp(p + n - 7, ".resume") != 0)
        return -1;
    glint_error err = {0};
    int argc;
    char **argv;
    if (batch_resume_args(p, &argc, &argv, &err) != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.msg);
        return glint_exit_code(err.code);
    }
    int code = parse_args(argc, argv, c);
    c->resume = true;
    if (code >= 0) {
        free(argv);
        return code;
    }
    kept_argv = argv; /* lives as long as the process: c points into it */
    return -1;
}

int main(int argc, char **argv)
{
    struct cli c;
    int code = parse_args(argc, argv, &c);
    if (code < 0)
        code = resume_command(&c);
    if (code >= 0)
        return code;
    if (c.preview || c.preview_bench)
        return preview_main(&c);
    return batch_main(&c);
}
