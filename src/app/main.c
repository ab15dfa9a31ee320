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
    "      --frames A:B       render frames A to B of an animated scene; the output\n"
    "                         name takes the number in a %d field (out-%04d.png),\n"
    "                         or gets -%04d before its extension\n"
    "      --frame N          render frame N only (named as with --frames)\n"
    "      --resume           skip frames (or an image) whose output file is already\n"
    "                         a complete image of the right size\n"
    "      --stats            print rays, samples per pixel, time and Mrays/s to stderr\n"
    "  -q, --quiet            no progress bar\n"
    "  -h, --help             show this help\n"
    "  -V, --version          show the version\n"
    "\n"
    "Exit status: 0 success, 1 runtime failure, 2 bad usage or bad input.\n";

enum { OPT_STATS = 256, OPT_TRANSFER, OPT_FORMAT, OPT_QUALITY, OPT_BITS, OPT_FRAMES, OPT_FRAME,
       OPT_RESUME };

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
    {"frames", required_argument, NULL, OPT_FRAMES},
    {"frame", required_argument, NULL, OPT_FRAME},
    {"resume", no_argument, NULL, OPT_RESUME},
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
    bool stats, quiet, resume;
    const char *frames; /* --frames or --frame as given, or NULL: a single image */
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

/* --format, --quality, --bits; false after printing why not. */
static bool output_option(struct cli *c, int opt, const char *arg)
{
    glint_error err;
    if (opt == OPT_FORMAT && glint_format_parse(arg, &c->write.format, &err) != GLINT_OK)
        return usage_error("--format: %s", err.msg) == 0;
    if (opt == OPT_QUALITY && !parse_int(arg, 1, 100, &c->write.quality))
        return usage_error("--quality: expected a whole number from 1 to 100, got '%s'", arg) == 0;
    if (opt == OPT_BITS && !parse_int(arg, 8, 32, &c->write.bits))
        return usage_error("--bits: expected 8, 16 or 32, got '%s'", arg) == 0;
    return true;
}

/* --frames A:B or --frame N; false after printing why not. */
static bool set_frames(struct cli *c, bool one, const char *arg)
{
    if (c->frames) {
        usage_error("--frames and --frame given more than once");
        return false;
    }
    if (one && strchr(arg, ':')) {
        usage_error("--frame: expected one frame number, got '%s'", arg);
        return false;
    }
    c->frames = arg;
    return true;
}

/* Returns -1 to go on, else the exit code. */
static int parse_args(int argc, char **argv, struct cli *c)
{
    *c = (struct cli){"glint.png", NULL, -1, -1, -1, -1, -1, -1, false, false, false, NULL, {0}};
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
        case OPT_FORMAT:
        case OPT_QUALITY:
        case OPT_BITS:
            if (!output_option(c, opt, optarg))
                return 2;
            break;
        case OPT_FRAMES:
        case OPT_FRAME:
            if (!set_frames(c, opt == OPT_FRAME, optarg))
                return 2;
            break;
        case OPT_RESUME:
            c->resume = true;
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

static void on_progress(void *user, const glint_progress *p)
{
    progress_update(user, p->percent);
}

/* The scene's settings with the command line's overrides, checked. */
static glint_rc cli_settings(const struct cli *c, const glint_scene *scene, glint_settings *s,
                             glint_error *err)
{
    glint_rc rc = glint_scene_settings(scene, s, err);
    if (rc != GLINT_OK)
        return rc;
    if (c->width > 0) {
        s->width = c->width;
        s->height = c->height;
    }
    if (c->samples > 0)
        s->samples = c->samples;
    if (c->depth >= 0)
        s->max_depth = c->depth;
    if (c->threads > 0)
        s->threads = c->threads;
    if (c->transfer >= 0)
        s->transfer = (glint_transfer)c->transfer;
    return glint_settings_check(s, err);
}

/* What a run adds up, for --stats. */
typedef struct totals {
    glint_stats stats;
    int images;
} totals;

/* Renders the scene as it stands into path (unless --resume finds it
 * complete) and adds to the totals. */
static glint_rc render_to(const struct cli *c, glint_scene *scene, const glint_settings *s,
                          const char *path, progress *bar, totals *t, glint_error *err)
{
    if (c->resume && glint_output_complete(path, s->width, s->height))
        return GLINT_OK;
    glint_callbacks cb = {0};
    if (bar) {
        cb.progress = on_progress;
        cb.user = bar;
    }
    glint_film film = {0};
    glint_stats st = {0};
    glint_rc rc = glint_render(scene, s, &cb, &film, &st, err);
    glint_write_options w = c->write;
    w.transfer = s->transfer;
    if (rc == GLINT_OK)
        rc = glint_film_write(&film, path, &w, err);
    glint_film_free(&film);
    t->stats.primary_rays += st.primary_rays;
    t->stats.secondary_rays += st.secondary_rays;
    t->stats.shadow_rays += st.shadow_rays;
    t->stats.seconds += st.seconds;
    t->images += rc == GLINT_OK;
    return rc;
}

/* Frames first..last, each at its time, to its own file. Frames --resume
 * will skip are left out of the progress bar's count. */
static glint_rc render_frames(const struct cli *c, glint_scene *scene, const glint_settings *s,
                              int first, int last, progress *bar, totals *t, glint_error *err)
{
    char path[4096];
    int todo = 0, k = 0;
    for (int f = first; f <= last; f++) {
        glint_rc rc = glint_frame_path(c->output, f, path, sizeof path, err);
        if (rc != GLINT_OK)
            return rc;
        todo += !(c->resume && glint_output_complete(path, s->width, s->height));
    }
    for (int f = first; f <= last; f++) {
        glint_rc rc = glint_frame_path(c->output, f, path, sizeof path, err);
        if (rc != GLINT_OK)
            return rc;
        if (c->resume && glint_output_complete(path, s->width, s->height))
            continue;
        if (bar)
            progress_frame(bar, ++k, todo);
        rc = glint_scene_set_frame(scene, f, err);
        if (rc == GLINT_OK)
            rc = render_to(c, scene, s, path, bar, t, err);
        if (rc != GLINT_OK)
            return rc;
    }
    return GLINT_OK;
}

static void print_stats(const glint_settings *s, const totals *t)
{
    const glint_stats *st = &t->stats;
    uint64_t total = st->primary_rays + st->secondary_rays + st->shadow_rays;
    int threads = s->threads > 0 ? s->threads : glint_default_threads();
    double pixels = (double)s->width * (double)s->height * (t->images > 0 ? t->images : 1);
    char how[96];
    if (s->sampler == GLINT_SAMPLER_ADAPTIVE)
        snprintf(how, sizeof how, "adaptive sampling (threshold %g, max_depth %d)", s->threshold,
                 s->adaptive_depth);
    else
        snprintf(how, sizeof how, "%d samples/pixel%s", s->samples,
                 s->sampler == GLINT_SAMPLER_JITTER ? " (jittered)" : "");
    fprintf(stderr,
            "image:   %dx%d, %s, depth %d, %d thread%s%s\n"
            "rays:    %llu (%llu primary, %llu secondary, %llu shadow)\n"
            "samples: %.2f per pixel on average\n"
            "time:    %.3f s\n"
            "speed:   %.2f Mrays/s\n",
            s->width, s->height, how, s->max_depth, threads,
            threads == 1 ? "" : "s", t->images > 1 ? ", per frame" : "",
            (unsigned long long)total, (unsigned long long)st->primary_rays,
            (unsigned long long)st->secondary_rays, (unsigned long long)st->shadow_rays,
            (double)st->primary_rays / pixels, st->seconds,
            st->seconds > 0 ? (double)total / st->seconds * 1e-6 : 0.0);
    if (t->images > 1)
        fprintf(stderr, "frames:  %d rendered\n", t->images);
}

/* Loads the scene and checks the output name (the first frame's, for a
 * sequence) before anything is rendered; *first and *last get the frames
 * (0 and 0: a single image). */
static glint_rc prepare(const struct cli *c, glint_scene **scene, glint_settings *s,
                        int *first, int *last, glint_error *err)
{
    char path[4096];
    *first = *last = 0;
    glint_rc rc = GLINT_OK;
    if (c->frames)
        rc = glint_frame_path(c->output, 1, path, sizeof path, err);
    if (rc == GLINT_OK)
        rc = glint_output_check(c->frames ? path : c->output, &c->write, err);
    if (rc == GLINT_OK)
        rc = c->scene_path ? glint_scene_load(c->scene_path, scene, err)
                           : glint_scene_builtin(scene, err);
    if (rc == GLINT_OK)
        rc = cli_settings(c, *scene, s, err);
    glint_animation anim;
    if (rc == GLINT_OK && c->frames)
        rc = glint_scene_animation(*scene, &anim, err);
    if (rc == GLINT_OK && c->frames) {
        rc = glint_frames_parse(c->frames, anim.frames, first, last, err);
        if (rc != GLINT_OK) {
            char msg[900];
            snprintf(msg, sizeof msg, "%.899s", err->msg);
            snprintf(err->msg, sizeof err->msg, "--frame%s: %.900s",
                     strchr(c->frames, ':') ? "s" : "", msg);
        }
    }
    return rc;
}

int main(int argc, char **argv)
{
    struct cli c;
    int code = parse_args(argc, argv, &c);
    if (code >= 0)
        return code;

    glint_error err = {0};
    glint_scene *scene = NULL;
    glint_settings s;
    totals t = {{0}, 0};
    int first, last;
    glint_rc rc = prepare(&c, &scene, &s, &first, &last, &err);
    if (rc != GLINT_OK)
        goto fail;

    progress bar;
    bool show = !c.quiet && isatty(STDERR_FILENO);
    if (show)
        progress_begin(&bar, stderr);
    if (first > 0)
        rc = render_frames(&c, scene, &s, first, last, show ? &bar : NULL, &t, &err);
    else
        rc = render_to(&c, scene, &s, c.output, show ? &bar : NULL, &t, &err);
    if (show)
        progress_end(&bar);
    if (rc != GLINT_OK)
        goto fail;
    if (c.stats)
        print_stats(&s, &t);
    glint_scene_free(scene);
    return 0;

fail:
    fprintf(stderr, "glint: %s\n", err.msg);
    glint_scene_free(scene);
    return glint_exit_code(rc);
}
