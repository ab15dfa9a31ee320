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
#include "progress.h"

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
    "      --stats            print rays, time and Mrays/s to stderr\n"
    "  -q, --quiet            no progress bar\n"
    "  -h, --help             show this help\n"
    "  -V, --version          show the version\n"
    "\n"
    "Exit status: 0 success, 1 runtime failure, 2 bad usage or bad input.\n";

enum { OPT_STATS = 256, OPT_TRANSFER, OPT_FORMAT, OPT_QUALITY, OPT_BITS };

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
    {"quiet", no_argument, NULL, 'q'},
    {"help", no_argument, NULL, 'h'},
    {"version", no_argument, NULL, 'V'},
    {NULL, 0, NULL, 0},
};

struct cli {
    const char *output;
    const char *scene_path;
    int width, height, samples, depth, threads; /* -1: not given */
    int transfer;
    bool stats, quiet;
    glint_write_options write; /* format, quality, bits from the command line */
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

/* Returns -1 to go on, else the exit code. */
static int parse_args(int argc, char **argv, struct cli *c)
{
    *c = (struct cli){"glint.png", NULL, -1, -1, -1, -1, -1, -1, false, false, {0}};
    opterr = 0;
    int opt;
    while ((opt = getopt_long(argc, argv, ":o:r:s:d:t:qhV", long_options, NULL)) != -1) {
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
        case OPT_STATS:
            c->stats = true;
            break;
        case 'q':
            c->quiet = true;
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

static void print_stats(const glint_settings *s, const glint_stats *stats)
{
    uint64_t total = stats->primary_rays + stats->secondary_rays + stats->shadow_rays;
    int threads = s->threads > 0 ? s->threads : glint_default_threads();
    fprintf(stderr,
            "image:   %dx%d, %d samples/pixel, depth %d, %d thread%s\n"
            "rays:    %llu (%llu primary, %llu secondary, %llu shadow)\n"
            "time:    %.3f s\n"
            "speed:   %.2f Mrays/s\n",
            s->width, s->height, s->samples, s->max_depth, threads, threads == 1 ? "" : "s",
            (unsigned long long)total, (unsigned long long)stats->primary_rays,
            (unsigned long long)stats->secondary_rays, (unsigned long long)stats->shadow_rays,
            stats->seconds, stats->seconds > 0 ? (double)total / stats->seconds * 1e-6 : 0.0);
}

/* What the scene's files left to say (dropped triangles, unused textures). */
static void print_warnings(const glint_scene *scene)
{
    for (const char *w = glint_scene_warnings(scene); *w;) {
        const char *end = strchr(w, '\n');
        int n = end ? (int)(end - w) : (int)strlen(w);
        fprintf(stderr, "glint: warning: %.*s\n", n, w);
        w += n + (end != NULL);
    }
}

static void on_progress(void *user, const glint_progress *p)
{
    progress_update(user, p->percent);
}

int main(int argc, char **argv)
{
    struct cli c;
    int code = parse_args(argc, argv, &c);
    if (code >= 0)
        return code;

    glint_error err = {0};
    glint_scene *scene = NULL;
    glint_film film = {0};
    glint_stats stats = {0};
    glint_rc rc;

    /* a bad output name fails now, not after the render */
    rc = glint_output_check(c.output, &c.write, &err);
    if (rc != GLINT_OK)
        goto fail;

    rc = c.scene_path ? glint_scene_load(c.scene_path, &scene, &err)
                      : glint_scene_builtin(&scene, &err);
    if (rc != GLINT_OK)
        goto fail;
    print_warnings(scene);

    glint_settings s;
    rc = glint_scene_settings(scene, &s, &err);
    if (rc != GLINT_OK)
        goto fail;
    if (c.width > 0) {
        s.width = c.width;
        s.height = c.height;
    }
    if (c.samples > 0)
        s.samples = c.samples;
    if (c.depth >= 0)
        s.max_depth = c.depth;
    if (c.threads > 0)
        s.threads = c.threads;
    if (c.transfer >= 0)
        s.transfer = (glint_transfer)c.transfer;
    rc = glint_settings_check(&s, &err);
    if (rc != GLINT_OK)
        goto fail;

    progress bar;
    glint_callbacks cb = {0};
    bool show = !c.quiet && isatty(STDERR_FILENO);
    if (show) {
        progress_begin(&bar, stderr);
        cb.progress = on_progress;
        cb.user = &bar;
    }
    rc = glint_render(scene, &s, &cb, &film, &stats, &err);
    if (show)
        progress_end(&bar);
    if (rc != GLINT_OK)
        goto fail;
    c.write.transfer = s.transfer;
    rc = glint_film_write(&film, c.output, &c.write, &err);
    if (rc != GLINT_OK)
        goto fail;

    if (c.stats)
        print_stats(&s, &stats);
    glint_film_free(&film);
    glint_scene_free(scene);
    return 0;

fail:
    fprintf(stderr, "glint: %s\n", err.msg);
    glint_film_free(&film);
    glint_scene_free(scene);
    return glint_exit_code(rc);
}
