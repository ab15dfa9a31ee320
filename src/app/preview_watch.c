/* Watching a scene's files by polling their modification time and size
 * (portable, and a scene has few files; the window polls a few times a
 * second). */
#include "preview.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int64_t stamp(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return -1;
    return (int64_t)st.st_mtim.tv_sec * 1000000007LL + st.st_mtim.tv_nsec + (int64_t)st.st_size * 31;
}

static void add(watch_list *w, const char *path)
{
    for (int i = 0; i < w->n; i++)
        if (strcmp(w->paths[i], path) == 0)
            return;
    char **p = realloc(w->paths, (size_t)(w->n + 1) * sizeof *p);
    if (!p)
        return;
    w->paths = p;
    int64_t *s = realloc(w->stamps, (size_t)(w->n + 1) * sizeof *s);
    if (!s)
        return;
    w->stamps = s;
    if (!(w->paths[w->n] = strdup(path)))
        return;
    w->stamps[w->n] = stamp(path);
    w->n++;
}

void watch_set(watch_list *w, const char *scene_path, const glint_scene *scene)
{
    watch_free(w);
    if (scene_path)
        add(w, scene_path);
    int n = scene ? glint_scene_source_count(scene) : 0;
    for (int i = 0; i < n; i++)
        add(w, glint_scene_source(scene, i));
}

bool watch_changed(watch_list *w)
{
    bool changed = false;
    for (int i = 0; i < w->n; i++) {
        int64_t s = stamp(w->paths[i]);
        if (s != w->stamps[i]) {
            w->stamps[i] = s;
            changed = true;
        }
    }
    return changed;
}

void watch_free(watch_list *w)
{
    for (int i = 0; i < w->n; i++)
        free(w->paths[i]);
    free(w->paths);
    free(w->stamps);
    *w = (watch_list){0};
}
