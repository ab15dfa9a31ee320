/* tile_lists: what a tile's camera rays from a pinhole may meet, found once
 * for the tile: the objects of the scene's tree its cone of directions may
 * reach (scene_cone_objects), which its packets then test without the
 * walk (scene_intersect8_among), and for each of the first point or spot
 * lights the objects the shadow rays from their hits may meet
 * (scene_shadow_cone_objects), which the hits' lighting tests alone
 * (trace_ctx.tile). The same hits and shadows as the walks. */
#ifndef GLINT_RENDER_TILE_LISTS_H
#define GLINT_RENDER_TILE_LISTS_H

#include <stdint.h>
#include "glint.h"
#include "scene/camera.h"
#include "trace/whitted.h"

struct glint_scene;

/* The most objects a tile's camera rays are tested against without the
 * scene's tree: as many as a light's list holds. */
#define TILE_LISTS_MAX TRACE_TILE_OBJECTS

/* The lists of the pixels of r for pinhole frame f (perspective, no lens):
 * the camera rays' objects into cone (room for TILE_LISTS_MAX), their
 * count returned, or -1 where the rays must walk the tree (then shadows is
 * not set); shadows->n[i] -1 where light i's shadow rays walk it. Returns
 * whether any light has a list (*lit). */
int tile_lists(const struct glint_scene *s, const camera_frame *f, glint_rect r, int32_t *cone,
               trace_tile_shadows *shadows, bool *lit);

#endif
