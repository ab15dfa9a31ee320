/* Resume files (include/glint.h, src/render/resume.h): a render stopped
 * after any number of tiles, written, read back and finished, is the
 * byte-identical image; a record from another scene, camera or settings is
 * refused with a message naming the difference; a cut or damaged file is
 * refused; the caller's note comes back verbatim. */
#include <criterion/criterion.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "film.h"
#include "glint.h"
#include "tmpdir.h"

static glint_error err;
#define OK(call) cr_assert_eq((call), GLINT_OK, "%s: %s", #call, err.msg)

static void setup(void) { tmpdir_make("resume"); }

TestSuite(resume, .init = setup, .fini = tmpdir_remove);

/* Cancels once `left` tiles have finished. */
typedef struct stopper {
    atomic_int left;
} stopper;

static void count_tile(void *u, const glint_film *f, int x0, int y0, int x1, int y1)
{
    (void)f, (void)x0, (void)y0, (void)x1, (void)y1;
    atomic_fetch_sub(&((stopper *)u)->left, 1);
}

static int stop_now(void *u) { return atomic_load(&((stopper *)u)->left) <= 0; }

static glint_settings small_settings(const glint_scene *s, int threads)
{
    glint_settings st;
    OK(glint_scene_settings(s, &st, &err));
    st.width = 90; /* not a multiple of the tile side */
    st.height = 70;
    st.samples = 4;
    st.threads = threads;
    return st;
}

/* Stops a render after `after` tiles, writes the record, reads it back and
 * finishes it; the film must equal the uninterrupted one. */
static void interrupt_and_finish(const glint_scene *s, int after, int threads)
{
    glint_settings st = small_settings(s, threads);
    glint_film whole = test_render(s, st.width, st.height, st.samples, 1);
    glint_resume r;
    OK(glint_resume_init(&r, s, &st, &err));
    OK(glint_resume_set_note(&r, "note\0bytes", 10, &err));
    stopper sp = {after};
    glint_callbacks cb = {&sp, count_tile, NULL, stop_now};
    glint_rc rc = glint_resume_render(s, &st, &cb, &r, NULL, &err);
    int done = glint_resume_done(&r);
    cr_assert(rc == GLINT_ERR_CANCELLED || done == r.ntiles, "rc %d: %s", rc, err.msg);
    cr_assert_geq(done, after < r.ntiles ? after : r.ntiles, "stopped after %d tiles", done);
    char path[128];
    snprintf(path, sizeof path, "%s/out.png.resume", dir);
    OK(glint_resume_write(&r, path, &err));
    glint_resume_free(&r);

    glint_resume back;
    OK(glint_resume_read(path, &back, &err));
    cr_assert_eq(glint_resume_done(&back), done);
    cr_assert_eq(back.note_len, 10);
    cr_assert_eq(memcmp(back.note, "note\0bytes", 10), 0);
    OK(glint_resume_check(&back, s, &st, &err));
    OK(glint_resume_render(s, &st, NULL, &back, NULL, &err));
    cr_assert_eq(glint_resume_done(&back), back.ntiles);
    size_t n = (size_t)st.width * (size_t)st.height * 3 * sizeof(float);
    cr_expect_eq(memcmp(back.film.rgb, whole.rgb, n), 0,
                 "interrupted after %d tiles, finished image differs", done);
    glint_resume_free(&back);
    glint_film_free(&whole);
}

Test(resume, finishes_to_the_same_image_from_any_point)
{
    glint_scene *s;
    OK(glint_scene_builtin(&s, &err));
    int points[] = {0, 1, 7, 20, 29, 30};
    for (size_t i = 0; i < sizeof points / sizeof points[0]; i++)
        interrupt_and_finish(s, points[i], 1 + (int)(i % 2));
    glint_scene_free(s);
}

/* A record made for the built-in scene at small_settings, written to dir. */
static void write_record(const glint_scene *s, const glint_settings *st, const char *path)
{
    glint_resume r;
    OK(glint_resume_init(&r, s, st, &err));
    stopper sp = {3};
    glint_callbacks cb = {&sp, count_tile, NULL, stop_now};
    cr_assert_eq(glint_resume_render(s, st, &cb, &r, NULL, &err), GLINT_ERR_CANCELLED);
    OK(glint_resume_write(&r, path, &err));
    glint_resume_free(&r);
}

static void expect_refused(const glint_resume *r, const glint_scene *s, const glint_settings *st,
                           const char *words)
{
    glint_resume copy = *r;
    cr_expect_eq(glint_resume_check(&copy, s, st, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, words), "expected '%s' in: %s", words, err.msg);
    cr_expect_eq(glint_resume_render(s, st, NULL, &copy, NULL, &err), GLINT_ERR_INPUT);
}

Test(resume, refuses_other_scenes_and_settings)
{
    glint_scene *s;
    OK(glint_scene_builtin(&s, &err));
    glint_settings st = small_settings(s, 0);
    char path[128];
    snprintf(path, sizeof path, "%s/r.resume", dir);
    write_record(s, &st, path);
    glint_resume r;
    OK(glint_resume_read(path, &r, &err));

    glint_settings other = st;
    other.threads = 3; /* threads never change a pixel */
    OK(glint_resume_check(&r, s, &other, &err));
    other = st;
    other.samples = 9;
    expect_refused(&r, s, &other, "4 samples per pixel, this render takes 9");
    other = st;
    other.width = 91;
    expect_refused(&r, s, &other, "90x70 image, this render is 91x70");
    other = st;
    other.max_depth = 2;
    expect_refused(&r, s, &other, "depth");
    other = st;
    other.transfer = GLINT_TRANSFER_SRGB;
    expect_refused(&r, s, &other, "transfer");

    glint_camera cam;
    OK(glint_scene_camera(s, &cam, &err));
    cam.eye[0] += 0.5;
    OK(glint_scene_set_camera(s, &cam, &err));
    expect_refused(&r, s, &st, "different scene or camera");
    glint_scene_free(s);

    glint_scene *other_scene;
    OK(glint_scene_new(&other_scene, &err));
    glint_object ball = {.shape = {.kind = GLINT_SHAPE_SPHERE, .sphere = {{0, 0, -3}, 1}},
                         .material = -1};
    glint_material m = glint_material_default();
    OK(glint_scene_add_material(other_scene, &m, &ball.material, &err));
    OK(glint_scene_add_object(other_scene, &ball, NULL, &err));
    OK(glint_scene_build(other_scene, &err));
    expect_refused(&r, other_scene, &st, "different scene or camera");
    glint_scene_free(other_scene);
    glint_resume_free(&r);
}

Test(resume, fingerprint_follows_every_part_of_the_scene)
{
    glint_scene *a, *b;
    OK(glint_scene_builtin(&a, &err));
    OK(glint_scene_builtin(&b, &err));
    glint_settings st = small_settings(a, 0);
    uint64_t fa, fb;
    OK(glint_fingerprint(a, &st, &fa, &err));
    OK(glint_fingerprint(b, &st, &fb, &err));
    cr_expect_eq(fa, fb, "the same scene loaded twice");
    double grey[3] = {0.5, 0.5, 0.5};
    OK(glint_scene_set_background(b, grey, &err));
    OK(glint_scene_build(b, &err));
    OK(glint_fingerprint(b, &st, &fb, &err));
    cr_expect_neq(fa, fb, "background");
    OK(glint_scene_set_ambient(a, grey, &err));
    OK(glint_scene_build(a, &err));
    OK(glint_fingerprint(a, &st, &fa, &err));
    cr_expect_neq(fa, fb, "ambient");
    glint_scene_free(a);
    glint_scene_free(b);
}

/* The scene file's and an included file's bytes are in the fingerprint as
 * they were loaded: a comment edited in either makes another fingerprint
 * for the scene loaded again, and none for the scene loaded before (which
 * is what a render of it draws). */
Test(resume, fingerprint_follows_the_files_as_loaded)
{
    static const char *inc = "lights: [{type: point, position: [2, 4, 3]}]\n";
    static const char *top = "camera: {eye: [0, 1, 5], look_at: [0, 0, 0]}\n"
                             "objects: [{type: sphere, center: [0, 0, 0], radius: 1}]\n"
                             "include: lights.yaml\n";
    char lights[512], scene[512];
    tmpdir_write("lights.yaml", inc, lights, sizeof lights);
    tmpdir_write("scene.yaml", top, scene, sizeof scene);
    glint_scene *a, *b, *c;
    OK(glint_scene_load(scene, &a, &err));
    cr_assert_eq(glint_scene_source_count(a), 2);
    glint_settings st = small_settings(a, 1);
    uint64_t fa, again, fb, fc;
    OK(glint_fingerprint(a, &st, &fa, &err));
    char edited[512];
    snprintf(edited, sizeof edited, "%s# edited\n", inc);
    tmpdir_write("lights.yaml", edited, lights, sizeof lights);
    OK(glint_fingerprint(a, &st, &again, &err));
    cr_expect_eq(again, fa, "the loaded scene's fingerprint keeps the bytes it was read from");
    OK(glint_scene_load(scene, &b, &err));
    OK(glint_fingerprint(b, &st, &fb, &err));
    cr_expect_neq(fb, fa, "an included file edited");
    snprintf(edited, sizeof edited, "%s# edited\n", top);
    tmpdir_write("scene.yaml", edited, scene, sizeof scene);
    OK(glint_scene_load(scene, &c, &err));
    OK(glint_fingerprint(c, &st, &fc, &err));
    cr_expect_neq(fc, fb, "the scene file edited");
    glint_scene_free(a);
    glint_scene_free(b);
    glint_scene_free(c);
}

static void rewrite(const char *path, long cut, long flip)
{
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    unsigned char *data = malloc((size_t)n);
    cr_assert_eq(fread(data, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    if (flip >= 0)
        data[flip] ^= 0x40;
    f = fopen(path, "wb");
    cr_assert_eq(fwrite(data, 1, (size_t)(cut >= 0 ? cut : n), f), (size_t)(cut >= 0 ? cut : n));
    fclose(f);
    free(data);
}

Test(resume, refuses_cut_damaged_and_foreign_files)
{
    glint_scene *s;
    OK(glint_scene_builtin(&s, &err));
    glint_settings st = small_settings(s, 0);
    char path[128];
    snprintf(path, sizeof path, "%s/r.resume", dir);
    glint_resume r;
    struct { long cut, flip; const char *words; } cases[] = {
        {100, -1, "cut short"}, {2000, -1, "cut short"}, {-1, 3000, "damaged"},
        {-1, 1, "not a glint resume file"}, {5, -1, "not a glint resume file"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        write_record(s, &st, path);
        rewrite(path, cases[i].cut, cases[i].flip);
        cr_expect_eq(glint_resume_read(path, &r, &err), GLINT_ERR_INPUT, "case %zu", i);
        cr_expect(strstr(err.msg, cases[i].words) && strstr(err.msg, path),
                  "case %zu: expected '%s' and the path in: %s", i, cases[i].words, err.msg);
    }
    snprintf(path, sizeof path, "%s/missing.resume", dir);
    cr_expect_eq(glint_resume_read(path, &r, &err), GLINT_ERR_INPUT);
    cr_expect(strstr(err.msg, "No such file"), "%s", err.msg);
    cr_expect_eq(glint_resume_read(NULL, &r, &err), GLINT_ERR_INPUT);
    cr_expect_eq(glint_resume_write(NULL, path, &err), GLINT_ERR_INPUT);
    glint_scene_free(s);
}
