/* image_write: films to image files. The format comes from the options or
 * the file name's extension; the whole file is encoded in memory by its
 * codec (codec.h), then handed to file_write_pieces (file.h), which
 * replaces the target atomically. image_write_check runs the same checks up front, so a
 * caller can refuse a bad output name before spending time on a render. */
#ifndef GLINT_IO_IMAGE_WRITE_H
#define GLINT_IO_IMAGE_WRITE_H

#include "glint.h"

/* The format's usual extension without the dot ("png", "jpg"...); "" for
 * GLINT_FORMAT_AUTO. */
const char *image_format_name(glint_format f);
/* A format from a name or extension, any case, with or without the dot. */
glint_rc image_format_parse(const char *name, glint_format *out, glint_error *err);

/* Format, bits, quality, transfer: everything but the file system. */
glint_rc image_write_options_check(const char *path, const glint_write_options *opts,
                                   glint_error *err);
/* The options, the library the format is written with (JPEG and OpenEXR:
 * opened at first use), then the target (file_check_output). */
glint_rc image_write_check(const char *path, const glint_write_options *opts, glint_error *err);

/* Writes a width*height linear RGB float film to path ("-": standard
 * output). opts may be NULL. */
glint_rc image_write_film(const char *path, int width, int height, const float *rgb,
                          const glint_write_options *opts, glint_error *err);

#endif
