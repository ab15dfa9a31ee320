/* A program that knows glint only through its installed header and
 * pkg-config file: builds a small scene in code, renders it and checks the
 * result. scripts/check-install compiles it against an installed glint. */
#include <glint.h>
#include <stdio.h>
#include <string.h>

int main(void)
{
    glint_error err = {0};
    glint_scene *scene = NULL;
    glint_film film = {0};
    int material, green_index;
    glint_material red = glint_material_default(), green = glint_material_default();
    red.color[1] = red.color[2] = 0.0;
    green.color[0] = green.color[2] = 0.0;
    glint_light light = {GLINT_LIGHT_POINT, {0, 10, 10}, {1, 1, 1}};
    glint_object ball = {.shape = {.kind = GLINT_SHAPE_SPHERE, .sphere = {{0, 0, -5}, 1}}};
    /* A ring below the ball, in the lower rows of the image. */
    glint_object ring = {.shape = {.kind = GLINT_SHAPE_TORUS, .torus = {{0, -3, -5}, 1.5, 0.4}}};
    glint_settings settings;
    if (strcmp(glint_version(), GLINT_VERSION) != 0) {
        fprintf(stderr, "client: library %s, header %s\n", glint_version(), GLINT_VERSION);
        return 1;
    }
    if (glint_scene_new(&scene, &err) || glint_scene_add_material(scene, &red, &material, &err))
        goto fail;
    ball.material = material;
    if (glint_scene_add_material(scene, &green, &green_index, &err))
        goto fail;
    ring.material = green_index;
    if (glint_scene_add_light(scene, &light, NULL, &err) ||
        glint_scene_add_object(scene, &ball, NULL, &err) ||
        glint_scene_add_object(scene, &ring, NULL, &err) || glint_scene_build(scene, &err) ||
        glint_scene_settings(scene, &settings, &err))
        goto fail;
    settings.width = settings.height = 9;
    if (glint_render(scene, &settings, NULL, &film, NULL, &err))
        goto fail;
    const float *centre = film.rgb + (4 * 9 + 4) * 3;
    int ring_seen = 0;
    for (int i = 6 * 9; i < 9 * 9; i++)
        ring_seen |= film.rgb[i * 3 + 1] > 0.1f && film.rgb[i * 3] == 0.0f;
    if (!(centre[0] > 0.5f && centre[1] == 0.0f && film.rgb[0] == 0.0f && ring_seen)) {
        fprintf(stderr, "client: unexpected pixels\n");
        return 1;
    }
    glint_film_free(&film);
    glint_scene_free(scene);
    return 0;
fail:
    fprintf(stderr, "client: %s\n", err.msg);
    glint_scene_free(scene);
    return 1;
}
