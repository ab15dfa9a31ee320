/* The built-in scene: the nine objects of the assignment this renderer grew
 * from (DESIGN.md). It is scenes/seed.yaml itself, compiled into the library
 * with the two textures it names, and read by the same loader as any scene
 * file, so `glint` and `glint scenes/seed.yaml` cannot drift apart. */
#include "core/error.h"
#include "load/assets.h"
#include "load/load.h"

glint_rc scene_load_builtin(int threads, scene **out, glint_error *err)
{
    const unsigned char *text;
    size_t size;
    if (!asset_find(ASSET_SEED_SCENE, &text, &size))
        return err_set(err, GLINT_ERR_IO, "built-in asset %s is missing", ASSET_SEED_SCENE);
    return scene_load_text_threads((const char *)text, size, ASSET_SEED_SCENE, "", asset_read, NULL,
                                   threads, out, err);
}
