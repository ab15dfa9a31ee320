/* glint command line: the first client of the library (include/glint.h).
 * The option set is a stable contract, documented in README.md.
 *
 * Options live in one table (options[] below): each row names the option,
 * its value, its help text and the function that takes it, and the
 * getopt_long tables and --help are made from it. A new option is a row
 * and a function. */
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

static const char usage_head[] =
    "usage: glint [options] [SCENE.yaml | -]\n"
    "Renders SCENE.yaml ('-': the scene from standard input, its paths relative to\n"
    "the current folder), or with no scene the built-in nine-object scene. The scene\n"
    "format: docs/scene-format.md (installed in share/doc/glint).\n"
    "\n";

static const char usage_tail[] =
    "\n"
    "Options override the scene's image settings; the rest come from the scene.\n"
    "Exit status: 0 success; 1 the render or the output failed (out of memory,\n"
    "a write error); 2 bad usage or bad input: an option, the scene or a file it\n"
    "names, an unreadable one included.\n";

struct cli {
    const char *output;
    const char *scene_path;
    int width, height, samples, depth, threads; /* -1: not given */
    int transfer;
    bool stats, quiet, resume;
    const char *frames; /* --frames or --frame as given, or NULL: a single image */
    bool one_frame;     /* it was --frame */
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
        return usage_error("-r: expected WIDTHxHEIGHT such as 800x600, got '%s'", arg);
    return -1;
}

static int opt_spp(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 1, INT_MAX, &c->samples))
        return usage_error("-s: expected a positive whole number, got '%s'", arg);
    return -1;
}

static int opt_depth(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 0, INT_MAX, &c->depth))
        return usage_error("-d: expected a whole number >= 0, got '%s'", arg);
    return -1;
}

static int opt_threads(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 0, INT_MAX, &c->threads))
        return usage_error("-t: expected a whole number >= 0 (0: all cores), got '%s'", arg);
    return -1;
}

static int opt_transfer(struct cli *c, const char *arg)
{
    if (strcmp(arg, "none") == 0)
        c->transfer = GLINT_TRANSFER_NONE;
    else if (strcmp(arg, "srgb") == 0)
        c->transfer = GLINT_TRANSFER_SRGB;
    else
        return usage_error("--transfer: expected none or srgb, got '%s'", arg);
    return -1;
}

static int opt_format(struct cli *c, const char *arg)
{
    glint_error err;
    if (glint_format_parse(arg, &c->write.format, &err) != GLINT_OK)
        return usage_error("--format: %s", err.msg);
    return -1;
}

static int opt_quality(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 1, 100, &c->write.quality))
        return usage_error("--quality: expected a whole number from 1 to 100, got '%s'", arg);
    return -1;
}

static int opt_bits(struct cli *c, const char *arg)
{
    if (!parse_int(arg, 8, 32, &c->write.bits))
        return usage_error("--bits: expected 8, 16 or 32, got '%s'", arg);
    return -1;
}

/* --frames A:B and --frame N; the range is checked against the scene's
 * frames once it is loaded. */
static int take_frames(struct cli *c, const char *arg, bool one)
{
    if (c->frames)
        return usage_error("--frames and --frame given more than once");
    if (one && strchr(arg, ':'))
        return usage_error("--frame: expected one frame number, got '%s'", arg);
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

static int opt_help(struct cli *c, const char *arg);

static int opt_version(struct cli *c, const char *arg)
{
    (void)c, (void)arg;
    printf("glint %s\n", GLINT_VERSION);
    return flush_stdout();
}

typedef struct option_row {
    const char *name;    /* the long name */
    char letter;         /* the short name, 0: none */
    const char *value;   /* NULL: a flag; else what --help calls its value */
    option_fn take;
    const char *help;    /* lines after the first are indented under it */
} option_row;

static const option_row options[] = {
    {"output", 'o', "FILE", opt_output,
     "output image (default glint.png); '-' for standard output\n"
     ".png .ppm .jpg .hdr .pfm .exr, by extension or --format"},
    {"format", 0, "F", opt_format, "png, ppm, jpg, hdr, pfm or exr, whatever the name"},
    {"quality", 0, "N", opt_quality, "JPEG quality, 1 to 100 (default 90)"},
    {"bits", 0, "N", opt_bits,
     "bits per channel: PNG, PPM 8 (default) or 16;\n"
     "EXR 16 (half, default) or 32 (float)"},
    {"resolution", 'r', "WxH", opt_resolution,
     "image size, 1 to 32768 a side (default: the scene's, else\n"
     "500x500); the horizontal field of view is kept"},
    {"spp", 's', "N", opt_spp,
     "samples per pixel, a perfect square from 1 to 1024 on a\n"
     "grid, 4 = 2x2 (default: the scene's, else 1; the adaptive\n"
     "sampler chooses its own)"},
    {"depth", 'd', "N", opt_depth,
     "reflection/refraction recursion limit, 0 to 64\n"
     "(default: the scene's, else 5)"},
    {"threads", 't', "N", opt_threads, "render threads, 0 to 1024 (default 0: one per core)"},
    {"transfer", 0, "T", opt_transfer,
     "none or srgb: how film values become pixels\n"
     "(default: the scene's, else none)"},
    {"frames", 0, "A:B", opt_frames,
     "render frames A to B of an animated scene; the output\n"
     "name takes the number in a %d field (out-%04d.png),\n"
     "or gets -%04d before its extension"},
    {"frame", 0, "N", opt_frame, "render frame N only (named as with --frames)"},
    {"resume", 0, NULL, opt_resume,
     "skip frames (or an image) whose output file is already\n"
     "a complete image of the right size"},
    {"stats", 0, NULL, opt_stats,
     "print rays, samples per pixel, time and Mrays/s to stderr"},
    {"quiet", 'q', NULL, opt_quiet, "no progress bar"},
    {"help", 'h', NULL, opt_help, "show this help"},
    {"version", 'V', NULL, opt_version, "show the version"},
};

#define NOPTIONS (sizeof options / sizeof options[0])
#define HELP_COLUMN 25

static int opt_help(struct cli *c, const char *arg)
{
    (void)c, (void)arg;
    fputs(usage_head, stdout);
    for (size_t i = 0; i < NOPTIONS; i++) {
        const option_row *o = &options[i];
        char left[64];
        snprintf(left, sizeof left, "  %c%c%c --%s%s%s", o->letter ? '-' : ' ',
                 o->letter ? o->letter : ' ', o->letter ? ',' : ' ', o->name, o->value ? " " : "",
                 o->value ? o->value : "");
        printf("%-*s", HELP_COLUMN - 1, left);
        for (const char *line = o->help; line;) {
            const char *nl = strchr(line, '\n');
            int len = nl ? (int)(nl - line) : (int)strlen(line);
            if (line == o->help)
                printf(" %.*s\n", len, line);
            else
                printf("%*s%.*s\n", HELP_COLUMN, "", len, line);
            line = nl ? nl + 1 : NULL;
        }
    }
    fputs(usage_tail, stdout);
    return flush_stdout();
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
static int option_error(int opt, char **argv)
{
    char buf[64];
    const option_row *o = option_by_key(optopt);
    const char *written = argv[optind - 1];
    if (opt == ':')
        return usage_error("%s needs a value", o ? option_shown(o, written, buf, sizeof buf)
                                                 : written);
    if (o && !o->value && strncmp(written, "--", 2) == 0 && strchr(written, '='))
        return usage_error("--%s takes no value (got '%s')", o->name, written);
    if (optopt > 0 && optopt < 256)
        return usage_error("unknown option -%c", optopt);
    return usage_error("unknown option %s", written);
}

/* Returns -1 to go on, else the exit code. */
static int parse_args(int argc, char **argv, struct cli *c)
{
    *c = (struct cli){"glint.png", NULL, -1, -1, -1, -1, -1, -1, false, false, false, NULL,
                      false, {0}};
    char shorts[2 * NOPTIONS + 2];
    struct option longs[NOPTIONS + 1];
    option_tables(shorts, longs);
    opterr = 0;
    int opt;
    while ((opt = getopt_long(argc, argv, shorts, longs, NULL)) != -1) {
        const option_row *o = opt == ':' || opt == '?' ? NULL : option_by_key(opt);
        if (!o)
            return option_error(opt, argv);
        int code = o->take(c, optarg);
        if (code >= 0)
            return code;
    }
    if (optind < argc)
        c->scene_path = argv[optind++];
    if (optind < argc)
        return usage_error("more than one scene given ('%s' and '%s')", c->scene_path,
                           argv[optind]);
    return -1;
}

/* ---- the render ------------------------------------------------------------ */

/* The scene's settings with the command line's on top. */
static glint_rc settings_for(const glint_scene *scene, const struct cli *c, glint_settings *s,
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
    if (c->threads >= 0)
        s->threads = c->threads;
    if (c->transfer >= 0)
        s->transfer = (glint_transfer)c->transfer;
    return glint_settings_check(s, err);
}

/* One line on stderr for each thing the scene's files left to say (dropped
 * triangles, textures left out), and for a scene that will render but
 * probably not as meant: nothing in it, or nothing lighting it. */
static void warn_about(const glint_scene *scene, const char *path)
{
    for (const char *w = glint_scene_warnings(scene); *w;) {
        const char *end = strchr(w, '\n');
        int len = end ? (int)(end - w) : (int)strlen(w);
        fprintf(stderr, "glint: warning: %.*s\n", len, w);
        w += len + (end != NULL);
    }
    glint_scene_counts n;
    if (glint_scene_count(scene, &n, NULL) != GLINT_OK)
        return;
    const char *name = !path ? "the built-in scene" : strcmp(path, "-") == 0 ? "<stdin>" : path;
    if (n.objects == 0)
        fprintf(stderr, "glint: warning: %s has no objects: the image is the background\n",
                name);
    else if (n.lights == 0)
        fprintf(stderr,
                "glint: warning: %s has no lights: only ambient light shows (add a 'lights' "
                "list)\n",
                name);
}

static void on_progress(void *user, const glint_progress *p)
{
    progress_update(user, p->percent);
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
            s->width, s->height, how, s->max_depth, threads, threads == 1 ? "" : "s",
            t->images > 1 ? ", per frame" : "", (unsigned long long)total,
            (unsigned long long)st->primary_rays, (unsigned long long)st->secondary_rays,
            (unsigned long long)st->shadow_rays, (double)st->primary_rays / pixels, st->seconds,
            st->seconds > 0 ? (double)total / st->seconds * 1e-6 : 0.0);
    if (t->images > 1)
        fprintf(stderr, "frames:  %d rendered\n", t->images);
}

/* The frames to render: *first and *last, or 0 and 0 for a single image. */
static glint_rc frames_for(const struct cli *c, const glint_scene *scene, int *first, int *last,
                           glint_error *err)
{
    *first = *last = 0;
    if (!c->frames)
        return GLINT_OK;
    glint_animation anim;
    glint_rc rc = glint_scene_animation(scene, &anim, err);
    if (rc == GLINT_OK)
        rc = glint_frames_parse(c->frames, anim.frames, first, last, err);
    if (rc != GLINT_OK && rc != GLINT_ERR_NOMEM) {
        char msg[900];
        snprintf(msg, sizeof msg, "%.899s", err->msg);
        snprintf(err->msg, sizeof err->msg, "--frame%s: %.900s", c->one_frame ? "" : "s", msg);
    }
    return rc;
}

/* Loads, renders and writes; returns the exit code. */
static int run(struct cli *c)
{
    glint_error err = {0};
    glint_scene *scene = NULL;
    glint_settings s;
    totals t = {{0}, 0};
    char first_name[4096];
    int first = 0, last = 0;
    /* a bad output name (for a sequence: the first frame's) fails now, not
     * after the render */
    glint_rc rc = c->frames ? glint_frame_path(c->output, 1, first_name, sizeof first_name, &err)
                            : GLINT_OK;
    if (rc == GLINT_OK)
        rc = glint_output_check(c->frames ? first_name : c->output, &c->write, &err);
    if (rc == GLINT_OK)
        rc = c->scene_path ? glint_scene_load(c->scene_path, &scene, &err)
                           : glint_scene_builtin(&scene, &err);
    if (rc == GLINT_OK)
        rc = settings_for(scene, c, &s, &err);
    if (rc == GLINT_OK)
        rc = frames_for(c, scene, &first, &last, &err);
    if (rc == GLINT_OK) {
        warn_about(scene, c->scene_path);
        progress bar;
        bool show = !c->quiet && isatty(STDERR_FILENO);
        if (show)
            progress_begin(&bar, stderr);
        rc = first > 0 ? render_frames(c, scene, &s, first, last, show ? &bar : NULL, &t, &err)
                       : render_to(c, scene, &s, c->output, show ? &bar : NULL, &t, &err);
        if (show)
            progress_end(&bar);
    }
    if (rc == GLINT_OK && c->stats)
        print_stats(&s, &t);
    if (rc != GLINT_OK)
        fprintf(stderr, "glint: %s\n", err.msg);
    glint_scene_free(scene);
    return glint_exit_code(rc);
}

int main(int argc, char **argv)
{
    struct cli c;
    int code = parse_args(argc, argv, &c);
    return code >= 0 ? code : run(&c);
}
