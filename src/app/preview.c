/* The preview window (glint -p): SDL2 for the window, input and drawing;
 * the picture comes from the render thread (preview_render.c). */
#include "preview.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sdl_load.h"

static const char keys_help[] =
    "glint preview keys:\n"
    "  left drag          orbit around the look-at point\n"
    "  right drag         pan\n"
    "  wheel              dolly (move closer or away)\n"
    "  right button held + W A S D  fly forward, left, back, right;  Q E  down, up\n"
    "  S                  save the image to the output file\n"
    "  R                  render again from the start\n"
    "  P                  print the camera as a YAML 'camera:' block\n"
    "  H                  this list\n"
    "  Esc, Q             close\n";

typedef struct window {
    SDL_Window *win;
    SDL_Renderer *ren;
    SDL_Texture *tex;
    int shown_w, shown_h;  /* window size in screen pixels */
    double last_title, last_watch, reload_at;
    unsigned reported;     /* the last final image reported (GLINT_TEST_REPORT) */
    bool left, right;      /* mouse buttons held */
} window;

/* Threads of this process (Linux): the test checks that the render thread
 * is gone when the window closes. */
static int thread_count(void)
{
    DIR *d = opendir("/proc/self/task");
    int n = 0;
    if (!d)
        return -1;
    for (struct dirent *e; (e = readdir(d));)
        n += e->d_name[0] != '.';
    closedir(d);
    return n;
}

/* A change of view: the render in flight stops, a new one starts. */
static void view_changed(preview *p, bool moved)
{
    pthread_mutex_lock(&p->lock);
    p->gen++;
    if (moved) {
        p->last_move = cli_now();
        p->cam_moved = true;
    }
    atomic_store(&p->cancel, 1);
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
}

static void ask(preview *p, bool *flag)
{
    pthread_mutex_lock(&p->lock);
    *flag = true;
    atomic_store(&p->cancel, 1);
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
}

static void move_camera(preview *p, void (*fn)(glint_camera *, double, double), double a,
                        double b)
{
    pthread_mutex_lock(&p->lock);
    fn(&p->cam, a, b);
    pthread_mutex_unlock(&p->lock);
    view_changed(p, true);
}

static void fly(preview *p, double f, double r, double u)
{
    pthread_mutex_lock(&p->lock);
    camera_fly(&p->cam, f, r, u);
    pthread_mutex_unlock(&p->lock);
    view_changed(p, true);
}

static void print_camera(preview *p)
{
    char buf[512];
    pthread_mutex_lock(&p->lock);
    camera_yaml(&p->cam, buf, sizeof buf);
    pthread_mutex_unlock(&p->lock);
    fputs(buf, stdout);
    fflush(stdout);
}

/* Returns false when the window should close. */
static bool on_key(preview *p, window *w, SDL_Keycode k)
{
    const double step = 0.05;
    if (w->right) {
        switch (k) {
        case SDLK_w: fly(p, step, 0, 0); return true;
        case SDLK_s: fly(p, -step, 0, 0); return true;
        case SDLK_a: fly(p, 0, -step, 0); return true;
        case SDLK_d: fly(p, 0, step, 0); return true;
        case SDLK_q: fly(p, 0, 0, -step); return true;
        case SDLK_e: fly(p, 0, 0, step); return true;
        default: break;
        }
    }
    switch (k) {
    case SDLK_ESCAPE:
    case SDLK_q:
        return false;
    case SDLK_s:
        ask(p, &p->save);
        break;
    case SDLK_r:
        pthread_mutex_lock(&p->lock);
        p->accum_gen = p->gen - 1; /* forget the samples so far */
        pthread_mutex_unlock(&p->lock);
        view_changed(p, false);
        break;
    case SDLK_p:
        print_camera(p);
        break;
    case SDLK_h:
        fputs(keys_help, stdout);
        fflush(stdout);
        break;
    default:
        break;
    }
    return true;
}

static void on_motion(preview *p, window *w, const SDL_MouseMotionEvent *m)
{
    if (w->left)
        move_camera(p, camera_orbit, m->xrel * 0.3, m->yrel * 0.3);
    else if (w->right)
        move_camera(p, camera_pan, -(double)m->xrel / w->shown_w, (double)m->yrel / w->shown_h);
}

/* Returns false when the window should close. */
static bool on_event(preview *p, window *w, const SDL_Event *e)
{
    switch (e->type) {
    case SDL_QUIT:
        return false;
    case SDL_KEYDOWN:
        return on_key(p, w, e->key.keysym.sym);
    case SDL_MOUSEBUTTONDOWN:
    case SDL_MOUSEBUTTONUP:
        if (e->button.button == SDL_BUTTON_LEFT)
            w->left = e->type == SDL_MOUSEBUTTONDOWN;
        else if (e->button.button == SDL_BUTTON_RIGHT)
            w->right = e->type == SDL_MOUSEBUTTONDOWN;
        break;
    case SDL_MOUSEMOTION:
        on_motion(p, w, &e->motion);
        break;
    case SDL_MOUSEWHEEL:
        if (e->wheel.y != 0) {
            pthread_mutex_lock(&p->lock);
            camera_dolly(&p->cam, e->wheel.y > 0 ? 0.9 : 1.0 / 0.9);
            pthread_mutex_unlock(&p->lock);
            view_changed(p, true);
        }
        break;
    case SDL_WINDOWEVENT:
        if (e->window.event == SDL_WINDOWEVENT_SIZE_CHANGED) {
            w->shown_w = e->window.data1;
            w->shown_h = e->window.data2;
        }
        pthread_mutex_lock(&p->lock);
        p->dirty = true;
        pthread_mutex_unlock(&p->lock);
        break;
    default:
        break;
    }
    return true;
}

/* Draws the picture when it changed, and the title twice a second. */
static void draw(preview *p, window *w)
{
    double t = cli_now();
    pthread_mutex_lock(&p->lock);
    bool dirty = p->dirty;
    if (dirty) {
        SDL_UpdateTexture(w->tex, NULL, p->pixels, p->width * 3);
        p->dirty = false;
    }
    bool final = p->final;
    unsigned final_gen = p->final_gen;
    int spp = p->spp;
    char title[160];
    if (t - w->last_title > 0.5 || dirty) {
        int total = p->settings.samples;
        if (p->final)
            snprintf(title, sizeof title, "glint - done, %d/%d spp", total, total);
        else if (p->moving)
            snprintf(title, sizeof title, "glint - moving, half resolution, %.1f Mrays/s",
                     p->mrays);
        else
            snprintf(title, sizeof title, "glint - %.0f%%, %d/%d spp, %.1f Mrays/s", p->percent,
                     p->spp, total, p->mrays);
    }
    pthread_mutex_unlock(&p->lock);
    if (t - w->last_title > 0.5 || dirty) {
        SDL_SetWindowTitle(w->win, title);
        w->last_title = t;
    }
    if (dirty) {
        SDL_RenderClear(w->ren);
        SDL_RenderCopy(w->ren, w->tex, NULL, NULL);
        SDL_RenderPresent(w->ren);
    }
    /* the final image is on the screen now: the tests take their shot */
    if (final && p->report && final_gen != w->reported) {
        w->reported = final_gen;
        fprintf(stderr, "preview: final image %u, %d samples per pixel\n", final_gen, spp);
    }
}

/* Once the camera stops, the full-resolution passes start; a changed file
 * is reloaded once it has been quiet for a moment (editors write in steps). */
static void tick(preview *p, window *w)
{
    double t = cli_now();
    pthread_mutex_lock(&p->lock);
    bool settled = p->moving && p->gen == p->done_gen && t - p->last_move >= PREVIEW_SETTLE;
    bool check = t - w->last_watch > 0.25;
    bool changed = check && watch_changed(&p->watch);
    pthread_mutex_unlock(&p->lock);
    if (settled)
        view_changed(p, false);
    if (check)
        w->last_watch = t;
    if (changed)
        w->reload_at = t + 0.2;
    if (w->reload_at > 0 && t >= w->reload_at) {
        w->reload_at = 0;
        ask(p, &p->reload);
    }
}

/* The window: the image's size, scaled down to fit the screen. */
static bool window_open(preview *p, window *w)
{
    if (!sdl_load(NULL))
        return false;
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "0");
    if (SDL_Init(SDL_INIT_VIDEO) != 0)
        return false;
    SDL_Rect screen;
    double f = 1.0;
    if (SDL_GetDisplayUsableBounds(0, &screen) == 0) {
        double fx = 0.95 * screen.w / p->width, fy = 0.95 * screen.h / p->height;
        f = fx < f ? fx : f;
        f = fy < f ? fy : f;
    }
    w->shown_w = (int)(p->width * f) > 0 ? (int)(p->width * f) : 1;
    w->shown_h = (int)(p->height * f) > 0 ? (int)(p->height * f) : 1;
    w->win = SDL_CreateWindow("glint", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, w->shown_w,
                              w->shown_h, SDL_WINDOW_RESIZABLE);
    if (w->win)
        w->ren = SDL_CreateRenderer(w->win, -1, SDL_RENDERER_SOFTWARE);
    if (w->ren)
        w->tex = SDL_CreateTexture(w->ren, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING,
                                   p->width, p->height);
    if (!w->tex) {
        if (w->ren)
            SDL_DestroyRenderer(w->ren);
        if (w->win)
            SDL_DestroyWindow(w->win);
        SDL_Quit();
        return false;
    }
    return true;
}

static void window_close(window *w)
{
    SDL_DestroyTexture(w->tex);
    SDL_DestroyRenderer(w->ren);
    SDL_DestroyWindow(w->win);
    SDL_Quit();
}

/* With --exit-when-done under test, the window stays until the file named
 * by GLINT_TEST_HOLD_FILE exists (a screenshot is being taken), at most a
 * minute. */
static void hold_for_test(preview *p, window *w)
{
    const char *hold = getenv("GLINT_TEST_HOLD_FILE");
    for (double t0 = cli_now(); hold && access(hold, F_OK) != 0 && cli_now() - t0 < 60;) {
        SDL_Event e;
        while (SDL_PollEvent(&e))
            ;
        draw(p, w);
        SDL_Delay(20);
    }
}

static void loop(preview *p, window *w)
{
    for (bool open = true; open;) {
        SDL_Event e;
        if (SDL_WaitEventTimeout(&e, 16)) {
            do
                open = on_event(p, w, &e) && open;
            while (open && SDL_PollEvent(&e));
        }
        tick(p, w);
        draw(p, w);
        pthread_mutex_lock(&p->lock);
        bool done = p->final && p->cli->exit_when_done;
        pthread_mutex_unlock(&p->lock);
        if (done) {
            draw(p, w);
            hold_for_test(p, w);
            open = false;
        }
    }
}

static int run(preview *p)
{
    window w = {0};
    if (!window_open(p, &w)) {
        const char *why = NULL;
        fprintf(stderr, "glint: cannot open a window (%s); rendering to %s instead\n",
                sdl_load(&why) ? SDL_GetError() : why, p->cli->output);
        return batch_main(p->cli);
    }
    int before = thread_count();
    pthread_t th;
    if (pthread_create(&th, NULL, preview_render_main, p) != 0) {
        window_close(&w);
        fprintf(stderr, "glint: cannot start the render thread\n");
        return 1;
    }
    loop(p, &w);
    pthread_mutex_lock(&p->lock);
    p->quit = true;
    atomic_store(&p->cancel, 1);
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
    pthread_join(th, NULL);
    if (p->report)
        fprintf(stderr, "preview: threads %d before the render thread, %d after it\n", before,
                thread_count());
    window_close(&w);
    return 0;
}

/* Whether the environment variable names something (set and not empty:
 * an empty DISPLAY reaches no X server either). */
static bool names_display(const char *var)
{
    const char *v = getenv(var);
    return v && *v;
}

int preview_main(const struct cli *c)
{
    bool display = names_display("DISPLAY") || names_display("WAYLAND_DISPLAY");
    if (c->preview_bench)
        return preview_bench(c, display);
    if (!display) {
        fprintf(stderr, "glint: no display for the preview window (DISPLAY and WAYLAND_DISPLAY "
                        "are unset or empty); rendering to %s\n", c->output);
        return batch_main(c);
    }
    preview p = {.cli = c, .report = getenv("GLINT_TEST_REPORT") != NULL};
    glint_error err = {0};
    glint_rc rc = cli_load(c, &p.scene, &p.settings, NULL, &err);
    if (rc != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.msg);
        return glint_exit_code(rc);
    }
    cli_warn(p.scene, c->scene_path);
    p.width = p.settings.width;
    p.height = p.settings.height;
    glint_scene_camera(p.scene, &p.cam, NULL);
    p.pixels = calloc((size_t)p.width * (size_t)p.height, 3);
    if (!p.pixels) {
        glint_scene_free(p.scene);
        fprintf(stderr, "glint: out of memory\n");
        return 1;
    }
    watch_set(&p.watch, c->scene_path, p.scene);
    pthread_mutex_init(&p.lock, NULL);
    pthread_cond_init(&p.wake, NULL);
    p.gen = 1;
    int code = run(&p);
    pthread_cond_destroy(&p.wake);
    pthread_mutex_destroy(&p.lock);
    watch_free(&p.watch);
    free(p.pixels);
    glint_scene_free(p.scene);
    return code;
}
