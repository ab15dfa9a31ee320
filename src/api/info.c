/* glint_scene_describe: counts of what a scene holds, for reports. */
#include "glint.h"

#include "api/check.h"
#include "scene/scene.h"

glint_rc glint_scene_describe(const glint_scene *s, glint_scene_info *out, glint_error *err)
{
    if (!s || !out)
        return api_null(err, __func__, !s ? "scene" : "out");
    *out = (glint_scene_info){s->nobjects, s->nlights, s->nmaterials, s->ntextures, s->nmeshes,
                              0, s->build_seconds};
    for (int i = 0; i < s->nobjects; i++) {
        const shape *sh = &s->objects[i].shape;
        if (sh->kind == SHAPE_MESH)
            out->triangles += (uint64_t)sh->mesh->ntris;
        else if (sh->kind == SHAPE_TRIANGLE)
            out->triangles++;
    }
    return GLINT_OK;
}

int glint_scene_source_count(const glint_scene *s) { return s ? s->nsources : 0; }

const char *glint_scene_source(const glint_scene *s, int i)
{
    return s && i >= 0 && i < s->nsources ? s->sources[i].path : NULL;
}
