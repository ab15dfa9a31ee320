/* Interrupted renders on the command line: Ctrl-C (SIGINT) and SIGTERM keep
 * the render in OUTPUT.resume and exit 130 / 143; --resume finishes it to
 * the byte-identical image; a resume file of another scene or other
 * settings is refused; a second signal exits at once. Signals are raised
 * at chosen tiles through GLINT_TEST_SIGNALS (src/app/batch.c), and once
 * with kill from outside. Also the terminal's reports: --progress lines,
 * the 'wrote' line, --stats. */
#include <criterion/criterion.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "glint.h"
#include "tmpdir.h"
#include "glint_run.h"

static void setup(void) { tmpdir_make("interrupt"); }

TestSuite(interrupt, .init = setup, .fini = tmpdir_remove);

/* 100x80 is 7 x 5 = 35 tiles; -t 1 makes the tiles finished exact. */
#define ARGS "-t 1 -r 100x80 -s 4"

/* Percent of the 100x80 image's pixels in its first n tiles. */
static int percent_after(int n)
{
    glint_settings s = {.width = 100, .height = 80, .samples = 4, .max_depth = 5, .threads = 1};
    long px = 0;
    for (int t = 0; t < n; t++) {
        glint_rect r;
        cr_assert_eq(glint_tile_rect(&s, t, &r, NULL), GLINT_OK);
        px += (long)(r.x1 - r.x0) * (r.y1 - r.y0);
    }
    return (int)(100.0 * (double)px / 8000.0);
}

Test(interrupt, resumes_to_the_same_image_from_several_points)
{
    char out[4096], env[64], args[256];
    cr_assert_eq(glint_run("", "-q " ARGS " -o whole.png", out, sizeof out), 0, "%s", out);
    const int at[] = {1, 12, 34};
    const int sig[] = {SIGINT, SIGTERM, SIGINT};
    for (int i = 0; i < 3; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/out.png", dir);
        unlink(path);
        snprintf(env, sizeof env, "GLINT_TEST_SIGNALS=%d@%d", sig[i], at[i]);
        int code = glint_run(env, ARGS " -o out.png", out, sizeof out);
        cr_expect_eq(code, 128 + sig[i], "signal %d after tile %d: %s", sig[i], at[i], out);
        char line[200];
        snprintf(line, sizeof line,
                 "glint: interrupted at %d%%; kept in out.png.resume (continue with: glint --resume out.png.resume)\n",
                 percent_after(at[i]));
        cr_expect_str_eq(out, line);
        cr_expect(!dir_has("out.png"), "an interrupted render writes no image");
        cr_assert(dir_has("out.png.resume"));
        /* the file alone (i even) or the same command line with --resume */
        if (i % 2 == 0)
            snprintf(args, sizeof args, "--resume out.png.resume");
        else
            snprintf(args, sizeof args, "--resume " ARGS " -o out.png");
        cr_expect_eq(glint_run("", args, out, sizeof out), 0, "%s", out);
        cr_expect(strstr(out, "wrote out.png (100x80, "), "%s", out);
        cr_expect(dir_same("out.png", "whole.png"), "resumed after %d tiles: image differs", at[i]);
        cr_expect(!dir_has("out.png.resume"), "the resume file is removed once used");
    }
}

Test(interrupt, refuses_a_resume_file_of_other_settings_or_scene)
{
    char out[4096];
    dir_put("s.yaml", "image: {width: 64, height: 48}\n"
                      "lights: [{type: point, position: [0, 5, 0]}]\n"
                      "objects: [{type: sphere, center: [0, 0, -5], radius: 1}]\n");
    cr_expect_eq(glint_run("GLINT_TEST_SIGNALS=2@2", "-t 1 s.yaml -o o.png", out, sizeof out), 130,
                 "%s", out);
    cr_expect_eq(glint_run("", "-t 1 -s 4 s.yaml --resume -o o.png", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: o.png.resume: resume file is for 1 samples per pixel, this render takes 4\n");
    cr_expect_eq(glint_run("", "-r 64x40 s.yaml --resume -o o.png", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: o.png.resume: resume file is for a 64x48 image, this render is 64x40\n");
    dir_put("s.yaml", "image: {width: 64, height: 48}\n"
                      "lights: [{type: point, position: [0, 5, 0]}]\n"
                      "objects: [{type: sphere, center: [0, 0, -5], radius: 1.5}]\n");
    cr_expect_eq(glint_run("", "s.yaml --resume -o o.png", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: o.png.resume: resume file was written for a different scene or camera\n");
    cr_expect(!dir_has("o.png") && dir_has("o.png.resume"), "a refused resume file is kept");
    dir_put("junk.resume", "not a resume file at all\n");
    cr_expect_eq(glint_run("", "--resume junk.resume", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: junk.resume: not a glint resume file\n");
    /* --resume with no file: a note, then the whole render */
    cr_expect_eq(glint_run("", "-r 16x16 --resume -o fresh.png", out, sizeof out), 0);
    cr_expect(strstr(out, "glint: no resume file fresh.png.resume; rendering from the start\n"),
              "%s", out);
    cr_expect(dir_has("fresh.png"));
}

Test(interrupt, a_second_signal_exits_at_once)
{
    char out[4096];
    int code = glint_run("GLINT_TEST_SIGNALS=2@3,2@3", ARGS " -o out.png", out, sizeof out);
    cr_expect_eq(code, 130, "%s", out);
    cr_expect(!strstr(out, "kept in"), "nothing is kept after the second signal: %s", out);
    cr_expect(!dir_has("out.png") && !dir_has("out.png.resume"));
    code = glint_run("GLINT_TEST_SIGNALS=15@3,15@3", ARGS " -o out.png", out, sizeof out);
    cr_expect_eq(code, 143, "%s", out);
}

/* glint args (with --progress) run in the background, signalled from
 * outside by the shell commands `send` once its first progress line
 * shows it rendering (a shell's background job ignores SIGINT); killed
 * outright should it ever miss the signal (glint_run puts "cd DIR &&"
 * first: the "true;" ends that list so that only glint runs in the
 * background). timeout runs in the foreground: otherwise it passes the
 * TERM on twice, to glint and to its process group. Returns glint's exit
 * code; out gets its standard error. */
static int signal_while_rendering(const char *args, const char *send, char *out, size_t cap)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd,
             "%s 2> log & pid=$!; i=0; while ! grep -qs Mrays log && [ $i -lt 600 ]; do "
             "sleep 0.1; i=$((i+1)); done; %s wait $pid; c=$?; cat log; exit $c; :",
             args, send);
    return glint_run("true; timeout --foreground -s KILL 120", cmd, out, cap);
}

Test(interrupt, kill_from_outside_keeps_a_resume_file)
{
    char out[4096];
    /* a render of minutes, stopped by one SIGTERM */
    int code = signal_while_rendering("--progress -t 2 -r 1000x1000 -s 256 -o big.png",
                                      "kill -TERM $pid;", out, sizeof out);
    cr_expect_eq(code, 143, "%s", out);
    cr_expect(strstr(out, "kept in big.png.resume"), "%s", out);
    char path[512];
    snprintf(path, sizeof path, "%s/big.png.resume", dir);
    glint_resume r;
    glint_error err;
    cr_assert_eq(glint_resume_read(path, &r, &err), GLINT_OK, "%s", err.msg);
    cr_expect_lt(glint_resume_done(&r), r.ntiles);
    cr_expect(strstr(r.note + strlen(r.note) + 1, "glint"), "the note keeps the command line");
    glint_resume_free(&r);
}

/* The same signal twice from one process, 20 ms apart, as timeout(1)
 * can send it (to the command, then to its process group): one request,
 * and the render is kept, where a second signal would leave at once. The
 * scene's tiles take a good part of a second each, so the second comes
 * while a tile is still being rendered. */
Test(interrupt, one_sender_signalling_twice_at_once_is_one_request)
{
    char out[4096];
    dir_put("slow.yaml",
            "image: {width: 64, height: 64, samples: 1024, depth: 12}\n"
            "camera: {eye: [0, 0, 3], look_at: [0, 0, 0], fov: 60}\n"
            "lights: [{type: point, position: [2, 3, 4]}, {type: point, position: [-3, 2, 4]}]\n"
            "objects:\n"
            "  - {type: sphere, center: [0, 0, 0], radius: 1.6, material: {color: 1, "
            "specular: 1, shininess: 200, reflect: 0.4, transmit: 0.5, ior: 1.5}}\n"
            "  - {type: sphere, center: [0, 0, -4], radius: 3, material: {reflect: 0.8}}\n");
    int code = signal_while_rendering("--progress -t 1 slow.yaml -o twice.png",
                                      "kill -TERM $pid; sleep 0.02; kill -TERM $pid;", out,
                                      sizeof out);
    cr_expect_eq(code, 143, "%s", out);
    cr_expect(strstr(out, "kept in twice.png.resume"), "%s", out);
    cr_expect(dir_has("twice.png.resume"));
}

Test(interrupt, progress_lines_wrote_line_and_stats)
{
    char out[8192];
    cr_assert_eq(glint_run("", "--progress " ARGS " -o p.png", out, sizeof out), 0, "%s", out);
    cr_expect(strncmp(out, "glint: ", 7) == 0 && strstr(out, "% "), "%s", out);
    cr_expect(strstr(out, "glint: 100%  "), "%s", out);
    cr_expect(strstr(out, " Mrays/s"), "%s", out);
    cr_expect(strstr(out, "glint: writing p.png\xe2\x80\xa6\n"), "%s", out);
    cr_expect(strstr(out, "wrote p.png (100x80, "), "%s", out);
    cr_assert_eq(glint_run("", ARGS " -o p.png", out, sizeof out), 0, "%s", out);
    cr_expect(strncmp(out, "wrote p.png (100x80, ", 21) == 0 && !strchr(out + 1, '%'),
              "no terminal, no --progress: only the wrote line: %s", out);
    cr_assert_eq(glint_run("", "-q --stats -r 40x30 -s 1 -o s.png", out, sizeof out), 0, "%s", out);
    cr_expect(strstr(out, "scene:   9 objects, 0 triangles, 1 lights, 0 meshes\n"), "%s", out);
    cr_expect(strstr(out, "time:    load "), "%s", out);
    cr_expect(strstr(out, ", render "), "%s", out);
    cr_expect(strstr(out, ", write "), "%s", out);
    cr_expect(strstr(out, "(1200 primary, "), "%s", out);
    cr_expect(strstr(out, "memory:  "), "%s", out);
    cr_expect(strstr(out, " MiB peak"), "%s", out);
}
