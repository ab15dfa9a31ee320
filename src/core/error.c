#include "error.h"

#include <stdarg.h>
#include <stdio.h>

glint_rc err_set(glint_error *err, glint_rc code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return code;
}

glint_rc err_nomem(glint_error *err)
{
    return err_set(err, GLINT_ERR_NOMEM, "out of memory");
}
