/* The lights: section. */
#include "loader.h"

#include <math.h>
#include <stddef.h>
/* ---- lights, image, camera -------------------------------------------- */

static const char *const light_types[] = {"point", NULL};
static const char *const point_light_keys[] = {"type", "position", "color", NULL};

glint_rc load_light(loader *L, uint32_t map)
{
    if (load_node(L, map)->kind != YNODE_MAP)
        return load_expected(L, map, "a mapping", "lights");
    uint32_t v;
    int type;
    glint_rc rc = load_need(L, map, "type", "light", &v);
    if (rc == GLINT_OK)
        rc = load_enum(L, v, "type", "light type", light_types, &type);
    if (rc == GLINT_OK)
        rc = load_check_keys(L, map, point_light_keys, "in point light");
    light l = {LIGHT_POINT, v3s(0.0f), v3s(1.0f)};
    if (rc == GLINT_OK)
        rc = load_need(L, map, "position", "point light", &v);
    if (rc == GLINT_OK)
        rc = load_anim_value(L, v, "position", 3, load_read_vec3, &l.position.x,
                             (int)(offsetof(light, position) / sizeof(float)), -INFINITY,
                             INFINITY);
    if (rc == GLINT_OK && (v = load_get(L, map, "color")) != YDOC_NONE)
        rc = load_anim_value(L, v, "color", 3, load_read_color, &l.color.x,
                             (int)(offsetof(light, color) / sizeof(float)), 0.0f, INFINITY);
    if (rc != GLINT_OK)
        return rc;
    int index = scene_add_light(L->s, &l);
    return index < 0 ? err_nomem(L->err) : load_anim_bind(L, ANIM_LIGHT, index);
}

