/* preview: the live window (glint -p). Two threads: the window's (SDL
 * events, drawing, watching the scene's files) and a render thread that
 * turns the current view into pictures: a quick 1-sample pass at half
 * resolution while the camera moves, then progressive passes at full
 * resolution (1 sample per pixel, then more) that end in exactly the batch
 * image (glint_render_pass, glint_accum). Any change of view or scene bumps
 * a generation counter and cancels the render in flight, which stops within
 * one tile (the library polls cancellation before every tile).
 *
 * The window's code is the only code in glint that includes SDL. */
#ifndef GLINT_APP_PREVIEW_H
#define GLINT_APP_PREVIEW_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <sys/types.h>

#include "cli.h"
#include "glint.h"

/* Seconds after the last camera change during which the view counts as
 * moving (quick passes at reduced resolution). */
#define PREVIEW_SETTLE 0.15

/* ---- watching files (preview_watch.c) ---- */
typedef struct watch_list {
    char **paths;
    int64_t *stamps; /* modification time and size, mixed; -1: missing */
    int n;
} watch_list;

typedef struct preview {
    const struct cli *cli;
    int width, height; /* the image's pixels */

    /* shared between the two threads, under lock */
    pthread_mutex_t lock;
    pthread_cond_t wake;
    glint_scene *scene;      /* swapped only by the render thread */
    glint_settings settings;
    glint_camera cam;        /* the view wanted */
    bool cam_moved;          /* the user moved the camera since the last load */
    unsigned gen, done_gen;  /* a change bumps gen; done_gen: final image shown */
    double last_move;        /* cli_now() of the last camera change */
    bool moving;             /* the render in flight is a quick pass */
    bool reload, quit;
    uint8_t *pixels;         /* width*height*3, what the window shows */
    bool dirty;              /* pixels changed since the window drew them */
    int spp;                 /* samples per pixel in every tile shown */
    double percent, mrays;   /* of the pass in flight */
    bool final;              /* pixels are the finished image */
    unsigned final_gen;      /* generation of the last finished image */
    bool save;               /* S: write the image shown to the output */
    unsigned accum_gen;      /* generation the accumulated samples belong to */
    atomic_int cancel;       /* the render in flight must stop */
    watch_list watch;        /* the scene's files (set by the render thread) */
    bool report;             /* GLINT_TEST_REPORT: a line on stderr per final image */
} preview;

/* ---- the render thread (preview_render.c) ---- */
void *preview_render_main(void *arg);

/* ---- camera moves (preview_camera.c), in the scene's units ---- */
/* Turns the eye around look_at: yaw about up, pitch towards or away from it
 * (kept short of the poles), in degrees. */
void camera_orbit(glint_camera *c, double yaw, double pitch);
/* Moves eye and look_at together along the view's right and up vectors, by
 * fractions of the distance between them. */
void camera_pan(glint_camera *c, double right, double up);
/* Moves the eye towards look_at by a factor of the distance (0.9: closer). */
void camera_dolly(glint_camera *c, double factor);
/* Flies eye and look_at: forward, right and up, by fractions of the
 * distance. */
void camera_fly(glint_camera *c, double forward, double right, double up);
/* The camera as a YAML 'camera:' block for a scene file. */
void camera_yaml(const glint_camera *c, char *buf, size_t size);

/* The scene file (may be NULL: the built-in scene, nothing to watch) and
 * every file the scene was read from. */
void watch_set(watch_list *w, const char *scene_path, const glint_scene *scene);
/* Whether a file changed since watch_set or the last call that said so. */
bool watch_changed(watch_list *w);
void watch_free(watch_list *w);

/* ---- the benchmark (preview_bench.c) ---- */
int preview_bench(const struct cli *c, bool display);

#endif
