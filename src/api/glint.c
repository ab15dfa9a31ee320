/* The public library API (include/glint.h): every glint_* function, each a
 * thin layer that checks its arguments and hands over to the module that
 * owns the work. Nothing below this file knows the public names. */
#include "glint.h"

#include <stdlib.h>

#include "core/error.h"
#include "io/image_write.h"
#include "load/load.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/settings.h"

int glint_exit_code(glint_rc rc)
{
    switch (rc) {
    case GLINT_OK:
        return 0;
    case GLINT_ERR_INPUT:
        return 2;
    case GLINT_ERR_NOMEM:
    case GLINT_ERR_IO:
    case GLINT_ERR_CANCELLED:
        return 1;
    }
    return 1;
}

glint_rc glint_scene_builtin(glint_scene **out, glint_error *err)
{
    if (!out)
        return err_set(err, GLINT_ERR_INPUT, "glint_scene_builtin: out is NULL");
    return scene_load_builtin(out, err);
}

glint_rc glint_scene_load(const char *path, glint_scene **out, glint_error *err)
{
    if (!path || !out)
        return err_set(err, GLINT_ERR_INPUT, "glint_scene_load: %s is NULL",
                       !path ? "path" : "out");
    return scene_load_file(path, out, err);
}

void glint_scene_free(glint_scene *s) { scene_free(s); }

void glint_scene_settings(const glint_scene *s, glint_settings *out)
{
    if (s && out)
        *out = s->settings;
}

glint_rc glint_settings_check(const glint_settings *s, glint_error *err)
{
    if (!s)
        return err_set(err, GLINT_ERR_INPUT, "glint_settings_check: settings is NULL");
    return settings_check(s, err);
}

int glint_default_threads(void) { return settings_default_threads(); }

glint_rc glint_render(const glint_scene *sc, const glint_settings *settings,
                      const glint_callbacks *callbacks, glint_film *film, glint_stats *stats,
                      glint_error *err)
{
    if (!sc || !settings || !film)
        return err_set(err, GLINT_ERR_INPUT, "glint_render: %s is NULL",
                       !sc ? "scene" : !settings ? "settings" : "film");
    return render_run(sc, settings, callbacks, film, stats, err);
}

void glint_film_free(glint_film *film) { render_film_free(film); }

glint_rc glint_film_write(const glint_film *film, const char *path,
                          const glint_write_options *opts, glint_error *err)
{
    if (!film || !film->rgb || !path)
        return err_set(err, GLINT_ERR_INPUT, "glint_film_write: %s is NULL",
                       !path ? "path" : "film");
    if (film->width <= 0 || film->height <= 0)
        return err_set(err, GLINT_ERR_INPUT, "glint_film_write: film is %dx%d", film->width,
                       film->height);
    return image_write_film(path, film->width, film->height, film->rgb, opts, err);
}

glint_rc glint_output_check(const char *path, const glint_write_options *opts, glint_error *err)
{
    if (!path)
        return err_set(err, GLINT_ERR_INPUT, "glint_output_check: path is NULL");
    return image_write_check(path, opts, err);
}

glint_rc glint_format_parse(const char *name, glint_format *out, glint_error *err)
{
    if (!name || !out)
        return err_set(err, GLINT_ERR_INPUT, "glint_format_parse: %s is NULL",
                       !name ? "name" : "out");
    return image_format_parse(name, out, err);
}
