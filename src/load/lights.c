/* The lights: section. */
#include "loader.h"
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
        rc = load_need_vec3(L, map, "position", "point light", &l.position);
    if (rc == GLINT_OK && (v = load_get(L, map, "color")) != YDOC_NONE)
        rc = load_color(L, v, "color", &l.color);
    if (rc != GLINT_OK)
        return rc;
    return scene_add_light(L->s, &l) < 0 ? err_nomem(L->err) : GLINT_OK;
}

