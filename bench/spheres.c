/* spheres: how render time grows with the number of objects. For each N
 * from 10 to 1,000,000 (x10), N random spheres (fixed seed) fill a box in
 * front of the camera with their total volume kept constant; the scene is
 * built (BVH) and rendered at 640x480, one sample per pixel, all cores.
 * Prints one markdown table row per N. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "core/rng.h"
#include "scene/scene.h"
#include "sphere_field.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int run(int n, int threads)
{
    glint_error err = {0};
    scene *s = scene_new();
    if (!s)
        return 1;
    s->camera = (camera){.eye = v3(0, 0, 0), .target = v3(0, 0, -1), .up = v3(0, 1, 0),
                         .hfov = 60.0f};
    light l = light_point(v3(30, 60, 20), v3s(1.0f), v3(1, 0, 0)); /* white, unattenuated */
    scene_add_light(s, &l);
    material m = material_default();
    m.specular = 0.5f;
    m.color = v3(0.8f, 0.6f, 0.3f);
    int mi = scene_add_material(s, &m);
    float radius = sphere_field_radius(n);
    rng r = sphere_field_rng();
    for (int i = 0; i < n; i++) {
        shape sh = shape_sphere(sphere_field_next(&r), radius);
        if (scene_add_object(s, &sh, mi, -1) < 0) {
            scene_free(s);
            return 1;
        }
    }
    double t0 = now();
    if (scene_build(s, &err) != GLINT_OK) {
        fprintf(stderr, "spheres: %s\n", err.msg);
        scene_free(s);
        return 1;
    }
    double t1 = now();
    glint_settings st = {640, 480, 1, 5, threads, GLINT_TRANSFER_NONE, 1.0 / 255,
                         GLINT_SAMPLER_GRID, 0.05, 3, 0};
    glint_film film;
    glint_stats stats;
    if (glint_render(s, &st, NULL, &film, &stats, &err) != GLINT_OK) {
        fprintf(stderr, "spheres: %s\n", err.msg);
        scene_free(s);
        return 1;
    }
    uint64_t rays = stats.primary_rays + stats.secondary_rays + stats.shadow_rays;
    printf("| %d | %.4f | %.4f | %.2f |\n", n, t1 - t0, stats.seconds, rays / stats.seconds * 1e-6);
    fflush(stdout);
    glint_film_free(&film);
    scene_free(s);
    return 0;
}

int main(int argc, char **argv)
{
    int max = argc > 1 ? atoi(argv[1]) : 1000000;
    int threads = argc > 2 ? atoi(argv[2]) : 0;
    printf("| spheres | build s | render s | Mrays/s |\n| ---: | ---: | ---: | ---: |\n");
    for (int n = 10; n <= max; n *= 10)
        if (run(n, threads) != 0)
            return 1;
    return 0;
}
