/* load: scene files. A YAML scene (the format is docs/scene-format.md)
 * becomes a built scene, or an error that names the file, line and column
 * of what is wrong, in one line, with GLINT_ERR_INPUT (or GLINT_ERR_NOMEM).
 *
 * Files reach the loader through a scene_reader, so one code path serves
 * scenes on disk and scenes compiled into the program. Paths written in a
 * file (includes, texture images) are relative to that file's folder; the
 * reader is given them joined to it and tidied ("a/./b/../c" is "a/c").
 *
 * The loader is the first code untrusted input meets. Beyond the checks of
 * the format, it bounds what a file can make it do: file size
 * (LOAD_MAX_FILE_BYTES), nesting and alias expansion (yaml_doc.h), include
 * depth and count, and the number of objects; sizes and sample counts are
 * checked against the render limits (scene/settings.h) before anything is
 * allocated for them. On failure nothing leaks and *out is untouched. */
#ifndef GLINT_LOAD_LOAD_H
#define GLINT_LOAD_LOAD_H

#include <stddef.h>
#include "glint.h"

typedef struct glint_scene scene;

#define LOAD_MAX_FILE_BYTES (1u << 30)
#define LOAD_MAX_FILES 256        /* the scene and everything it includes */
#define LOAD_MAX_INCLUDE_DEPTH 32 /* files open inside one another */
#define LOAD_MAX_OBJECTS 10000000
#define LOAD_MAX_FRAMES 1000000 /* frames of an animation */

/* Reads the file at path (already resolved as above) into *data, a buffer
 * the caller frees with free(), and its length into *size. On failure it
 * returns an error with err->msg holding only the reason (for example "No
 * such file or directory"); the loader adds where and which file. Failures
 * other than GLINT_ERR_NOMEM are reported as GLINT_ERR_INPUT. */
typedef glint_rc (*scene_reader)(void *user, const char *path, char **data, size_t *size,
                                 glint_error *err);

/* The reader for files on disk (user is unused): regular files only; a
 * FIFO, a device or a folder is refused at once ("not a regular file",
 * "Is a directory"), before a byte is read. */
glint_rc scene_read_file(void *user, const char *path, char **data, size_t *size,
                         glint_error *err);

/* Opens path for reading when it is a regular file (without blocking on a
 * FIFO); else returns an error whose message is the reason alone. */
glint_rc load_open_regular(const char *path, int *fd, glint_error *err);

/* Loads the scene file at path; paths in it resolve against its folder.
 * Messages name the file as path. "-" and "/dev/stdin" are standard
 * input, read to its end (whatever it is), named <stdin> in messages, its
 * paths relative to the current folder. */
glint_rc scene_load_file(const char *path, scene **out, glint_error *err);

/* Loads a scene from text (len bytes). name is the text's path: messages
 * name it, and an include that leads back to it is a cycle. Relative paths
 * in the text resolve against base_dir (NULL or "": used as written).
 * reader (NULL: scene_read_file) supplies included files and texture
 * images; user is passed to it. */
glint_rc scene_load_text(const char *text, size_t len, const char *name, const char *base_dir,
                         scene_reader reader, void *user, scene **out, glint_error *err);

/* scene_load_file and scene_load_text on up to `threads` threads (0: one
 * per CPU, core/cpus.h), which the scene keeps (scene.threads): its
 * textures are decoded, its meshes' trees and its own built on that many,
 * then and at every later build. */
glint_rc scene_load_file_threads(const char *path, int threads, scene **out, glint_error *err);
glint_rc scene_load_text_threads(const char *text, size_t len, const char *name,
                                 const char *base_dir, scene_reader reader, void *user,
                                 int threads, scene **out, glint_error *err);

/* The built-in scene: scenes/seed.yaml and its textures, compiled in
 * (threads as scene_load_file_threads). */
glint_rc scene_load_builtin(int threads, scene **out, glint_error *err);

#endif
