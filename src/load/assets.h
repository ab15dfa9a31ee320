/* assets: files compiled into the library (the built-in scene and its
 * textures), found by name. The table is generated at build time by
 * tools/embed.c; names are paths as scenes/ holds them ("textures/flag.png"). */
#ifndef GLINT_LOAD_ASSETS_H
#define GLINT_LOAD_ASSETS_H

#include <stdbool.h>
#include <stddef.h>
#include "glint.h"

/* The built-in scene's text (scenes/seed.yaml). */
#define ASSET_SEED_SCENE "seed.yaml"

struct asset {
    const char *name;
    const unsigned char *data;
    size_t size;
};

/* Terminated by an entry with a null name. */
extern const struct asset assets[];

bool asset_find(const char *name, const unsigned char **data, size_t *size);

/* A scene_reader (load/load.h) serving the assets: a copy of the asset
 * named path, or "No such file or directory". user is unused. */
glint_rc asset_read(void *user, const char *path, char **data, size_t *size, glint_error *err);

#endif
