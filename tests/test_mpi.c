/* glint-mpi as a user meets it under mpirun: the same bytes as glint for
 * any number of processes, one message for bad input however many processes
 * met it, statistics and tile costs for each process. Runs the binaries
 * named by GLINT_BIN and GLINT_MPI_BIN (set by `make check`); each test
 * skips, saying why, where Open MPI or glint-mpi is missing. */
#include <criterion/criterion.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "glint.h"
#include "tmpdir.h"

/* Under AddressSanitizer each process of a job starts slowly (Open MPI
 * loads dozens of plug-ins), so the sanitised build runs fewer jobs: the
 * process counts 1 and 3, and leaks are looked for in one job of their own
 * (leak_check). */
#ifdef __SANITIZE_ADDRESS__
#define SANITISED 1
#define COUNTS "1 3"
#else
#define SANITISED 0
#define COUNTS "1 2 3 4"
#endif

TestSuite(mpi, .fini = tmpdir_remove);

/* An absolute path for a binary named relative to the source folder. */
static void absolute(const char *bin, char *out, size_t n)
{
    snprintf(out, n, "%s%s%s", bin[0] == '/' ? "" : GLINT_SOURCE_DIR, bin[0] == '/' ? "" : "/",
             bin);
}

/* Skips the test unless glint-mpi was built and mpirun is there; then makes
 * the test's folder. */
static void need_mpi(void)
{
    const char *bin = getenv("GLINT_MPI_BIN");
    if (!bin || !*bin)
        cr_skip_test("glint-mpi was not built (Open MPI's mpicc is missing): MPI tests skipped");
    if (system("command -v mpirun >/dev/null 2>&1") != 0)
        cr_skip_test("mpirun is missing (scripts/install-deps installs openmpi-bin): MPI tests skipped");
    tmpdir_make("mpi");
}

/* Runs a shell script in the test's folder with $GLINT (glint), $MPI
 * (glint-mpi), $MPIRUN (mpirun with its options: as root too, more
 * processes than cores allowed) and run K ARGS... ($MPIRUN -n K ARGS...). Returns the exit code; out gets
 * standard output and error. leaks: whether the sanitised build looks for
 * leaks, Open MPI's own set aside (tests/lsan-mpi.supp, which needs full
 * stacks: slower). */
static int sh_leaks(const char *script, char *out, size_t outlen, bool leaks)
{
    char glint[512], mpi[512], cmd[4096];
    absolute(getenv("GLINT_BIN") ? getenv("GLINT_BIN") : "build/glint", glint, sizeof glint);
    absolute(getenv("GLINT_MPI_BIN"), mpi, sizeof mpi);
    const char *root = geteuid() == 0 ? "--allow-run-as-root" : "";
    snprintf(cmd, sizeof cmd,
             "cd '%s' && export LSAN_OPTIONS=suppressions='%s/tests/lsan-mpi.supp':print_suppressions=0 "
             "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}%s\" "
             "&& GLINT='%s' && MPIRUN='mpirun %s --oversubscribe' && run() { $MPIRUN -n \"$@\"; } "
             "&& MPI='%s' && { %s; } 2>&1",
             dir, GLINT_SOURCE_DIR, leaks ? "fast_unwind_on_malloc=0" : "detect_leaks=0", glint, root,
             mpi, script);
    FILE *p = popen(cmd, "r");
    cr_assert_not_null(p);
    size_t n = fread(out, 1, outlen - 1, p);
    out[n] = '\0';
    int status = pclose(p);
    cr_assert(WIFEXITED(status), "the script did not exit normally: %s", out);
    return WEXITSTATUS(status);
}

static int sh(const char *script, char *out, size_t outlen)
{
    return sh_leaks(script, out, outlen, false);
}

/* Occurrences of what in text. */
static int count(const char *text, const char *what)
{
    int n = 0;
    for (const char *p = strstr(text, what); p; p = strstr(p + 1, what))
        n++;
    return n;
}

Test(mpi, one_to_four_processes_write_glints_bytes)
{
    need_mpi();
    char out[8192];
    /* 97x61: tiles cut at both edges; -t 2 keeps several threads per process */
    const char *opts = "-q -r 97x61 -s 4 -t 2";
    char script[2048];
    snprintf(script, sizeof script,
             "$GLINT %s -o g.png && $GLINT %s -o g.pfm && "
             "for k in " COUNTS "; do run $k $MPI %s -o m$k.png && run $k $MPI %s -o m$k.pfm && "
             "cmp g.png m$k.png && cmp g.pfm m$k.pfm && echo same $k; done",
             opts, opts, opts, opts);
    cr_expect_eq(sh(script, out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, SANITISED ? "same 1\nsame 3\n" : "same 1\nsame 2\nsame 3\nsame 4\n");
}

Test(mpi, a_scene_file_with_its_textures_and_srgb)
{
    need_mpi();
    if (SANITISED)
        cr_skip_test("the optimised build's run covers this (slow under the sanitisers)");
    char out[8192];
    char script[2048];
    snprintf(script, sizeof script,
             "S='%s/scenes/textures.yaml' && $GLINT -q -r 120x90 -s 1 \"$S\" -o g.png && "
             "run 3 $MPI -q -r 120x90 -s 1 -t 1 \"$S\" -o m.png && cmp g.png m.png && echo same && "
             "run 2 $MPI -q -r 120x90 -s 1 \"$S\" -o - > s.png && cmp g.png s.png && echo same on stdout",
             GLINT_SOURCE_DIR);
    cr_expect_eq(sh(script, out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "same\nsame on stdout\n");
}

/* Every process loads the scene and meets the error; rank 0 alone says it. */
Test(mpi, bad_input_is_reported_once)
{
    need_mpi();
    char out[8192];
    cr_expect_eq(sh("printf 'objects:\\n  - {type: sphere, center: [0, 0, -5], radius: -3}\\n' > bad.yaml"
                    " && run 3 $MPI -q bad.yaml 2>err.txt; echo $?; cat err.txt | grep glint",
                    out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "2\nglint-mpi: bad.yaml:2:48: radius must be > 0 (got -3)\n");
    if (SANITISED)
        return; /* one job is enough there; the rest are the same path */
    cr_expect_eq(sh("run 2 $MPI -q nope.yaml 2>err.txt; echo $?; grep glint err.txt", out, sizeof out), 0);
    cr_expect_str_eq(out, "2\nglint-mpi: nope.yaml: cannot read scene: No such file or directory\n");
    cr_expect_eq(sh("run 3 $MPI --bogus 2>err.txt; echo $?; grep glint err.txt", out, sizeof out), 0);
    cr_expect_str_eq(out, "2\nglint-mpi: unknown option --bogus (try 'glint-mpi --help')\n");
    cr_expect_eq(sh("run 2 $MPI -q -r 8x8 -o nowhere/x.png 2>err.txt; echo $?; grep glint err.txt",
                    out, sizeof out), 0);
    cr_expect_str_eq(out, "2\nglint-mpi: nowhere/x.png: folder 'nowhere' does not exist\n");
    cr_expect_eq(sh("run 3 $MPI -V", out, sizeof out), 0);
    cr_expect_str_eq(out, "glint-mpi " GLINT_VERSION "\n");
    cr_expect_eq(sh("ls", out, sizeof out), 0);
    cr_expect_str_eq(out, "bad.yaml\nerr.txt\n", "no image written");
}

/* glint-mpi takes every option glint has but the preview window's. */
Test(mpi, every_glint_option_is_a_glint_mpi_option)
{
    need_mpi();
    char out[8192];
    /* the preview window is one machine's: glint-mpi has none (-p,
     * --exit-when-done, --preview-bench) */
    cr_expect_eq(sh("$GLINT --help | grep -o -- '--[a-z-]*' | "
                    "grep -v -e '^--preview' -e '^--exit-when-done' | sort -u > a && "
                    "$MPI --help | grep -o -- '--[a-z-]*' | sort -u > b && comm -23 a b",
                    out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "", "options of glint missing from glint-mpi");
    /* and says what is wrong with them in glint's words */
    cr_expect_eq(sh("for a in '-t -1' '--frames' '--stats=1' '-r 100' '--frame 1:2'; do "
                    "$GLINT $a 2>&1 | sed 's/glint/G/g' > a; $MPI $a 2>&1 | sed 's/glint-mpi/G/g' > b; "
                    "cmp -s a b || { echo \"$a:\"; cat a b; }; done",
                    out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "", "messages differ from glint's");
}

Test(mpi, stats_give_each_process_its_tiles)
{
    need_mpi();
    char out[8192];
    cr_assert_eq(sh("run 3 $MPI -q -r 64x48 -s 1 -t 1 --stats -o a.png", out, sizeof out), 0, "%s", out);
    cr_expect(strstr(out, "image:   64x48, 1 samples/pixel, depth 5, 3 processes x 1 thread\n"), "%s", out);
    cr_expect(strstr(out, "(3072 primary"), "every pixel's ray counted once: %s", out);
    int tiles = 0, batches = 0;
    for (int r = 0; r < 3; r++) {
        char key[32];
        snprintf(key, sizeof key, "rank %d:  ", r);
        const char *line = strstr(out, key);
        cr_assert_not_null(line, "%s", out);
        int t, b;
        cr_assert_eq(sscanf(line + strlen(key), "%d tiles in %d batches", &t, &b), 2, "%s", line);
        tiles += t;
        batches += b;
    }
    cr_expect_eq(tiles, 4 * 3, "the 12 tiles, each rendered once");
    cr_expect_geq(batches, 3);
    cr_expect(strstr(out, "all:     efficiency "), "%s", out);
}

Test(mpi, tile_costs_list_every_tile_once)
{
    need_mpi();
    char out[65536];
    cr_assert_eq(sh("run 2 $MPI -q -r 100x40 -s 1 -t 2 --tile-costs costs.txt -o a.png && cat costs.txt",
                    out, sizeof out), 0, "%s", out);
    cr_expect_eq(strncmp(out, "# glint tile costs: 100x40, 16-pixel tiles, 21 tiles, 1 samples/pixel", 68), 0,
                 "%s", out);
    int seen[21] = {0}, lines = 0;
    for (const char *p = strchr(out, '\n'); p && p[1]; p = strchr(p + 1, '\n')) {
        if (p[1] == '#')
            continue;
        int t, x0, y0, x1, y1, rank;
        double s;
        cr_assert_eq(sscanf(p + 1, "%d %d %d %d %d %lf %d", &t, &x0, &y0, &x1, &y1, &s, &rank), 7, "%s", p + 1);
        cr_assert(t >= 0 && t < 21, "tile %d", t);
        seen[t]++;
        lines++;
        cr_expect(x0 == (t % 7) * 16 && y0 == (t / 7) * 16, "tile %d at (%d, %d)", t, x0, y0);
        cr_expect(x1 == (x0 + 16 < 100 ? x0 + 16 : 100) && y1 == (y0 + 16 < 40 ? y0 + 16 : 40));
        cr_expect(s > 0 && s < 60, "tile %d took %g s", t, s);
        cr_expect(rank == 0 || rank == 1, "tile %d by rank %d", t, rank);
    }
    cr_expect_eq(lines, 21);
    for (int t = 0; t < 21; t++)
        cr_expect_eq(seen[t], 1, "tile %d listed %d times", t, seen[t]);
    cr_expect_eq(count(out, "\n"), 21 + 3);
}

/* The sanitised build's leak check: a job of two processes, rank 0's and
 * the other side's code both run, with --stats and --tile-costs. */
Test(mpi, leak_check)
{
    need_mpi();
    char out[8192];
    cr_expect_eq(sh_leaks("run 2 $MPI -q -r 40x20 -s 1 -t 2 --stats --tile-costs c.txt -o a.png "
                          "2>err.txt; echo $?; grep -c '^rank' err.txt; grep -c Sanitizer err.txt",
                          out, sizeof out, true), 1, "%s", out);
    cr_expect_str_eq(out, "0\n2\n0\n", "exit 0, two ranks' lines, nothing from the sanitisers");
}

/* An animation: whole frames to each process when there are as many frames
 * as processes, tiles of each frame when there are fewer. */
Test(mpi, frames_are_glints_frames)
{
    need_mpi();
    char out[8192], script[2048];
    snprintf(script, sizeof script,
             "S='%s/scenes/orbit.yaml' && O='-q -r 48x36 -s 4' && "
             "$GLINT $O \"$S\" --frames 1:5 -o g-%%d.png && "
             "run 3 $MPI $O \"$S\" --frames 1:5 -o w-%%d.png && "
             "run 3 $MPI $O \"$S\" --frames 2:3 -o t-%%d.png && "
             "for i in 1 2 3 4 5; do cmp g-$i.png w-$i.png || echo whole $i differs; done && "
             "for i in 2 3; do cmp g-$i.png t-$i.png || echo tiled $i differs; done && ls t-* && "
             "run 2 $MPI $O \"$S\" --frames 0:3 2>&1 | grep glint",
             GLINT_SOURCE_DIR);
    cr_expect_eq(sh(script, out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "t-2.png\nt-3.png\n"
                          "glint-mpi: --frames: expected frames as FIRST:LAST or N, numbered from 1, got '0:3'\n");
}

/* A job stopped part of the way leaves its finished frames; --resume
 * renders only the others, and the sequence is glint's. */
Test(mpi, a_stopped_sequence_resumes)
{
    need_mpi();
    char out[8192], script[4096];
    snprintf(script, sizeof script,
             "S='%s/scenes/orbit.yaml'; O='-q -t 1 -r 128x96 -s 16'; "
             "$GLINT $O \"$S\" --frames 1:16 -o g-%%02d.png || exit 1; "
             "$MPIRUN -n 2 $MPI $O \"$S\" --frames 1:16 -o f-%%02d.png & job=$!; "
             "n=0; while [ ! -e f-01.png ] && [ ! -e f-02.png ] && [ $n -lt 600 ]; do sleep 0.05; n=$((n+1)); done; "
             "kill -TERM $job; wait $job 2>/dev/null; "
             "ls f-*.png > before && touch -d @0 f-*.png && "
             "{ run 2 $MPI $O \"$S\" --frames 1:16 --resume --stats -o f-%%02d.png 2> stats || cat stats; } && "
             "for f in $(cat before); do [ $(stat -c %%Y $f) = 0 ] || echo rewritten: $f; done; "
             "for i in 01 02 03 04 05 06 07 08 09 10 11 12 13 14 15 16; do cmp g-$i.png f-$i.png || echo frame $i differs; done; "
             "echo $(wc -l < before) $(awk '/^frames:/ { n = $2 } END { print n + 0 }' stats)",
             GLINT_SOURCE_DIR);
    cr_assert_eq(sh(script, out, sizeof out), 0, "%s", out);
    int kept = -1, rendered = -1;
    const char *last = strrchr(out, '\n');
    while (last && last > out && last[-1] != '\n')
        last--;
    cr_assert_not_null(last, "%s", out);
    cr_assert_eq(sscanf(last, "%d %d", &kept, &rendered), 2, "%s", out);
    cr_expect(!strstr(out, "rewritten") && !strstr(out, "differs"), "%s", out);
    cr_expect_geq(kept, 1, "the first frames were written before the stop");
    cr_expect_eq(kept + rendered, 16, "--resume rendered only the %d frames missing, not %d", 16 - kept,
                 rendered);
}

Test(mpi, resume_leaves_a_complete_image)
{
    need_mpi();
    char out[8192];
    /* a file rewritten gets the time of now; the one before is dated 1970 */
    cr_expect_eq(sh("run 2 $MPI -q -r 32x16 -s 1 -o a.png && touch -d @0 a.png && "
                    "run 2 $MPI -q -r 32x16 -s 1 -o a.png --resume --stats 2> s; "
                    "[ $(stat -c %Y a.png) = 0 ] && echo kept; cat s; "
                    "run 2 $MPI -q -r 32x24 -s 1 -o a.png --resume && [ $(stat -c %Y a.png) != 0 ] && echo redone",
                    out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "kept\nredone\n", "a complete image is not rendered again; one of another size is");
}

/* A frame that cannot be written (its name is a folder) fails the job once,
 * whichever process met it; the frames before it are on disk. */
Test(mpi, a_frame_that_cannot_be_written_fails_the_job_once)
{
    need_mpi();
    char out[8192], script[2048];
    snprintf(script, sizeof script,
             "mkdir f-3.png && run 3 $MPI -q -r 16x16 -s 1 '%s/scenes/orbit.yaml' --frames 1:6 "
             "-o f-%%d.png 2> err; echo $?; grep -c glint-mpi err; grep -o 'f-3.png: is a directory' err",
             GLINT_SOURCE_DIR);
    cr_expect_eq(sh(script, out, sizeof out), 0, "%s", out);
    cr_expect(strncmp(out, "1\n1\nf-3.png: is a directory\n", 40) == 0 ||
                  strncmp(out, "2\n1\nf-3.png: is a directory\n", 40) == 0,
              "one message, a failing status: %s", out);
}

/* A job killed part of the way through one image keeps its final tiles in
 * OUTPUT.resume (written as they come in, and again on SIGTERM); --resume
 * renders only the others, writes glint's bytes and removes the file. */
Test(mpi, a_killed_image_resumes_from_its_resume_file)
{
    need_mpi();
    if (SANITISED)
        cr_skip_test("the optimised build's run covers this (a render of seconds there)");
    char out[8192];
    /* a render long enough that the stop comes well before its end, even
     * on a loaded machine (the reference on every core: the same bytes):
     * about 6 s for the two ranks on one thread each here; at 144 samples
     * a pixel, 1.5 s, the job sometimes finished before the stop */
    const char *script =
        "O='-q -t 1 -r 512x384 -s 576'; $GLINT $O -t 0 -o g.png || exit 1; "
        "$MPIRUN -n 2 $MPI $O -o m.png & job=$!; "
        "n=0; while [ ! -e m.png.resume ] && [ $n -lt 1200 ]; do sleep 0.05; n=$((n+1)); done; "
        "kill -TERM $job; wait $job 2>/dev/null; "
        "[ -e m.png.resume ] && echo kept; [ -e m.png ] && echo 'image written before the stop'; "
        "run 2 $MPI $O -o m.png --resume --stats 2> stats || cat stats; "
        "cmp g.png m.png && echo same; [ -e m.png.resume ] && echo 'resume file left'; "
        "awk '/^rank/ { n += $3 } END { print n }' stats";
    cr_assert_eq(sh(script, out, sizeof out), 0, "%s", out);
    cr_expect(!strstr(out, "written before") && !strstr(out, "left"), "%s", out);
    const char *kept = strstr(out, "kept\nsame\n");
    cr_assert_not_null(kept, "the stop kept a resume file, and --resume wrote glint's bytes: %s",
                       out);
    int rendered = -1;
    cr_assert_eq(sscanf(kept + 10, "%d", &rendered), 1, "%s", out);
    /* 512x384: 32 x 24 tiles */
    cr_expect(rendered >= 0 && rendered < 768, "--resume rendered %d of the 768 tiles", rendered);
}

/* A resume file of another render is refused, once, with glint's words. */
Test(mpi, a_resume_file_of_another_render_is_refused_once)
{
    need_mpi();
    char out[8192];
    cr_expect_eq(sh("GLINT_TEST_SIGNALS=15@3 $GLINT -r 64x48 -s 1 -t 1 -o o.png 2>/dev/null; "
                    "run 3 $MPI -q -r 64x48 -s 4 -o o.png --resume 2>err; echo $?; grep glint err; "
                    "[ -e o.png ] && echo image written; true",
                    out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "2\nglint-mpi: o.png.resume: resume file is for 1 samples per pixel, this "
                          "render takes 4\n");
}

/* Rank 0 alone shows progress: each line once, however many processes. */
Test(mpi, progress_is_shown_once)
{
    need_mpi();
    char out[16384];
    cr_expect_eq(sh("run 3 $MPI -r 64x48 -s 1 --progress -o p.png", out, sizeof out), 0, "%s", out);
    cr_expect_eq(count(out, "100%"), 1, "%s", out);
    cr_expect_eq(count(out, "wrote p.png (64x48, "), 1, "%s", out);
    cr_expect_eq(sh("run 3 $MPI -q -r 64x48 -s 1 --progress -o q.png", out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "", "-q: no progress, no 'wrote' line");
}

/* Options are glint's table: a bad one, or one of glint's preview window,
 * is reported once, by rank 0, with status 2. */
Test(mpi, a_bad_option_is_reported_once_with_status_2)
{
    need_mpi();
    char out[8192];
    cr_expect_eq(sh("run 3 $MPI -q -s 0 2>err; echo $?; cat err | grep glint; "
                    "run 2 $MPI -p 2>err; echo $?; cat err | grep glint", out, sizeof out), 0);
    cr_expect_str_eq(out, "2\nglint-mpi: -s: expected a positive whole number, got '0' (try "
                          "'glint-mpi --help')\n"
                          "2\nglint-mpi: -p: the preview window is glint's; glint-mpi renders to "
                          "files (try 'glint-mpi --help')\n");
}

/* Frames behave as glint's: a frame stopped part of the way keeps its own
 * resume file (here glint's: the format is one), which --resume continues
 * and then removes, and the sequence is glint's. */
Test(mpi, a_frames_resume_file_is_continued)
{
    need_mpi();
    char out[8192], script[2048];
    snprintf(script, sizeof script,
             "S='%s/scenes/orbit.yaml' && O='-q -t 1 -r 48x36 -s 4' && "
             "$GLINT $O \"$S\" --frames 1:4 -o g-%%d.png && "
             "{ GLINT_TEST_SIGNALS=15@2 $GLINT $O \"$S\" --frames 1:4 -o f-%%d.png 2>/dev/null; true; } && "
             "ls f-* && run 2 $MPI $O \"$S\" --frames 1:4 -o f-%%d.png --resume && "
             "for i in 1 2 3 4; do cmp g-$i.png f-$i.png || echo frame $i differs; done; ls f-*",
             GLINT_SOURCE_DIR);
    cr_expect_eq(sh(script, out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "f-1.png.resume\nf-1.png\nf-2.png\nf-3.png\nf-4.png\n");
}
