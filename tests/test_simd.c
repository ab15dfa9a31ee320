/* The SIMD paths of src/accel/isa.h: the built-in scene and every scene of
 * the gallery (every .yaml file in scenes/) render to the same bytes whichever path
 * traverses the BVHs (scalar, SSE, AVX2, AVX-512; the ones this CPU lacks
 * are skipped), and a forced path is the one the built BVHs use. */
#include <criterion/criterion.h>
#include <glob.h>
#include <stdlib.h>
#include <string.h>
#include "glint.h"
#include "accel/isa.h"
#include "load/load.h"
#include "scene/scene.h"
#include "film.h"

#define SCENES GLINT_SOURCE_DIR "/scenes"
#define W 96
#define H 72

/* path NULL: the built-in scene. */
static scene *load(const char *path)
{
    scene *s = NULL;
    glint_error err = {0};
    glint_rc rc = path ? scene_load_file(path, &s, &err) : glint_scene_builtin(&s, &err);
    cr_assert_eq(rc, GLINT_OK, "%s: %s", path ? path : "built-in scene", err.msg);
    return s;
}

/* Renders the scene at path with each path the CPU has and compares every
 * film with the first (scalar) one, byte for byte. */
static void same_on_every_path(const char *path)
{
    const char *name = path ? path : "built-in scene";
    glint_film first = {0};
    for (int i = ACCEL_SCALAR; i <= ACCEL_AVX512; i++) {
        if (accel_isa_force((accel_isa)i) != (accel_isa)i)
            continue; /* this CPU lacks it */
        scene *s = load(path);
        cr_assert_eq(s->bvh.isa, (accel_isa)i, "%s: the scene's BVH is not laid out for %s",
                     name, accel_isa_name((accel_isa)i));
        cr_assert_eq(s->bvh.width, accel_isa_width((accel_isa)i));
        for (int m = 0; m < s->nmeshes; m++)
            cr_assert_eq(s->meshes[m]->bvh.isa, (accel_isa)i, "%s: mesh %d", name, m);
        glint_film film = test_render(s, W, H, 4, 2);
        if (!first.rgb)
            first = film;
        else {
            cr_expect_eq(memcmp(first.rgb, film.rgb, sizeof(float) * W * H * 3), 0,
                         "%s: the %s path renders different bytes from the scalar one", name,
                         accel_isa_name((accel_isa)i));
            glint_film_free(&film);
        }
        scene_free(s);
    }
    glint_film_free(&first);
    accel_isa_force(ACCEL_AUTO);
}

Test(simd, builtin_scene_is_byte_identical_on_every_path)
{
    same_on_every_path(NULL);
}

Test(simd, gallery_is_byte_identical_on_every_path, .timeout = 120)
{
    glob_t g;
    cr_assert_eq(glob(SCENES "/*.yaml", 0, NULL, &g), 0, "no scenes in " SCENES);
    for (size_t i = 0; i < g.gl_pathc; i++)
        same_on_every_path(g.gl_pathv[i]);
    globfree(&g);
}

Test(simd, names_parse_and_forcing_never_goes_above_the_cpu)
{
    accel_isa a;
    for (int i = ACCEL_SCALAR; i <= ACCEL_AVX512; i++) {
        cr_assert(accel_isa_parse(accel_isa_name((accel_isa)i), &a));
        cr_assert_eq(a, (accel_isa)i);
    }
    cr_assert_not(accel_isa_parse("sse9", &a));
    accel_isa best = accel_isa_best();
    cr_assert_eq(accel_isa_force(ACCEL_AVX512), best);
    cr_assert_eq(accel_isa_active(), best);
    cr_assert_eq(accel_isa_force(ACCEL_SCALAR), ACCEL_SCALAR);
    cr_assert_eq(accel_isa_active(), ACCEL_SCALAR);
}

Test(simd, glint_simd_chooses_the_path)
{
    setenv("GLINT_SIMD", "scalar", 1);
    cr_assert_eq(accel_isa_force(ACCEL_AUTO), ACCEL_SCALAR);
    setenv("GLINT_SIMD", "nonsense", 1);
    cr_assert_eq(accel_isa_force(ACCEL_AUTO), accel_isa_best());
    unsetenv("GLINT_SIMD");
    cr_assert_eq(accel_isa_force(ACCEL_AUTO), accel_isa_best());
}
