/* The batch render: scene in, image file out, with the progress bar, the
 * --stats report, and resume files. Every render goes through a resume
 * record (glint_resume_render), so an interruption at any point can be kept
 * and finished later into the same bytes. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "cli.h"

#include "cli/progress.h"
#include "cli/rerun.h"
#include "cli/signals.h"

/* What the render's callbacks share. */
typedef struct watch {
    progress bar;
    int tiles;              /* finished so far */
    int hook_sig[2], hook_at[2]; /* test hook: raise sig once `at` tiles are done */
} watch;

static void on_progress(void *user, const glint_progress *p)
{
    progress_update(&((watch *)user)->bar, p);
}

/* GLINT_TEST_SIGNALS="SIG@N[,SIG@M]" raises signal SIG (a number) after
 * the N-th finished tile: the tests interrupt renders at chosen points
 * through the real handlers. */
static void hook_parse(watch *w)
{
    const char *e = getenv("GLINT_TEST_SIGNALS");
    for (int i = 0; i < 2; i++)
        w->hook_sig[i] = 0;
    if (e)
        sscanf(e, "%d@%d,%d@%d", &w->hook_sig[0], &w->hook_at[0], &w->hook_sig[1],
               &w->hook_at[1]);
}

static void on_tile(void *user, const glint_film *f, int x0, int y0, int x1, int y1)
{
    (void)f, (void)x0, (void)y0, (void)x1, (void)y1;
    watch *w = user;
    w->tiles++;
    for (int i = 0; i < 2; i++)
        if (w->hook_sig[i] && w->tiles == w->hook_at[i])
            raise(w->hook_sig[i]);
}

static int on_cancel(void *user)
{
    (void)user;
    return signals_caught() != 0;
}

typedef struct times {
    double load, render, write;
} times;

/* A batch run: the scene, its settings, and what its images add up. */
typedef struct run {
    const struct cli *c;
    glint_scene *scene;
    glint_settings s;
    glint_stats stats;
    times t;
    int images;
    watch w;
    glint_scene_info info; /* the scene's, kept when it is freed before the end */
} run;

/* Frees the scene once the last image is rendered, before that image is
 * written: the PNG writer's buffers then take the scene's memory, already
 * mapped, instead of fresh pages (on a virtual machine whose host takes
 * back the memory a guest leaves free, a fresh huge page costs 2-4 ms:
 * bench row 8's write phase took 15-18 ms right after POV-Ray, median 16,
 * against 15-30, median 20, with the scene kept). */
static void release_scene(run *r)
{
    glint_scene_describe(r->scene, &r->info, NULL);
    glint_scene_free(r->scene);
    r->scene = NULL;
}

static void print_stats(const run *r)
{
    const glint_settings *s = &r->s;
    const glint_stats *st = &r->stats;
    glint_scene_info info = r->info;
    if (r->scene)
        glint_scene_describe(r->scene, &info, NULL);
    uint64_t total = st->primary_rays + st->secondary_rays + st->shadow_rays;
    int threads = s->threads > 0 ? s->threads : glint_default_threads();
    double pixels = (double)s->width * (double)s->height * (r->images > 0 ? r->images : 1);
    char how[96];
    if (s->sampler == GLINT_SAMPLER_ADAPTIVE)
        snprintf(how, sizeof how, "adaptive sampling (threshold %g, max_depth %d)", s->threshold,
                 s->adaptive_depth);
    else
        snprintf(how, sizeof how, "%d samples/pixel%s", s->samples,
                 s->sampler == GLINT_SAMPLER_JITTER ? " (jittered)" : "");
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    fprintf(stderr,
            "image:   %dx%d, %s, depth %d, %d thread%s\n"
            "scene:   %d objects, %llu triangles, %d lights, %d meshes\n"
            "time:    load %.3f s (build %.3f s), render %.3f s, write %.3f s\n"
            "rays:    %llu (%llu primary, %llu secondary, %llu shadow)\n"
            "samples: %.2f per pixel on average\n"
            "speed:   %.2f Mrays/s\n"
            "memory:  %.1f MiB peak\n",
            s->width, s->height, how, s->max_depth, threads, threads == 1 ? "" : "s",
            info.objects, (unsigned long long)info.triangles, info.lights, info.meshes,
            r->t.load, info.build_seconds, r->t.render, r->t.write, (unsigned long long)total,
            (unsigned long long)st->primary_rays, (unsigned long long)st->secondary_rays,
            (unsigned long long)st->shadow_rays, (double)st->primary_rays / pixels,
            st->seconds > 0 ? (double)total / st->seconds * 1e-6 : 0.0,
            (double)ru.ru_maxrss / 1024.0);
    if (r->images > 1)
        fprintf(stderr, "frames:  %d rendered\n", r->images);
}

/* Writes the finished image, with its phase on the progress line. */
static glint_rc write_image(const struct cli *c, const char *path, const glint_settings *s,
                            const glint_film *film, progress *bar, double *seconds,
                            glint_error *err)
{
    double t0 = cli_now();
    char what[600];
    snprintf(what, sizeof what, "writing %.500s\xe2\x80\xa6", path);
    progress_phase(bar, what);
    glint_write_options w = c->write;
    w.transfer = s->transfer;
    w.threads = s->threads;
    glint_rc rc = glint_film_write(film, path, &w, err);
    progress_clear(bar);
    *seconds += cli_now() - t0;
    return rc;
}

static int finish(glint_rc rc, const glint_error *err, glint_resume *rec, char *rpath)
{
    if (rc != GLINT_OK)
        fprintf(stderr, "glint: %s\n", err->msg);
    if (rec)
        glint_resume_free(rec);
    free(rpath);
    return glint_exit_code(rc);
}

static void add_stats(glint_stats *to, const glint_stats *st)
{
    to->primary_rays += st->primary_rays;
    to->secondary_rays += st->secondary_rays;
    to->shadow_rays += st->shadow_rays;
    to->seconds += st->seconds;
}

/* Renders the scene as it stands into path through a resume record:
 * continued from path.resume with --resume, kept there when interrupted;
 * with last, the scene is freed once the render is done. Returns the exit
 * code. */
static int render_one(run *r, const char *path, bool last)
{
    const struct cli *c = r->c;
    glint_error err = {0};
    glint_resume rec = {0};
    glint_stats st = {0};
    bool resumed = false;
    double t0 = cli_now();
    char *rpath = rerun_path(path);
    glint_rc rc = !rpath && strcmp(path, "-") != 0 ? GLINT_ERR_NOMEM : GLINT_OK;
    if (rc == GLINT_OK)
        rc = rerun_open(c, r->scene, &r->s, rpath, &rec, &resumed, &err);
    if (rc != GLINT_OK)
        return finish(rc, &err, &rec, rpath);
    r->w.bar.base = rerun_percent(&rec);
    glint_callbacks cb = {&r->w, on_tile, on_progress, on_cancel};
    rc = glint_resume_render(r->scene, &r->s, &cb, &rec, &st, &err);
    add_stats(&r->stats, &st);
    r->t.render += st.seconds;
    progress_end(&r->w.bar);
    if (rc == GLINT_ERR_CANCELLED && signals_caught()) {
        int code = rerun_keep(c, &rec, rpath, true);
        finish(GLINT_OK, &err, &rec, rpath);
        return code;
    }
    if (rc == GLINT_OK && last)
        release_scene(r);
    if (rc == GLINT_OK)
        rc = write_image(c, path, &r->s, &rec.film, &r->w.bar, &r->t.write, &err);
    if (rc == GLINT_OK && resumed)
        unlink(rpath);
    if (rc == GLINT_OK && !c->quiet)
        fprintf(stderr, "wrote %s (%dx%d, %.1f s)\n", path, r->s.width, r->s.height,
                cli_now() - t0);
    r->images += rc == GLINT_OK;
    return finish(rc, &err, &rec, rpath);
}

/* Frames first..last, each at its time, to its own file. Frames --resume
 * skips are left out of the progress line's count. Returns the exit code. */
static int render_frames(run *r, int first, int last)
{
    char path[4096];
    glint_error err = {0};
    int todo = 0, k = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (int f = first; f <= last; f++) {
            glint_rc rc = glint_frame_path(r->c->output, f, path, sizeof path, &err);
            if (rc == GLINT_OK && rerun_done(r->c, path, &r->s))
                continue;
            if (rc == GLINT_OK && pass == 0) {
                todo++;
                continue;
            }
            progress_frame(&r->w.bar, ++k, todo);
            if (rc == GLINT_OK)
                rc = glint_scene_set_frame(r->scene, f, &err);
            if (rc != GLINT_OK)
                return finish(rc, &err, NULL, NULL);
            int code = render_one(r, path, false);
            if (code != 0)
                return code;
        }
    }
    return 0;
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

int batch_main(const struct cli *c)
{
    glint_error err = {0};
    run r = {.c = c};
    char first_name[4096];
    int first = 0, last = 0;
    /* a bad output name (for a sequence: the first frame's) fails now, not
     * after the render */
    glint_rc rc = c->frames ? glint_frame_path(c->output, 1, first_name, sizeof first_name, &err)
                            : GLINT_OK;
    if (rc == GLINT_OK)
        rc = glint_output_check(c->frames ? first_name : c->output, &c->write, &err);
    if (rc == GLINT_OK)
        rc = cli_load(c, &r.scene, &r.s, &r.t.load, &err);
    if (rc == GLINT_OK)
        rc = frames_for(c, r.scene, &first, &last, &err);
    if (rc != GLINT_OK) {
        glint_scene_free(r.scene);
        return finish(rc, &err, NULL, NULL);
    }
    cli_warn(r.scene, c->scene_path);
    signals_install();
    hook_parse(&r.w);
    progress_begin(&r.w.bar, stderr, progress_choose(c->quiet, c->progress, isatty(STDERR_FILENO)),
                   "glint");
    int code = first > 0 ? render_frames(&r, first, last)
               : rerun_done(c, c->output, &r.s) ? 0 : render_one(&r, c->output, true);
    if (code == 0 && c->stats)
        print_stats(&r);
    glint_scene_free(r.scene);
    return code;
}
