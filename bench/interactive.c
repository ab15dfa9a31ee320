/* interactive: frames per second of the built-in scene at preview sizes
 * (bench/README.md, row 6): 640x360 and 1280x720, one sample per pixel,
 * all cores, the render alone (the scene is loaded once, as a preview
 * window would keep it). Two warm-up frames, then the median of --frames
 * frames per size. Prints one table row per size. */
#include <stdio.h>
#include <stdlib.h>

#include "glint.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int run(glint_scene *s, int w, int h, int frames, double goal)
{
    glint_settings st;
    glint_error err = {0};
    glint_scene_settings(s, &st, NULL);
    st.width = w;
    st.height = h;
    st.samples = 1;
    st.threads = 0;
    double *t = malloc(sizeof *t * (size_t)frames);
    if (!t)
        return 1;
    for (int i = -2; i < frames; i++) {
        glint_film film = {0};
        glint_stats stats;
        if (glint_render(s, &st, NULL, &film, &stats, &err) != GLINT_OK) {
            fprintf(stderr, "interactive: %s\n", err.msg);
            free(t);
            return 1;
        }
        if (i >= 0)
            t[i] = stats.seconds;
        glint_film_free(&film);
    }
    qsort(t, (size_t)frames, sizeof *t, cmp_double);
    double med = frames % 2 ? t[frames / 2] : 0.5 * (t[frames / 2 - 1] + t[frames / 2]);
    double fps = 1.0 / med;
    printf("| 6 | built-in scene %dx%d, 1 sample, all cores: frames/s, render only | %.1f | — | "
           "%.2f (%s) | fps ÷ %.0f ≥ 1 |\n", w, h, fps, fps / goal, fps >= goal ? "met" : "missed",
           goal);
    free(t);
    return 0;
}

int main(int argc, char **argv)
{
    int frames = argc > 1 ? atoi(argv[1]) : 25;
    frames = frames > 0 ? frames : 25;
    glint_scene *s = NULL;
    glint_error err = {0};
    if (glint_scene_builtin(&s, &err) != GLINT_OK) {
        fprintf(stderr, "interactive: %s\n", err.msg);
        return 1;
    }
    int rc = run(s, 640, 360, frames, 60.0) || run(s, 1280, 720, frames, 30.0);
    glint_scene_free(s);
    return rc;
}
