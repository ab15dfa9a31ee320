#include "tile_lists.h"

#include <math.h>
#include "scene/scene.h"

/* A pinhole's ray through image position (x, y) has direction corner +
 * dx x + dy y, each component in floats a monotonic function of x and of
 * y, so the directions of every position of the tile's pixels lie between
 * those of its four corners. */
int tile_lists(const scene *s, const camera_frame *f, glint_rect r, int32_t *cone,
               trace_tile_shadows *shadows, bool *lit)
{
    *lit = false;
    vec3 lo = v3s(INFINITY), hi = v3s(-INFINITY);
    for (int c = 0; c < 4; c++) {
        ray8 p;
        camera_row8(f, c & 1 ? r.x1 : r.x0, 1, 0.0f, (float)(c & 2 ? r.y1 : r.y0), 0.5f, 0.5f,
                    0.0f, &p);
        vec3 d = v3(p.dx[0], p.dy[0], p.dz[0]);
        lo = v3_min(lo, d);
        hi = v3_max(hi, d);
    }
    aabb reach;
    int n = scene_cone_objects(s, f->eye, lo, hi, cone, TILE_LISTS_MAX, &reach);
    if (n < 0)
        return -1;
    for (int i = 0; i < TRACE_TILE_LIGHTS; i++) {
        const light *l = i < s->nlights ? &s->lights[i] : NULL;
        int m = -1;
        if (l && (l->kind == LIGHT_POINT || l->kind == LIGHT_SPOT))
            m = scene_shadow_cone_objects(s, reach,
                                          l->kind == LIGHT_POINT ? l->point.position
                                                                 : l->spot.position,
                                          shadows->list[i], TRACE_TILE_OBJECTS);
        shadows->n[i] = m;
        *lit |= m >= 0;
    }
    return n;
}
