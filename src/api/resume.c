/* The public resume-file functions (include/glint.h): argument checks, then
 * render/resume.c. */
#include "glint.h"

#include <stdlib.h>
#include <string.h>

#include "api/check.h"
#include "render/resume.h"
#include "scene/scene.h"
#include "scene/settings.h"

/* The settings a call uses, checked: the given ones or the scene's. */
static glint_rc use_settings(const glint_scene *sc, const glint_settings **s, glint_settings *own,
                             glint_error *err)
{
    if (!*s) {
        *own = scene_settings(sc);
        *s = own;
    }
    return settings_check(*s, err);
}

glint_rc glint_fingerprint(const glint_scene *sc, const glint_settings *s, uint64_t *out,
                           glint_error *err)
{
    if (!sc || !s || !out)
        return api_null(err, __func__, !sc ? "scene" : !s ? "settings" : "out");
    glint_rc rc = settings_check(s, err);
    if (rc != GLINT_OK)
        return rc;
    if (!sc->built)
        return api_bad(err, __func__, "scene was not built (objects were added since)");
    *out = resume_fingerprint(sc, s);
    return GLINT_OK;
}

glint_rc glint_resume_init(glint_resume *r, const glint_scene *sc, const glint_settings *s,
                           glint_error *err)
{
    if (!r || !sc)
        return api_null(err, __func__, !r ? "r" : "scene");
    glint_settings own;
    glint_rc rc = use_settings(sc, &s, &own, err);
    if (rc != GLINT_OK)
        return rc;
    return resume_init(r, sc, s, err);
}

void glint_resume_free(glint_resume *r) { resume_free(r); }

glint_rc glint_resume_set_note(glint_resume *r, const void *data, size_t len, glint_error *err)
{
    if (!r || (!data && len > 0))
        return api_null(err, __func__, !r ? "r" : "data");
    if (len > RESUME_MAX_NOTE)
        return api_bad(err, __func__, "note of %zu bytes is longer than %u", len, RESUME_MAX_NOTE);
    char *copy = malloc(len + 1);
    if (!copy)
        return err_nomem(err);
    if (len)
        memcpy(copy, data, len);
    copy[len] = '\0';
    free(r->note);
    r->note = copy;
    r->note_len = len;
    return GLINT_OK;
}

/* A record as glint_resume_init or glint_resume_read made it. */
static bool resume_whole(const glint_resume *r)
{
    glint_error e;
    return r->done && r->film.rgb && settings_check(&r->settings, &e) == GLINT_OK &&
           r->film.width == r->settings.width && r->film.height == r->settings.height &&
           r->ntiles == (r->settings.width + 15) / 16 * ((r->settings.height + 15) / 16);
}

glint_rc glint_resume_write(const glint_resume *r, const char *path, glint_error *err)
{
    if (!r || !path)
        return api_null(err, __func__, !r ? "r" : "path");
    if (!resume_whole(r) || (r->note_len && !r->note) || r->note_len > RESUME_MAX_NOTE)
        return api_bad(err, __func__, "record is not one glint_resume_init or _read made");
    return resume_write(r, path, err);
}

glint_rc glint_resume_read(const char *path, glint_resume *out, glint_error *err)
{
    if (!path || !out)
        return api_null(err, __func__, !path ? "path" : "out");
    return resume_read(path, out, err);
}

glint_rc glint_resume_check(const glint_resume *r, const glint_scene *sc,
                            const glint_settings *s, glint_error *err)
{
    if (!r || !sc)
        return api_null(err, __func__, !r ? "r" : "scene");
    glint_settings own;
    glint_rc rc = use_settings(sc, &s, &own, err);
    if (rc != GLINT_OK)
        return rc;
    if (!resume_whole(r))
        return api_bad(err, __func__, "record is not one glint_resume_init or _read made");
    return resume_check(r, sc, s, err);
}

glint_rc glint_resume_render(const glint_scene *sc, const glint_settings *s,
                             const glint_callbacks *cb, glint_resume *r, glint_stats *stats,
                             glint_error *err)
{
    if (!sc || !r)
        return api_null(err, __func__, !sc ? "scene" : "r");
    glint_settings own;
    glint_rc rc = use_settings(sc, &s, &own, err);
    if (rc != GLINT_OK)
        return rc;
    if (!resume_whole(r))
        return api_bad(err, __func__, "record is not one glint_resume_init or _read made");
    return resume_render(sc, s, cb, r, stats, err);
}

int glint_resume_done(const glint_resume *r) { return r && r->done ? resume_done_count(r) : 0; }
