#include "cli.h"

#include <stdio.h>
#include <string.h>

#include "cli/heap.h"

void cli_warn(const glint_scene *scene, const char *path)
{
    /* one line for each thing the scene's files left to say (dropped
     * triangles, textures left out) */
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

glint_rc cli_load(const struct cli *c, glint_scene **scene, glint_settings *s,
                  double *load_seconds, glint_error *err)
{
    double t0 = cli_now();
    *scene = NULL;
    glint_load_options lo = {c->threads > 0 ? c->threads : 0}; /* -t bounds every thread */
    glint_rc rc = c->scene_path ? glint_scene_load_with(c->scene_path, &lo, scene, err)
                                : glint_scene_builtin_with(&lo, scene, err);
    heap_settle(); /* the heap's room (cli/heap.h), mapped meanwhile */
    if (rc == GLINT_OK)
        rc = glint_scene_settings(*scene, s, err);
    if (rc != GLINT_OK) {
        glint_scene_free(*scene);
        *scene = NULL;
        return rc;
    }
    cli_settings(c, s);
    rc = glint_settings_check(s, err);
    if (rc != GLINT_OK) {
        glint_scene_free(*scene);
        *scene = NULL;
    }
    if (load_seconds)
        *load_seconds = cli_now() - t0;
    return rc;
}
