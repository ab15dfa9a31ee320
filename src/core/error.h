/* error: filling a glint_error. Every failing action in the library sets
 * one message and returns its code; callers add nothing and pass it up. */
#ifndef GLINT_CORE_ERROR_H
#define GLINT_CORE_ERROR_H

#include "glint.h"

#if defined(__GNUC__)
#define GLINT_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define GLINT_PRINTF(a, b)
#endif

/* Sets err (when non-null) and returns code. */
glint_rc err_set(glint_error *err, glint_rc code, const char *fmt, ...) GLINT_PRINTF(3, 4);
glint_rc err_nomem(glint_error *err);

#endif
