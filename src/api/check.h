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

static inline vec3 api_vec3(const double v[3])
{
    return v3((float)v[0], (float)v[1], (float)v[2]);
}

#endif
