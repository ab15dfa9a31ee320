/* fingerprint: a 64-bit hash of a built scene and the settings of a render,
 * for resume files (render/resume.h), which refuse to continue a render of
 * anything else. It covers the settings but the thread count (which never
 * changes a pixel), the camera, background and ambient light, the counts
 * of everything in the scene, the pixels of its images, the vertices and
 * triangles of its meshes, and the bytes of every file the scene was read
 * from (scene, includes, textures, meshes), read again now. The renderer
 * adds a small probe render of the scene (resume_fingerprint), which covers
 * what a scene built in code holds in no file. Values are hashed field by
 * field, never as structures, whose padding bytes are undefined. */
#ifndef GLINT_SCENE_FINGERPRINT_H
#define GLINT_SCENE_FINGERPRINT_H

#include <stddef.h>
#include <stdint.h>
#include "glint.h"

struct glint_scene;

/* FNV-1a, 64-bit (Fowler, Noll, Vo), taken eight bytes at a time with a
 * shift that folds the product's high bits down after each word (byte by
 * byte, a gigabyte of film or mesh took a second), in four lanes side by
 * side from FINGERPRINT_LANES_FROM bytes on (the built-in scene's
 * textures took 0.5 ms, twice a render): good enough to tell renders
 * apart, not meant to resist someone forging a collision. Each step is
 * invertible, and so is the folding of the lanes in each of them, so
 * inputs of one length that differ in one place never collide. */
#define FINGERPRINT_SEED 0xcbf29ce484222325ULL
#define FINGERPRINT_LANES_FROM 256

uint64_t fingerprint_bytes(uint64_t h, const void *data, size_t n);
/* A file's n bytes, FINGERPRINT_FILE_PIECE at a time from FINGERPRINT_SEED,
 * as scene_fingerprint hashes a file it reads (scene.h: scene_source). */
#define FINGERPRINT_FILE_PIECE ((size_t)1 << 14)
uint64_t fingerprint_file_bytes(const void *data, size_t n);

uint64_t scene_fingerprint(const struct glint_scene *s, const glint_settings *settings);

#endif
