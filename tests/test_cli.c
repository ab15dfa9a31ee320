/* The command line as a user meets it: options, messages, exit codes and
 * output files. Runs the binary named by GLINT_BIN (set by `make check`). */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "io/image.h"

static char tmpdir[64];

static void make_tmpdir(void)
{
    strcpy(tmpdir, "/tmp/glint-cli-XXXXXX");
    cr_assert_not_null(mkdtemp(tmpdir));
}

static void remove_tmpdir(void)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    cr_assert_eq(system(cmd), 0);
}

/* Runs glint with args (a shell fragment) in tmpdir; returns the exit code
 * and fills out with stdout+stderr. */
static int run(const char *args, char *out, size_t outlen)
{
    const char *bin = getenv("GLINT_BIN");
    cr_assert_not_null(bin, "GLINT_BIN must name the glint binary");
    char cmd[1024];
    char abs[512];
    if (bin[0] == '/')
        snprintf(abs, sizeof abs, "%s", bin);
    else
        snprintf(abs, sizeof abs, "%s/%s", GLINT_SOURCE_DIR, bin);
    snprintf(cmd, sizeof cmd, "cd '%s' && '%s' %s 2>&1", tmpdir, abs, args);
    FILE *p = popen(cmd, "r");
    cr_assert_not_null(p);
    size_t n = fread(out, 1, outlen - 1, p);
    out[n] = '\0';
    int status = pclose(p);
    cr_assert(WIFEXITED(status), "glint did not exit normally: %s", out);
    return WEXITSTATUS(status);
}

static bool exists(const char *name)
{
    char path[256];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    return stat(path, &st) == 0;
}

TestSuite(cli, .init = make_tmpdir, .fini = remove_tmpdir);

Test(cli, help_and_version)
{
    char out[4096];
    cr_expect_eq(run("--help", out, sizeof out), 0);
    cr_expect(strstr(out, "usage: glint [options] [SCENE.yaml | -]\n"), "%s", out);
    cr_expect(strstr(out, "--resolution WxH"));
    /* defaults and ranges, where the scene format is documented, what -r
     * keeps, and the exit status rule */
    static const char *const says[] = {
        "samples per pixel, a perfect square from 1 to 1024",
        "(default: the scene's, else 1;",
        "recursion limit, 0 to 64",
        "threads, 0 to 1024, for everything: textures, trees,",
        "docs/scene-format.md",
        "the horizontal field of view is kept",
        "'-': the scene from standard input",
        "Exit status: 0 success; 1 the render or the output failed",
        "2 bad usage or bad input: an option, the scene or a file it\nnames, an unreadable one "
        "included.",
    };
    for (size_t i = 0; i < sizeof says / sizeof *says; i++)
        cr_expect(strstr(out, says[i]), "--help lacks '%s'", says[i]);
    for (const char *p = out; *p; p++)
        cr_expect((*p >= ' ' && *p < 127) || *p == '\n', "--help prints byte 0x%02x",
                  (unsigned char)*p);
    cr_expect_eq(run("-V", out, sizeof out), 0);
    cr_expect_str_eq(out, "glint " GLINT_VERSION "\n");
}

Test(cli, default_render_writes_glint_png)
{
    char out[4096];
    cr_assert_eq(run("-q -r 40x30", out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "", "quiet and successful means silent");
    char path[256];
    snprintf(path, sizeof path, "%s/glint.png", tmpdir);
    image img;
    glint_error err = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    cr_expect_eq(img.width, 40);
    cr_expect_eq(img.height, 30);
    image_free(&img);
}

Test(cli, ppm_output_and_stats)
{
    char out[4096];
    cr_assert_eq(run("-q -r 20x20 -s 1 -t 2 --stats -o out.ppm", out, sizeof out), 0, "%s", out);
    cr_expect(strstr(out, "rays:    "), "%s", out);
    cr_expect(strstr(out, "(400 primary"), "%s", out);
    cr_expect(strstr(out, "Mrays/s"), "%s", out);
    /* the scene is freed before the image is written; its figures are kept */
    cr_expect(strstr(out, "scene:   9 objects, 0 triangles, 1 lights, 0 meshes"), "%s", out);
    char path[256];
    snprintf(path, sizeof path, "%s/out.ppm", tmpdir);
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f);
    char head[16] = {0};
    cr_expect_eq(fread(head, 1, 11, f), 11u);
    cr_expect_str_eq(head, "P6\n20 20\n25");
    fclose(f);
}

struct bad_case {
    const char *args;
    const char *message;
};

Test(cli, bad_options_exit_2_with_one_line)
{
    static const struct bad_case cases[] = {
        {"--bogus", "glint: unknown option --bogus (try 'glint --help')\n"},
        {"-x", "glint: unknown option -x (try 'glint --help')\n"},
        {"-r", "glint: -r needs a value (try 'glint --help')\n"},
        {"-r 100", "glint: -r: expected WIDTHxHEIGHT such as 800x600, got '100' (try 'glint --help')\n"},
        {"-r 0x10", "glint: -r: expected WIDTHxHEIGHT such as 800x600, got '0x10' (try 'glint --help')\n"},
        {"-s two", "glint: -s: expected a positive whole number, got 'two' (try 'glint --help')\n"},
        {"-t -1", "glint: -t: expected a whole number from 0 to 1024 (0: one per core), got '-1' (try 'glint --help')\n"},
        {"-t 1025", "glint: -t: expected a whole number from 0 to 1024 (0: one per core), got '1025' (try 'glint --help')\n"},
        /* long options were named through a byte that was no character:
         * a raw 0x01 for --transfer, a NUL for --stats=1 */
        {"--transfer", "glint: --transfer needs a value (try 'glint --help')\n"},
        {"--spp", "glint: --spp needs a value (try 'glint --help')\n"},
        {"-q -s", "glint: -s needs a value (try 'glint --help')\n"},
        {"--stats=1", "glint: --stats takes no value (got '--stats=1') (try 'glint --help')\n"},
        {"--quiet=yes", "glint: --quiet takes no value (got '--quiet=yes') (try 'glint --help')\n"},
        {"--s 4", "glint: unknown option --s (try 'glint --help')\n"},
        {"--transfer gamma", "glint: --transfer: expected none or srgb, got 'gamma' (try 'glint --help')\n"},
        {"-s 8", "glint: samples per pixel must be a perfect square (1, 4, 9, 16, ...) for the regular grid (got 8)\n"},
        {"-r 40000x10", "glint: resolution 40000x10 is out of range (1 to 32768 per side)\n"},
        {"a.yaml b.yaml", "glint: more than one scene given ('a.yaml' and 'b.yaml') (try 'glint --help')\n"},
        {"-q -r 8x8 -o out.gif", "glint: out.gif: unknown output format '.gif' (use .png, .ppm, .jpg, .hdr, .pfm or .exr)\n"},
    };
    char out[4096];
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        cr_expect_eq(run(cases[i].args, out, sizeof out), 2, "glint %s", cases[i].args);
        cr_expect_str_eq(out, cases[i].message, "glint %s", cases[i].args);
    }
    cr_expect(!exists("glint.png") && !exists("out.gif"), "bad input writes no image");
}

Test(cli, output_in_a_missing_folder_exits_2_and_leaves_nothing)
{
    char out[4096];
    cr_expect_eq(run("-q -r 8x8 -o missing-dir/x.png", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: missing-dir/x.png: folder 'missing-dir' does not exist\n");
    cr_expect(!exists("missing-dir"));
}

Test(cli, existing_output_is_replaced_whole)
{
    char out[4096];
    cr_assert_eq(run("-q -r 8x8 -o same.png", out, sizeof out), 0, "%s", out);
    cr_assert_eq(run("-q -r 16x8 -o same.png", out, sizeof out), 0, "%s", out);
    char path[256];
    snprintf(path, sizeof path, "%s/same.png", tmpdir);
    image img;
    glint_error err = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    cr_expect_eq(img.width, 16);
    image_free(&img);
    cr_expect_eq(run("-q -r 8x8 -o same.png && ls", out, sizeof out), 0);
    cr_expect_str_eq(out, "same.png\n", "no temporary files are left behind");
}

/* Writes text to name in tmpdir. */
static void put(const char *name, const char *text)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f);
    fputs(text, f);
    fclose(f);
}

Test(cli, bad_scene_files_exit_2_naming_file_line_and_column)
{
    char out[4096];
    put("bad.yaml", "objects:\n  - {type: sphere, center: [0, 0, -5], radius: -3}\n");
    cr_expect_eq(run("-q bad.yaml", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: bad.yaml:2:48: radius must be > 0 (got -3)\n");
    cr_expect_eq(run("-q nope.yaml", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: nope.yaml: cannot read scene: No such file or directory\n");
    put("typo.yaml", "objets: []\n");
    cr_expect_eq(run("-q typo.yaml", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: typo.yaml:1:1: unknown key 'objets' at the top level (did you "
                          "mean 'objects'?)\n");
    cr_expect(!exists("glint.png"), "bad input writes no image");
}

/* A model file that crashes the importer (assimp aborts on it) is one line
 * naming the file and exit 2; dropped triangles are a warning line. */
Test(cli, a_model_that_crashes_the_importer_exits_2_with_one_line)
{
    char out[4096], text[1024];
    snprintf(text, sizeof text, "objects: [{type: mesh, file: %s/tests/mesh-regress/"
             "abort-postprocess-1.ply}]\n", GLINT_SOURCE_DIR);
    put("crash.yaml", text);
    cr_expect_eq(run("-q -r 8x8 crash.yaml", out, sizeof out), 2);
    char want[1024];
    snprintf(want, sizeof want, "glint: crash.yaml:1:30: %s/tests/mesh-regress/"
             "abort-postprocess-1.ply: the importer failed (truncated or corrupt file?)\n",
             GLINT_SOURCE_DIR);
    cr_expect_str_eq(out, want);
    cr_expect(!exists("glint.png"), "bad input writes no image");
    put("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n");
    put("zero.yaml", "lights: [{type: point, position: [0, 5, 5]}]\n"
                     "objects: [{type: mesh, file: zero.obj}]\n");
    cr_expect_eq(run("-q -r 8x8 zero.yaml -o z.ppm", out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "glint: warning: zero.obj: 1 of 2 triangles dropped (1 of zero area)\n");
}

Test(cli, options_override_the_scene_settings)
{
    char out[4096];
    put("small.yaml", "image: {width: 8, height: 6, samples: 9, depth: 2}\n"
                      "lights: [{type: point, position: [0, 5, 0]}]\n"
                      "objects: [{type: sphere, center: [0, 0, -5], radius: 1}]\n");
    cr_expect_eq(run("-q --stats small.yaml -o a.ppm", out, sizeof out), 0, "%s", out);
    cr_expect(strstr(out, "image:   8x6, 9 samples/pixel, depth 2"), "%s", out);
    cr_expect_eq(run("-q --stats small.yaml -r 16x12 -s 1 -d 3 -o b.ppm", out, sizeof out), 0,
                 "%s", out);
    cr_expect(strstr(out, "image:   16x12, 1 samples/pixel, depth 3"), "%s", out);
    char path[256];
    snprintf(path, sizeof path, "%s/b.ppm", tmpdir);
    image img;
    glint_error err = {0};
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    cr_expect_eq(img.width, 16);
    cr_expect_eq(img.height, 12);
    image_free(&img);
}

/* Runs a shell script in tmpdir with $GLINT naming the binary; returns the
 * exit code and fills out with what the script writes to stdout+stderr
 * (redirections inside the script stay its own). */
static int run_sh(const char *script, char *out, size_t outlen)
{
    const char *bin = getenv("GLINT_BIN");
    cr_assert_not_null(bin, "GLINT_BIN must name the glint binary");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "cd '%s' && GLINT='%s%s%s' && { %s; } 2>&1", tmpdir,
             bin[0] == '/' ? "" : GLINT_SOURCE_DIR, bin[0] == '/' ? "" : "/", bin, script);
    FILE *p = popen(cmd, "r");
    cr_assert_not_null(p);
    size_t n = fread(out, 1, outlen - 1, p);
    out[n] = '\0';
    int status = pclose(p);
    cr_assert(WIFEXITED(status), "the script did not exit normally: %s", out);
    return WEXITSTATUS(status);
}

/* ---- output files --------------------------------------------------------- */

/* Output names are judged before the scene is rendered: these settings
 * (8000x8000 at 64 samples) would take minutes, but every case exits 2 with
 * one line at once, and nothing is written. */
Test(cli, bad_output_names_exit_2_before_rendering)
{
    char out[4096];
    cr_assert_eq(run("-q -r 8x8 -o sub.png && mkdir somedir sub.png.d && chmod 0444 sub.png", out,
                     sizeof out), 0, "%s", out);
    static const struct bad_case cases[] = {
        {"-r 8000x8000 -s 64 -o x.gif", "glint: x.gif: unknown output format '.gif' (use .png, "
                                       ".ppm, .jpg, .hdr, .pfm or .exr)\n"},
        {"-r 8000x8000 -s 64 -o somedir", "glint: somedir: is a directory\n"},
        {"-r 8000x8000 -s 64 -o nowhere/x.png", "glint: nowhere/x.png: folder 'nowhere' does not exist\n"},
        {"-r 8000x8000 -s 64 -o sub.png", "glint: sub.png: file is read-only (mode 0444)\n"},
        {"-r 8000x8000 -s 64 -o x.jpg --bits 16", "glint: x.jpg: 16 bits per channel is not possible in .jpg\n"},
        {"--format gif", "glint: --format: unknown image format 'gif' (use png, ppm, jpg, hdr, pfm or exr) (try 'glint --help')\n"},
        {"--quality 0", "glint: --quality: expected a whole number from 1 to 100, got '0' (try 'glint --help')\n"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        cr_expect_eq(run(cases[i].args, out, sizeof out), 2, "glint %s", cases[i].args);
        cr_expect_str_eq(out, cases[i].message, "glint %s", cases[i].args);
    }
    cr_expect_eq(run_sh("ls -A . somedir", out, sizeof out), 0);
    cr_expect_str_eq(out, ".:\nsomedir\nsub.png\nsub.png.d\n\nsomedir:\n",
                     "the checks leave no file behind");
    cr_expect(!exists("x.gif") && !exists("x.jpg"), "nothing written");
}

/* "-o -" writes to standard output: PNG unless --format says otherwise. */
Test(cli, dash_writes_the_image_to_standard_output)
{
    char out[4096];
    cr_assert_eq(run("-q -r 16x8 -o - > std.png", out, sizeof out), 0, "%s", out);
    cr_assert_eq(run("-q -r 16x8 --format ppm -o - > std.ppm", out, sizeof out), 0, "%s", out);
    const char *names[] = {"std.png", "std.ppm"};
    for (int i = 0; i < 2; i++) {
        char path[256];
        snprintf(path, sizeof path, "%s/%s", tmpdir, names[i]);
        image img;
        glint_error err = {0};
        cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
        cr_expect_eq(img.width, 16);
        cr_expect_eq(img.height, 8);
        image_free(&img);
    }
    cr_expect_eq(run("-q -r 8x8 --format exr -o - | head -c 4 | od -An -tx1", out, sizeof out), 0);
    cr_expect_str_eq(out, " 76 2f 31 01\n", "EXR magic number");
}

/* Write errors on standard output and devices are exit 1 with the reason. */
Test(cli, write_errors_exit_1)
{
    char out[4096];
    cr_expect_eq(run_sh("\"$GLINT\" --help > /dev/full", out, sizeof out), 1);
    cr_expect_str_eq(out, "glint: cannot write to standard output: No space left on device\n");
    cr_expect_eq(run_sh("\"$GLINT\" --version > /dev/full", out, sizeof out), 1);
    cr_expect_eq(run("-q -r 8x8 -o /dev/full", out, sizeof out), 1);
    cr_expect_str_eq(out, "glint: /dev/full: cannot write: No space left on device\n");
    cr_expect_eq(run_sh("\"$GLINT\" -q -r 8x8 -o - > /dev/full", out, sizeof out), 1);
    cr_expect_str_eq(out, "glint: standard output: cannot write: No space left on device\n");
    cr_expect_eq(run_sh("ln -s /dev/full full.png && \"$GLINT\" -q -r 8x8 -o full.png", out,
                        sizeof out), 1, "a link to /dev/full");
    cr_expect_str_eq(out, "glint: full.png: cannot write: No space left on device\n");
}

/* Every format by extension, and the options that shape them. */
Test(cli, every_output_format_by_extension)
{
    char out[4096];
    const char *args[] = {"-o a.ppm", "-o a.jpg --quality 80", "-o a.hdr", "-o a.pfm",
                          "-o a.exr", "-o b.exr --bits 32", "-o b.png --bits 16",
                          "-o b.ppm --bits 16"};
    const char *files[] = {"a.ppm", "a.jpg", "a.hdr", "a.pfm", "a.exr", "b.exr", "b.png",
                           "b.ppm"};
    for (size_t i = 0; i < sizeof args / sizeof *args; i++) {
        char cmd[256];
        snprintf(cmd, sizeof cmd, "-q -r 24x16 %s", args[i]);
        cr_assert_eq(run(cmd, out, sizeof out), 0, "glint %s: %s", cmd, out);
        char path[256];
        snprintf(path, sizeof path, "%s/%s", tmpdir, files[i]);
        image img;
        glint_error err = {0};
        cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
        cr_expect_eq(img.width, 24, "%s", files[i]);
        cr_expect_eq(img.height, 16, "%s", files[i]);
        image_free(&img);
    }
}

/* A small animated scene: 5 frames of a sphere moving right. */
static const char moving[] =
    "animation: {frames: 5, fps: 10}\n"
    "image: {width: 12, height: 8}\n"
    "camera: {eye: [0, 0, 5], look_at: [0, 0, 0]}\n"
    "lights: [{type: point, position: [0, 5, 5]}]\n"
    "objects:\n"
    "  - type: sphere\n"
    "    center: [0, 0, 0]\n"
    "    radius: 1\n"
    "    transform: [{translate: {keys: [[0, [-2, 0, 0]], [0.4, [2, 0, 0]]]}}]\n";

static long mtime_ns(const char *name)
{
    char path[256];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    cr_assert_eq(stat(path, &st), 0, "%s is missing", name);
    return (long)st.st_mtim.tv_sec * 1000000000L + st.st_mtim.tv_nsec;
}

Test(cli, frames_write_one_file_each_named_by_number)
{
    char out[4096];
    put("anim.yaml", moving);
    cr_assert_eq(run("-q anim.yaml --frames 2:4 -o f%02d.png", out, sizeof out), 0, "%s", out);
    cr_expect(!exists("f01.png") && exists("f02.png") && exists("f03.png") &&
              exists("f04.png") && !exists("f05.png"), "frames 2 to 4, named by %%02d");
    cr_assert_eq(run("-q anim.yaml --frame 5 -o seq.ppm", out, sizeof out), 0, "%s", out);
    cr_expect(exists("seq-0005.ppm"), "without a field: -%%04d before the extension");
    /* the frames differ: the sphere moves */
    char a[256];
    snprintf(a, sizeof a, "cmp -s '%s/f02.png' '%s/f04.png'", tmpdir, tmpdir);
    cr_expect_neq(system(a), 0, "frames 2 and 4 are the same picture");
    /* no --frames: frame 1 to the name as given */
    cr_assert_eq(run("-q anim.yaml -o still.png", out, sizeof out), 0, "%s", out);
    cr_expect(exists("still.png"));
}

Test(cli, resume_skips_complete_frames_only)
{
    char out[4096];
    put("anim.yaml", moving);
    cr_assert_eq(run("-q anim.yaml --frames 1:5 -o f%d.png", out, sizeof out), 0, "%s", out);
    long t1 = mtime_ns("f1.png"), t2 = mtime_ns("f2.png");
    /* frame 3 cut short, frame 4 gone, frame 5 of another size */
    char cmd[512];
    snprintf(cmd, sizeof cmd,
             "cd '%s' && head -c 40 f3.png > t && mv t f3.png && rm f4.png", tmpdir);
    cr_assert_eq(system(cmd), 0);
    cr_assert_eq(run("-q anim.yaml --frame 5 -r 6x4 -o f%d.png", out, sizeof out), 0, "%s", out);
    usleep(20000);
    cr_assert_eq(run("-q anim.yaml --frames 1:5 --resume -o f%d.png", out, sizeof out), 0, "%s",
                 out);
    cr_expect_eq(mtime_ns("f1.png"), t1, "a complete frame was rendered again");
    cr_expect_eq(mtime_ns("f2.png"), t2, "a complete frame was rendered again");
    for (int f = 3; f <= 5; f++) {
        char path[256];
        snprintf(path, sizeof path, "%s/f%d.png", tmpdir, f);
        image img;
        glint_error err = {0};
        cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "frame %d: %s", f, err.msg);
        cr_expect(img.width == 12 && img.height == 8, "frame %d is %dx%d", f, img.width,
                  img.height);
        image_free(&img);
    }
}

Test(cli, bad_frame_options_exit_2)
{
    char out[4096];
    put("anim.yaml", moving);
    cr_expect_eq(run("-q anim.yaml --frames 4:9", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: --frames: frame 9 is past the animation's last (5)\n");
    cr_expect_eq(run("-q anim.yaml --frames 3:1", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: --frames: frames 3:1: the first is after the last\n");
    cr_expect_eq(run("-q anim.yaml --frame 1:2", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: --frame: expected one frame number, got '1:2' (try 'glint "
                          "--help')\n");
    cr_expect_eq(run("-q anim.yaml --frames 1:2 -o -", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: a sequence of frames cannot go to standard output ('-')\n");
    cr_expect_eq(run("-q anim.yaml --frames 1:2 -o 'a%s.png'", out, sizeof out), 2);
    cr_expect(strstr(out, "the only % field allowed is the frame number"), "%s", out);
    cr_expect_eq(run("-q --frames 2", out, sizeof out), 2, "the built-in scene has one frame");
    cr_expect(!exists("glint-0002.png") && !exists("glint.png"));
}

/* image.alpha makes an RGBA PNG whose alpha is 0 on the background. */
Test(cli, alpha_writes_rgba)
{
    char out[4096];
    put("a.yaml", "image: {width: 8, height: 8, alpha: true}\n"
                  "camera: {eye: [0, 0, 5], look_at: [0, 0, 0], fov: 30}\n"
                  "objects: [{type: sphere, center: [0, 0, 0], radius: 0.5}]\n");
    cr_assert_eq(run("-q a.yaml -o a.png", out, sizeof out), 0, "%s", out);
    char path[256];
    snprintf(path, sizeof path, "%s/a.png", tmpdir);
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f);
    unsigned char head[26];
    cr_assert_eq(fread(head, 1, sizeof head, f), sizeof head);
    fclose(f);
    cr_expect_eq(head[25], 6, "PNG colour type %d, want 6 (RGBA)", head[25]);
}

/* -t 0 is the library's "one thread per core"; it was refused. */
Test(cli, zero_threads_means_all_cores)
{
    char out[4096];
    cr_expect_eq(run("-q -r 8x8 -t 0 --stats -o z.ppm", out, sizeof out), 0, "%s", out);
    char want[64];
    snprintf(want, sizeof want, "depth 5, %d thread", glint_default_threads());
    cr_expect(strstr(out, want), "%s", out);
}

/* A scene without objects or lights renders, with a line saying why the
 * picture is dark. */
Test(cli, empty_and_unlit_scenes_are_said)
{
    char out[4096];
    put("empty.yaml", "{}\n");
    cr_expect_eq(run("-q -r 8x8 empty.yaml -o e.png", out, sizeof out), 0);
    cr_expect_str_eq(out, "glint: warning: empty.yaml has no objects: the image is the "
                          "background\n");
    put("dark.yaml", "objects: [{type: sphere, center: [0, 0, -5], radius: 1}]\n");
    cr_expect_eq(run("-q -r 8x8 dark.yaml -o d.png", out, sizeof out), 0);
    cr_expect_str_eq(out, "glint: warning: dark.yaml has no lights: only ambient light shows "
                          "(add a 'lights' list)\n");
    cr_expect(exists("e.png") && exists("d.png"));
    put("empty2.yaml", "# nothing\n");
    cr_expect_eq(run("-q -r 8x8 empty2.yaml -o e2.png", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: empty2.yaml:1:1: the scene is empty (expected a mapping with "
                          "keys such as camera, lights and objects)\n");
}

/* '-' reads the scene from standard input; a FIFO or device named as the
 * scene is refused at once instead of blocking or being read. */
Test(cli, scene_from_standard_input_and_no_fifos, .timeout = 60)
{
    char out[4096];
    put("lit.yaml", "image: {width: 6, height: 4}\n"
                    "lights: [{type: point, position: [0, 5, 0]}]\n"
                    "objects: [{type: sphere, center: [0, 0, -5], radius: 1}]\n");
    cr_expect_eq(run("-q -o in.ppm - < lit.yaml", out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "");
    cr_expect_eq(run_sh("cat lit.yaml | \"$GLINT\" -q -o in2.ppm -", out, sizeof out), 0, "%s",
                 out);
    cr_expect_eq(run_sh("echo 'objets: []' | \"$GLINT\" -q -", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: <stdin>:1:1: unknown key 'objets' at the top level (did you "
                          "mean 'objects'?)\n");
    cr_expect_eq(run_sh("mkfifo pipe.yaml && \"$GLINT\" -q pipe.yaml", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: pipe.yaml: cannot read scene: not a regular file\n");
    cr_expect_eq(run("-q /dev/zero", out, sizeof out), 2);
    cr_expect_str_eq(out, "glint: /dev/zero: cannot read scene: not a regular file\n");
}

/* A scene file of over 1 MB: the programs make the library's spare block
 * from its size (cli/heap.h), the parse tree is built in it and the film
 * then takes it. The same scene from standard input (no size known, a
 * film below the spare's 4 MiB: no spare) gives the same bytes. */
Test(cli, a_big_scene_file_renders_as_from_standard_input, .timeout = 120)
{
    char path[256];
    snprintf(path, sizeof path, "%s/big.yaml", tmpdir);
    FILE *f = fopen(path, "w");
    cr_assert_not_null(f);
    fputs("lights: [{type: point, position: [0, 30, 20]}]\n"
          "camera: {eye: [0, 12, 30], look_at: [0, 0, 0], fov: 60}\nobjects:\n", f);
    for (int i = 0; i < 14000; i++)
        fprintf(f, "  - {type: sphere, center: [%d.25, %d.5, %d.75], radius: 0.%d, "
                   "material: {color: [0.%d, 0.5, 0.%d], specular: 0.25}}\n",
                i % 40 - 20, i % 7, i / 40 % 35 - 30, 1 + i % 4, i % 9, 9 - i % 9);
    long size = ftell(f);
    fclose(f);
    cr_assert_gt(size, 1 << 20);
    char out[4096];
    cr_assert_eq(run("-q -t 2 -r 480x360 -o file.png big.yaml", out, sizeof out), 0, "%s", out);
    cr_assert_eq(run("-q -t 2 -r 480x360 -o stdin.png - < big.yaml", out, sizeof out), 0, "%s",
                 out);
    cr_assert_eq(run_sh("cmp file.png stdin.png", out, sizeof out), 0, "%s", out);
}

/* Memory running out inside the mesh importer said "std::bad_alloc" and
 * exited 2, as if the file were bad. A 200-byte PLY declaring two billion
 * vertices is now refused from its header before anything is allocated
 * (exit 2, naming the file), even under a 400 MB address space limit (not
 * with AddressSanitizer, which needs terabytes of it). */
Test(cli, two_billion_declared_vertices_are_refused_before_allocating)
{
#if defined(__SANITIZE_ADDRESS__)
    cr_skip_test("AddressSanitizer cannot run under an address space limit");
#else
    char out[4096];
    put("huge.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\n"
                    "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                    "property list uchar int vertex_indices\nend_header\n");
    put("huge.yaml", "objects: [{type: mesh, file: huge.ply}]\n");
    cr_expect_eq(run_sh("ulimit -v 400000 && \"$GLINT\" -q -r 8x8 huge.yaml", out, sizeof out),
                 2);
    cr_expect_str_eq(out, "glint: huge.yaml:1:30: huge.ply: mesh is too large (2000000000 "
                          "vertices, limit 100663296; GLINT_MESH_TRIANGLES raises it)\n");
#endif
}
