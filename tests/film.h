/* film: rendering a scene into a film inside a test, failing the test with
 * the library's message when the render fails. Shared by the unit tests. */
#ifndef GLINT_TESTS_FILM_H
#define GLINT_TESTS_FILM_H

#include <criterion/criterion.h>

#include "glint.h"

/* The scene at w x h with its own settings but for samples (<= 0: the
 * scene's) and threads (0: all cores). Free with glint_film_free. */
static inline glint_film test_render(const glint_scene *s, int w, int h, int samples,
                                     int threads)
{
    glint_settings st;
    glint_scene_settings(s, &st);
    st.width = w;
    st.height = h;
    if (samples > 0)
        st.samples = samples;
    st.threads = threads;
    glint_film film = {0};
    glint_error err = {0};
    cr_assert_eq(glint_render(s, &st, NULL, &film, NULL, &err), GLINT_OK, "%s", err.msg);
    return film;
}

#endif
