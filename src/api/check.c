#include "check.h"

#include <stdarg.h>
#include <stdio.h>

glint_rc api_null(glint_error *err, const char *fn, const char *what)
{
    return err_set(err, GLINT_ERR_INPUT, "%s: %s is NULL", fn, what);
}

glint_rc api_bad(glint_error *err, const char *fn, const char *fmt, ...)
{
    if (err) {
        char msg[sizeof err->msg];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, sizeof msg, fmt, ap);
        va_end(ap);
        return err_set(err, GLINT_ERR_INPUT, "%s: %s", fn, msg);
    }
    return GLINT_ERR_INPUT;
}
