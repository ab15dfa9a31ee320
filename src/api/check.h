/* check: the argument checks every public function shares, so that each
 * refusal is a GLINT_ERR_INPUT whose message names the function. */
#ifndef GLINT_API_CHECK_H
#define GLINT_API_CHECK_H

#include <math.h>
#include <stdbool.h>
#include "glint.h"
#include "core/error.h"
#include "core/vec3.h"

/* "fn: what is NULL". */
glint_rc api_null(glint_error *err, const char *fn, const char *what);
/* "fn: " and the message. */
glint_rc api_bad(glint_error *err, const char *fn, const char *fmt, ...) GLINT_PRINTF(3, 4);

/* Whether n values are finite once rounded to the renderer's floats. */
static inline bool api_finite(const double *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite((float)v[i]))
            return false;
    return true;
}

/* A colour: finite, components >= 0. */
static inline bool api_color_ok(const double c[3])
{
    return api_finite(c, 3) && c[0] >= 0.0 && c[1] >= 0.0 && c[2] >= 0.0;
}

static inline vec3 api_vec3(const double v[3])
{
    return v3((float)v[0], (float)v[1], (float)v[2]);
}

#endif
