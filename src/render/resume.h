/* resume: keeping an interrupted render so that it can be finished later
 * into the byte-identical image (POV-Ray's continue-trace, +C, is the
 * model). The unit is the tile of the image's grid: a resume file holds the
 * settings, the fingerprint of the scene and settings (scene/fingerprint.h),
 * which tiles are final and their pixels, and a note of the caller's (the
 * command line keeps its arguments there to run again).
 *
 * File layout, every number little-endian:
 *   "GLINTRSM" magic, u32 version (1), u32 tile side (RENDER_TILE)
 *   i32 width, height, samples, max_depth, transfer, threads
 *   f64 adc_bailout (its IEEE bits as a u64)
 *   u64 fingerprint
 *   u32 tile count, u32 note length, note bytes
 *   one byte per tile: 1 final, 0 not yet
 *   for each final tile in order, its pixels row by row, 3 f32 each
 *   u64 fingerprint_bytes of every byte before it (a damaged or cut file
 *       is refused)
 * The file is written atomically (io/file.h): an interruption while it is
 * written leaves the previous one. */
#ifndef GLINT_RENDER_RESUME_H
#define GLINT_RENDER_RESUME_H

#include "glint.h"

/* 1: the fingerprint hashed a byte at a time; 2: in one lane; 3: the
 * scene's files chained into it as read again at the render */
#define RESUME_VERSION 4
#define RESUME_MAX_NOTE (1u << 20)

struct glint_scene;

/* scene_fingerprint with a small probe render of the scene mixed in. */
uint64_t resume_fingerprint(const struct glint_scene *sc, const glint_settings *s);

glint_rc resume_init(glint_resume *r, const struct glint_scene *sc, const glint_settings *s,
                     glint_error *err);
void resume_free(glint_resume *r);
glint_rc resume_write(const glint_resume *r, const char *path, glint_error *err);
glint_rc resume_read(const char *path, glint_resume *r, glint_error *err);
/* GLINT_OK when r was made by a render of this scene with these settings;
 * otherwise GLINT_ERR_INPUT naming the first difference. */
glint_rc resume_check(const glint_resume *r, const struct glint_scene *sc,
                      const glint_settings *s, glint_error *err);
/* Renders the tiles not yet final, marking each as it finishes, so that on
 * cancellation r holds exactly the tiles whose pixels are in its film. */
glint_rc resume_render(const struct glint_scene *sc, const glint_settings *s,
                       const glint_callbacks *cb, glint_resume *r, glint_stats *stats,
                       glint_error *err);
/* Tiles marked final. */
int resume_done_count(const glint_resume *r);

#endif
