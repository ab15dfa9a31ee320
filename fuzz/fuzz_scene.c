/* libFuzzer target for the scene loader: any bytes as a scene file. The
 * reader serves the built-in assets (textures/flag.png and textures/globe.png,
 * the paths the example scenes use, and seed.yaml) and refuses every other
 * path, so runs never touch the disk. A scene that loads is also
 * rendered at a tiny size to exercise what the loader let through. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "load/assets.h"
#include "load/load.h"
#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    scene *s = NULL;
    glint_error err = {0};
    if (scene_load_text((const char *)data, size, "fuzz.yaml", "", asset_read, NULL, &s, &err) !=
        GLINT_OK)
        return 0;
    glint_settings st;
    glint_scene_settings(s, &st);
    st.width = 8;
    st.height = 8;
    st.samples = 1;
    st.threads = 1;
    if (st.max_depth > 3)
        st.max_depth = 3;
    glint_film film;
    if (glint_render(s, &st, NULL, &film, NULL, &err) == GLINT_OK)
        glint_film_free(&film);
    glint_scene_free(s);
    return 0;
}
