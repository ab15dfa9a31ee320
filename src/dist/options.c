#define _GNU_SOURCE /* sched_getaffinity */
#include "options.h"

#include <sched.h>
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: mpirun -n K glint-mpi [options] [SCENE.yaml]\n"
    "Renders SCENE.yaml, or with no scene the built-in nine-object scene, with K\n"
    "processes (K = 1 without mpirun); writes the same image as glint.\n"
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
    "  -t, --threads N        render threads per process (default 0: one per core\n"
    "                         the process may run on)\n"
    "      --transfer T       none (default) or srgb: how film values become pixels\n"
    "      --frames A:B       render frames A to B of an animated scene; the output\n"
    "                         name takes the number in a %d field (out-%04d.png),\n"
    "                         or gets -%04d before its extension; each process\n"
    "                         renders whole frames (tiles of each frame when there\n"
    "                         are fewer frames than processes)\n"
    "      --frame N          render frame N only (named as with --frames)\n"
    "      --resume           skip frames (or an image) whose output file is already\n"
    "                         a complete image of the right size\n"
    "      --stats            print rays, time, Mrays/s and each process's tiles,\n"
    "                         busy time and efficiency to stderr\n"
    "      --tile-costs FILE  write each tile's render time (a thread's CPU seconds)\n"
    "                         to FILE (a single image)\n"
    "  -q, --quiet            no progress bar\n"
    "  -h, --help             show this help\n"
    "  -V, --version          show the version\n"
    "\n"
    "Exit status: 0 success, 1 runtime failure, 2 bad usage or bad input.\n";

enum { OPT_STATS = 256, OPT_TRANSFER, OPT_FORMAT, OPT_QUALITY, OPT_BITS, OPT_TILE_COSTS,
       OPT_FRAMES, OPT_FRAME, OPT_RESUME };

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
    {"tile-costs", required_argument, NULL, OPT_TILE_COSTS},
    {"frames", required_argument, NULL, OPT_FRAMES},
    {"frame", required_argument, NULL, OPT_FRAME},
    {"resume", no_argument, NULL, OPT_RESUME},
    {"quiet", no_argument, NULL, 'q'},
    {"help", no_argument, NULL, 'h'},
    {"version", no_argument, NULL, 'V'},
    {NULL, 0, NULL, 0},
};

__attribute__((format(printf, 2, 3))) static int usage_error(bool speak, const char *fmt, ...)
{
    if (!speak)
        return 2;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "glint-mpi: ");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, " (try 'glint-mpi --help')\n");
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

/* Prints text to standard output (rank 0 only); 1 when it cannot be written. */
static int say(bool speak, const char *text)
{
    if (!speak)
        return 0;
    fputs(text, stdout);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "glint-mpi: cannot write to standard output: %s\n", strerror(errno));
        return 1;
    }
    return 0;
}

/* The message for an option getopt_long refused, as glint words it: a
 * value missing, a value given to a flag, or no such option, the option
 * named as written (optopt holds the option's value, or 0). */
static int option_error(int opt, char **argv, bool speak)
{
    const char *written = argv[optind - 1];
    const struct option *o = NULL;
    for (const struct option *l = long_options; l->name && optopt; l++)
        if (l->val == optopt)
            o = l;
    bool as_long = strncmp(written, "--", 2) == 0;
    if (opt == ':' && o && !as_long && o->val < 256)
        return usage_error(speak, "-%c needs a value", o->val);
    if (opt == ':')
        return usage_error(speak, "%s%s needs a value", o ? "--" : "", o ? o->name : written);
    if (o && o->has_arg == no_argument && as_long && strchr(written, '='))
        return usage_error(speak, "--%s takes no value (got '%s')", o->name, written);
    if (optopt > 0 && optopt < 256)
        return usage_error(speak, "unknown option -%c", optopt);
    return usage_error(speak, "unknown option %s", written);
}

/* One option with its value; -1 to go on, else the exit code. */
static int parse_one(int opt, const char *arg, char **argv, dist_options *o, bool speak)
{
    switch (opt) {
    case 'o': o->output = arg; return -1;
    case OPT_TILE_COSTS: o->tile_costs = arg; return -1;
    case OPT_STATS: o->stats = true; return -1;
    case OPT_RESUME: o->resume = true; return -1;
    case OPT_FRAMES:
    case OPT_FRAME:
        if (o->frames)
            return usage_error(speak, "--frames and --frame given more than once");
        if (opt == OPT_FRAME && strchr(arg, ':'))
            return usage_error(speak, "--frame: expected one frame number, got '%s'", arg);
        o->frames = arg;
        return -1;
    case 'q': o->quiet = true; return -1;
    case 'h': return say(speak, usage);
    case 'V': return say(speak, "glint-mpi " GLINT_VERSION "\n");
    case 'r':
        if (!parse_resolution(arg, &o->width, &o->height))
            return usage_error(speak, "-r: expected WIDTHxHEIGHT such as 800x600, got '%s'", arg);
        return -1;
    case 's':
        if (!parse_int(arg, 1, INT_MAX, &o->samples))
            return usage_error(speak, "-s: expected a positive whole number, got '%s'", arg);
        return -1;
    case 'd':
        if (!parse_int(arg, 0, INT_MAX, &o->depth))
            return usage_error(speak, "-d: expected a whole number >= 0, got '%s'", arg);
        return -1;
    case 't':
        if (!parse_int(arg, 0, INT_MAX, &o->threads))
            return usage_error(speak, "-t: expected a whole number >= 0 (0: all cores), got '%s'",
                               arg);
        return -1;
    case OPT_TRANSFER:
        if (strcmp(arg, "none") == 0)
            o->transfer = GLINT_TRANSFER_NONE;
        else if (strcmp(arg, "srgb") == 0)
            o->transfer = GLINT_TRANSFER_SRGB;
        else
            return usage_error(speak, "--transfer: expected none or srgb, got '%s'", arg);
        return -1;
    case OPT_FORMAT: {
        glint_error err;
        if (glint_format_parse(arg, &o->write.format, &err) != GLINT_OK)
            return usage_error(speak, "--format: %s", err.msg);
        return -1;
    }
    case OPT_QUALITY:
        if (!parse_int(arg, 1, 100, &o->write.quality))
            return usage_error(speak, "--quality: expected a whole number from 1 to 100, got '%s'", arg);
        return -1;
    case OPT_BITS:
        if (!parse_int(arg, 8, 32, &o->write.bits))
            return usage_error(speak, "--bits: expected 8, 16 or 32, got '%s'", arg);
        return -1;
    default:
        return option_error(opt, argv, speak);
    }
}

int dist_parse_options(int argc, char **argv, dist_options *o, bool speak)
{
    *o = (dist_options){.output = "glint.png", .width = -1, .height = -1, .samples = -1,
                        .depth = -1, .threads = -1, .transfer = -1};
    opterr = 0;
    int opt;
    while ((opt = getopt_long(argc, argv, ":o:r:s:d:t:qhV", long_options, NULL)) != -1) {
        int code = parse_one(opt, optarg, argv, o, speak);
        if (code >= 0)
            return code;
    }
    if (optind < argc)
        o->scene_path = argv[optind++];
    if (optind < argc)
        return usage_error(speak, "more than one scene given ('%s' and '%s')", o->scene_path,
                           argv[optind]);
    if (o->frames && o->tile_costs)
        return usage_error(speak, "--tile-costs records a single image, not --frames");
    return -1;
}

/* The cores this process may run on: mpirun and srun bind each process to
 * its share of a node, and its threads should not crowd the others'. */
static int cpus_allowed(void)
{
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) != 0 || CPU_COUNT(&set) < 1)
        return glint_default_threads();
    int n = CPU_COUNT(&set);
    return n > 1024 ? 1024 : n;
}

glint_rc dist_settings(const glint_scene *scene, const dist_options *o, glint_settings *s,
                       glint_error *err)
{
    glint_rc rc = glint_scene_settings(scene, s, err);
    if (rc != GLINT_OK)
        return rc;
    if (o->width > 0) {
        s->width = o->width;
        s->height = o->height;
    }
    if (o->samples > 0)
        s->samples = o->samples;
    if (o->depth >= 0)
        s->max_depth = o->depth;
    if (o->threads > 0)
        s->threads = o->threads;
    else if (o->threads == 0 || s->threads == 0)
        s->threads = cpus_allowed();
    if (o->transfer >= 0)
        s->transfer = (glint_transfer)o->transfer;
    return glint_settings_check(s, err);
}
