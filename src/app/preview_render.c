/* The preview's render thread: quick passes while the camera moves,
 * progressive passes to the final image otherwise, scene reloads, saving. */
#include "preview.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct pass {
    preview *p;
    glint_accum *a;
    glint_film *film;
} pass;

static int on_cancel(void *u) { return atomic_load(&((pass *)u)->p->cancel); }

/* A tile of a progressive pass is done: show it. */
static void on_tile(void *u, const glint_film *f, int x0, int y0, int x1, int y1)
{
    (void)f;
    pass *ps = u;
    preview *p = ps->p;
    glint_rect r = {x0, y0, x1, y1};
    glint_accum_resolve(ps->a, &r, ps->film, NULL, NULL);
    pthread_mutex_lock(&p->lock);
    glint_film_quantize(ps->film, &r, p->settings.transfer, p->pixels, NULL);
    p->dirty = true;
    pthread_mutex_unlock(&p->lock);
}

static void on_progress(void *u, const glint_progress *g)
{
    preview *p = ((pass *)u)->p;
    pthread_mutex_lock(&p->lock);
    p->percent = g->percent;
    p->mrays = g->seconds > 0 ? (double)g->rays / g->seconds * 1e-6 : 0.0;
    pthread_mutex_unlock(&p->lock);
}

/* While moving: 1 sample per pixel at half the resolution, each pixel
 * shown as a 2 x 2 block. */
static glint_rc quick_pass(preview *p, glint_error *err)
{
    glint_settings s = p->settings;
    s.width = (p->width + 1) / 2;
    s.height = (p->height + 1) / 2;
    s.samples = 1;
    pass ps = {p, NULL, NULL};
    glint_callbacks cb = {&ps, NULL, on_progress, on_cancel};
    glint_film small = {0};
    glint_rc rc = glint_render(p->scene, &s, &cb, &small, NULL, err);
    uint8_t *rgb = rc == GLINT_OK ? malloc((size_t)s.width * (size_t)s.height * 3) : NULL;
    if (rc == GLINT_OK && !rgb)
        rc = GLINT_ERR_NOMEM;
    if (rc == GLINT_OK) {
        glint_film_quantize(&small, NULL, s.transfer, rgb, NULL);
        pthread_mutex_lock(&p->lock);
        for (int y = 0; y < p->height; y++)
            for (int x = 0; x < p->width; x++)
                memcpy(p->pixels + ((size_t)y * (size_t)p->width + (size_t)x) * 3,
                       rgb + ((size_t)(y / 2) * (size_t)s.width + (size_t)(x / 2)) * 3, 3);
        p->dirty = true;
        p->spp = 0;
        pthread_mutex_unlock(&p->lock);
    }
    free(rgb);
    glint_film_free(&small);
    return rc;
}

/* Passes of 1, 4, 16, ... samples per pixel, then all; a cancelled pass is
 * picked up where it stopped when the view has not changed. */
static glint_rc progressive(preview *p, unsigned gen, glint_accum *a, glint_film *film,
                            glint_error *err)
{
    if (p->accum_gen != gen) {
        glint_accum_clear(a);
        p->accum_gen = gen;
    }
    pass ps = {p, a, film};
    glint_callbacks cb = {&ps, on_tile, on_progress, on_cancel};
    int total = p->settings.samples;
    for (int upto = 1;; upto = upto * 4 < total ? upto * 4 : total) {
        glint_rc rc = glint_render_pass(p->scene, &p->settings, upto, &cb, a, NULL, err);
        if (rc != GLINT_OK)
            return rc;
        pthread_mutex_lock(&p->lock);
        p->spp = upto;
        pthread_mutex_unlock(&p->lock);
        if (upto == total)
            return GLINT_OK;
    }
}

/* Writes the film as the batch render would; a line on stderr either way. */
static void save(preview *p, const glint_film *film)
{
    glint_error err = {0};
    glint_write_options w = p->cli->write;
    w.transfer = p->settings.transfer;
    w.threads = p->settings.threads;
    if (glint_film_write(film, p->cli->output, &w, &err) != GLINT_OK)
        fprintf(stderr, "glint: %s\n", err.msg);
    else if (!p->cli->quiet)
        fprintf(stderr, "wrote %s (%dx%d)\n", p->cli->output, film->width, film->height);
}

/* Reads the scene again: on an error, one line and the last good scene
 * stays; the window's size stays; the user's view stays once moved. */
static void reload(preview *p)
{
    glint_scene *scene;
    glint_settings s;
    glint_error err = {0};
    if (cli_load(p->cli, &scene, &s, NULL, &err) != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.msg);
        return;
    }
    s.width = p->width;
    s.height = p->height;
    glint_camera cam;
    glint_scene_camera(scene, &cam, NULL);
    pthread_mutex_lock(&p->lock);
    glint_scene_free(p->scene);
    p->scene = scene;
    p->settings = s;
    if (!p->cam_moved)
        p->cam = cam;
    watch_set(&p->watch, p->cli->scene_path, scene);
    p->gen++;
    pthread_mutex_unlock(&p->lock);
    if (!p->cli->quiet)
        fprintf(stderr, "glint: reloaded %s\n", p->cli->scene_path);
}

/* One render for the current generation; called and returning with the
 * lock held. */
static void render_once(preview *p, glint_accum *a, glint_film *film)
{
    unsigned gen = p->gen;
    glint_camera cam = p->cam;
    bool moving = cli_now() - p->last_move < PREVIEW_SETTLE;
    atomic_store(&p->cancel, 0);
    p->moving = moving;
    p->final = false;
    pthread_mutex_unlock(&p->lock);
    glint_error err = {0};
    glint_rc rc = glint_scene_set_camera(p->scene, &cam, &err);
    if (rc == GLINT_OK)
        rc = moving ? quick_pass(p, &err) : progressive(p, gen, a, film, &err);
    if (rc == GLINT_OK && !moving && p->cli->exit_when_done)
        save(p, film);
    if (rc != GLINT_OK && rc != GLINT_ERR_CANCELLED)
        fprintf(stderr, "glint: %s\n", err.msg);
    pthread_mutex_lock(&p->lock);
    if (rc != GLINT_ERR_CANCELLED && p->gen == gen) {
        p->done_gen = gen;
        p->final = rc == GLINT_OK && !moving;
        if (p->final)
            p->final_gen = gen;
    }
}

void *preview_render_main(void *arg)
{
    preview *p = arg;
    glint_accum a = {0};
    glint_film film = {0};
    glint_error err = {0};
    if (glint_accum_alloc(&a, p->width, p->height, &err) != GLINT_OK ||
        glint_film_alloc(&film, p->width, p->height, &err) != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.msg);
        pthread_mutex_lock(&p->lock);
        p->quit = true;
        pthread_mutex_unlock(&p->lock);
    }
    pthread_mutex_lock(&p->lock);
    p->accum_gen = p->gen - 1;
    while (!p->quit) {
        if (p->save) {
            p->save = false;
            pthread_mutex_unlock(&p->lock);
            save(p, &film);
            pthread_mutex_lock(&p->lock);
        } else if (p->reload) {
            p->reload = false;
            pthread_mutex_unlock(&p->lock);
            reload(p);
            pthread_mutex_lock(&p->lock);
        } else if (p->gen != p->done_gen) {
            render_once(p, &a, &film);
        } else {
            pthread_cond_wait(&p->wake, &p->lock);
        }
    }
    pthread_mutex_unlock(&p->lock);
    glint_accum_free(&a);
    glint_film_free(&film);
    return NULL;
}
