#include "assets.h"

#include <string.h>

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
