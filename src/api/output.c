/* output: the public functions that write films to image files
 * (include/glint.h), with their argument checks; the work is src/io's. */
#include <stddef.h>

#include "core/error.h"
#include "glint.h"
#include "io/image_write.h"

glint_rc glint_film_write(const glint_film *film, const char *path,
                          const glint_write_options *opts, glint_error *err)
{
    if (!film || !film->rgb || film->width <= 0 || film->height <= 0)
        return err_set(err, GLINT_ERR_INPUT, "glint_film_write: no film (null or empty)");
    if (!path)
        return err_set(err, GLINT_ERR_INPUT, "glint_film_write: no output path");
    return image_write_film(path, film->width, film->height, film->rgb, opts, err);
}

glint_rc glint_output_check(const char *path, const glint_write_options *opts, glint_error *err)
{
    if (!path)
        return err_set(err, GLINT_ERR_INPUT, "glint_output_check: no output path");
    return image_write_check(path, opts, err);
}

glint_rc glint_format_parse(const char *name, glint_format *out, glint_error *err)
{
    if (!name || !out)
        return err_set(err, GLINT_ERR_INPUT, "glint_format_parse: null argument");
    return image_format_parse(name, out, err);
}
