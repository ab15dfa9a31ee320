/* fingerprint: a 64-bit hash of everything in a built scene that a pixel's
 * value depends on, with the settings of the render. Two renders whose
 * fingerprints match produce the same pixels, so a resume file (render/
 * resume.h) records it and refuses to continue a render of anything else.
 *
 * What it covers: the camera, background and ambient; every material,
 * texture (with its image's pixels), light and transform; every object's
 * shape (one case per kind), material and transform; every mesh's
 * vertices, normals, (u, v) and triangles; and the
 * settings but the thread count, which never changes a pixel. Values are
 * hashed field by field (never struct bytes, whose padding is undefined). */
#ifndef GLINT_SCENE_FINGERPRINT_H
#define GLINT_SCENE_FINGERPRINT_H

#include <stddef.h>
#include <stdint.h>
#include "glint.h"

struct glint_scene;

/* FNV-1a, 64-bit (Fowler, Noll, Vo): good enough to tell renders apart,
 * not meant to resist someone forging a collision. */
#define FINGERPRINT_SEED 0xcbf29ce484222325ULL

uint64_t fingerprint_bytes(uint64_t h, const void *data, size_t n);

/* The fingerprint of a built scene rendered with settings. */
uint64_t scene_fingerprint(const struct glint_scene *s, const glint_settings *settings);

#endif
