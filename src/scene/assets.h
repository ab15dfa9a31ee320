/* assets: files compiled into the library (the built-in scene's textures),
 * found by name. The table is generated at build time by tools/embed.c. */
#ifndef GLINT_SCENE_ASSETS_H
#define GLINT_SCENE_ASSETS_H

#include <stdbool.h>
#include <stddef.h>

struct asset {
    const char *name;
    const unsigned char *data;
    size_t size;
};

/* Terminated by an entry with a null name. */
extern const struct asset assets[];

bool asset_find(const char *name, const unsigned char **data, size_t *size);

#endif
