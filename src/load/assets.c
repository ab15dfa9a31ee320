#include "assets.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"

bool asset_find(const char *name, const unsigned char **data, size_t *size)
{
    for (const struct asset *a = assets; a->name; a++)
        if (strcmp(a->name, name) == 0) {
            *data = a->data;
            *size = a->size;
            return true;
        }
    return false;
}

glint_rc asset_read(void *user, const char *path, char **data, size_t *size, glint_error *err)
{
    (void)user;
    const unsigned char *bytes;
    size_t n;
    if (!asset_find(path, &bytes, &n))
        return err_set(err, GLINT_ERR_INPUT, "No such file or directory");
    *data = malloc(n ? n : 1);
    if (!*data)
        return err_nomem(err);
    memcpy(*data, bytes, n);
    *size = n;
    return GLINT_OK;
}
