/* Frame sequences: frame lists, output names with a frame number, and the
 * test for a frame's output being complete (include/glint.h). */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>

#include "glint.h"
#include "tmpdir.h"

static void frames_setup(void) { tmpdir_make("frames"); }

TestSuite(frames, .init = frames_setup, .fini = tmpdir_remove);

Test(frames, lists_of_frames)
{
    glint_error err = {0};
    int a = 0, b = 0;
    cr_assert_eq(glint_frames_parse("1:120", 120, &a, &b, &err), GLINT_OK, "%s", err.msg);
    cr_expect(a == 1 && b == 120, "1:120 gave %d:%d", a, b);
    cr_assert_eq(glint_frames_parse("7", 10, &a, &b, &err), GLINT_OK, "%s", err.msg);
    cr_expect(a == 7 && b == 7, "7 gave %d:%d", a, b);
    const char *bad[] = {"", "0:3", "3:2", "1:121", "a:b", "1:", ":4", "1:2:3", "-1:3",
                         "1 :2", "99999999999:1"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        err.msg[0] = '\0';
        cr_expect_eq(glint_frames_parse(bad[i], 120, &a, &b, &err), GLINT_ERR_INPUT,
                     "'%s' accepted", bad[i]);
        cr_expect_neq(err.msg[0], '\0', "'%s': no message", bad[i]);
    }
    cr_expect_eq(glint_frames_parse("1:2", 0, &a, &b, &err), GLINT_ERR_INPUT);
}

Test(frames, output_names)
{
    struct {
        const char *pattern;
        int frame;
        const char *want;
    } cases[] = {
        {"out-%04d.png", 7, "out-0007.png"},
        {"out%d.png", 12, "out12.png"},
        {"f%3d.ppm", 5, "f  5.ppm"},
        {"out.png", 3, "out-0003.png"},
        {"dir.v2/out", 3, "dir.v2/out-0003"},
        {"renders/.hidden", 1, "renders/.hidden-0001"},
        {"a.b.exr", 120, "a.b-0120.exr"},
        {"100%%-%d.png", 2, "100%-2.png"},
        {"100%%.png", 2, "100%-0002.png"},
        {"x.png", 12345, "x-12345.png"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        char out[64];
        glint_error err = {0};
        cr_assert_eq(glint_frame_path(cases[i].pattern, cases[i].frame, out, sizeof out, &err),
                     GLINT_OK, "%s: %s", cases[i].pattern, err.msg);
        cr_expect_str_eq(out, cases[i].want, "%s, frame %d", cases[i].pattern, cases[i].frame);
    }
    const char *bad[] = {"-", "a%s.png", "a%d%d.png", "a%x.png", "a%-4d.png", "a%"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char out[64];
        glint_error err = {0};
        cr_expect_eq(glint_frame_path(bad[i], 1, out, sizeof out, &err), GLINT_ERR_INPUT,
                     "'%s' accepted", bad[i]);
        cr_expect_neq(err.msg[0], '\0');
    }
    char small[8];
    glint_error err = {0};
    cr_expect_eq(glint_frame_path("long-name.png", 1, small, sizeof small, &err),
                 GLINT_ERR_INPUT, "a name longer than the buffer");
    cr_expect_str_eq(small, "");
}

/* A written image is complete; one cut short, one of another size, a
 * missing file and a folder are not. */
Test(frames, complete_outputs)
{
    glint_film film = {0};
    glint_error err = {0};
    cr_assert_eq(glint_film_alloc(&film, 6, 4, &err), GLINT_OK, "%s", err.msg);
    const char *names[] = {"a.png", "a.ppm", "a.jpg", "a.hdr", "a.pfm", "a.exr"};
    char path[256];
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        cr_assert_eq(glint_film_write(&film, path, NULL, &err), GLINT_OK, "%s", err.msg);
        cr_expect_eq(glint_output_complete(path, 6, 4), 1, "%s", names[i]);
        cr_expect_eq(glint_output_complete(path, 0, 0), 1, "%s, any size", names[i]);
        cr_expect_eq(glint_output_complete(path, 7, 4), 0, "%s, another size", names[i]);
        /* cut short */
        FILE *f = fopen(path, "r+b");
        cr_assert_not_null(f);
        fseek(f, 0, SEEK_END);
        long n = ftell(f);
        fclose(f);
        cr_assert_eq(truncate(path, n / 2), 0);
        cr_expect_eq(glint_output_complete(path, 6, 4), 0, "%s cut to %ld bytes", names[i],
                     n / 2);
        unlink(path);
        cr_expect_eq(glint_output_complete(path, 6, 4), 0, "%s missing", names[i]);
    }
    cr_expect_eq(glint_output_complete(dir, 0, 0), 0, "a folder");
    cr_expect_eq(glint_output_complete("-", 0, 0), 0, "standard output");
    glint_film_free(&film);
}
