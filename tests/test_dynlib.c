/* Libraries opened at their first use (src/core/dynlib.h): a table filled
 * from a real library, the words when the library or a function is
 * missing, the first use from many threads at once. Then the programs as
 * built: glint and glint-mpi map none of the libraries they open at run
 * time when they start; JPEG and OpenEXR files they write read back as
 * textures; a library that cannot be used is an error naming the file and
 * the library, except ISA-L, whose noisy PNG strips libdeflate then
 * compresses (other bytes, the same pixels). */
#define _GNU_SOURCE /* dladdr */
#include <criterion/criterion.h>
#include <dlfcn.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dynlib.h"
#include "core/rng.h"
#include "io/image.h"
#include "tmpdir.h"
#include "glint_run.h"

/* ---- the mechanism, on libm -------------------------------------------------- */

#define M_FUNCTIONS(X, t) X(t, cos) X(t, ldexp)

static DYNLIB_STRUCT(M_FUNCTIONS) m_fn, missing_fn, shared_fn;
static dynlib m_lib = DYNLIB("libm.so.6", M_FUNCTIONS, m_fn);
static dynlib missing_lib = DYNLIB("libglint-no-such-library.so.7", M_FUNCTIONS, missing_fn);
static dynlib shared_lib = DYNLIB("libm.so.6", M_FUNCTIONS, shared_fn);

Test(dynlib, fills_the_table_once_and_calls_go_through_it)
{
    const char *why = "untouched";
    cr_assert(dynlib_open(&m_lib, &why));
    cr_expect_str_eq(why, "untouched", "why is left alone on success");
    cr_expect_eq(m_fn.cos(0.5), cos(0.5));
    cr_expect_eq(m_fn.ldexp(3.0, 4), 48.0);
    double (*first)(double) = m_fn.cos;
    cr_assert(dynlib_open(&m_lib, NULL));
    cr_expect_eq(m_fn.cos, first);
}

Test(dynlib, a_missing_library_is_said_by_its_name_and_stays_missing)
{
    const char *why = NULL;
    cr_assert_not(dynlib_open(&missing_lib, &why));
    cr_assert_not_null(why);
    cr_expect(strstr(why, "libglint-no-such-library.so.7"), "%s", why);
    cr_expect(strstr(why, "cannot open"), "%s", why);
    const char *again = NULL;
    cr_expect_not(dynlib_open(&missing_lib, &again));
    cr_expect_str_eq(again, why);
    cr_expect_null(missing_fn.cos);
}

Test(dynlib, a_missing_function_is_said_by_its_name)
{
    static struct {
        double (*cos)(double);
        void (*none)(void);
    } t;
    const dynlib_symbol symbols[] = {
        {"cos", &t.cos}, {"glint_no_such_function", &t.none}, {NULL, NULL}};
    dynlib lib = {.soname = "libm.so.6", .symbols = symbols};
    const char *why = NULL;
    cr_assert_not(dynlib_open(&lib, &why));
    cr_expect(strstr(why, "glint_no_such_function"), "%s", why);
    cr_expect(strstr(why, "libm.so.6"), "%s", why);
}

static void *open_and_call(void *arg)
{
    double *got = arg;
    *got = dynlib_open(&shared_lib, NULL) ? shared_fn.cos(1.0) : -2.0;
    return NULL;
}

/* Texture decoding runs a thread per file and the PNG writer a thread per
 * strip: their first uses can come at once. */
Test(dynlib, a_first_use_from_many_threads_at_once)
{
    enum { N = 16 };
    pthread_t th[N];
    double got[N];
    for (int i = 0; i < N; i++)
        cr_assert_eq(pthread_create(&th[i], NULL, open_and_call, &got[i]), 0);
    for (int i = 0; i < N; i++) {
        pthread_join(th[i], NULL);
        cr_expect_eq(got[i], cos(1.0), "thread %d", i);
    }
}

/* ---- the programs ------------------------------------------------------------ */

static const char *const lazy[] = {GLINT_SONAME_JPEG, GLINT_SONAME_EXR,  GLINT_SONAME_STB,
                                   GLINT_SONAME_SPNG, GLINT_SONAME_ISAL, GLINT_SONAME_ASSIMP,
                                   "libSDL2"};

static void expect_not_mapped_at_start(const char *bin)
{
    char cmd[1024], out[8192];
    snprintf(cmd, sizeof cmd, "ldd '%s%s%s' 2>&1", bin[0] == '/' ? "" : GLINT_SOURCE_DIR,
             bin[0] == '/' ? "" : "/", bin);
    FILE *p = popen(cmd, "r");
    cr_assert_not_null(p);
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = '\0';
    cr_assert_eq(pclose(p), 0, "%s: %s", cmd, out);
    cr_assert(strstr(out, "libdeflate"), "%s", out);
    for (size_t i = 0; i < sizeof lazy / sizeof *lazy; i++)
        cr_expect_null(strstr(out, lazy[i]), "%s is linked to %s:\n%s", bin, lazy[i], out);
}

/* The dynamic loader maps what a program is linked to before main, and
 * these only a few runs use. */
Test(programs, map_no_library_they_open_when_needed_at_start)
{
    const char *bin = getenv("GLINT_BIN"), *mpi = getenv("GLINT_MPI_BIN");
    cr_assert_not_null(bin, "GLINT_BIN must name the glint binary");
    expect_not_mapped_at_start(bin);
    if (mpi && mpi[0])
        expect_not_mapped_at_start(mpi);
}

static void make_dir(void) { tmpdir_make("dynlib"); }

static void remove_dir(void) { tmpdir_remove(); }

TestSuite(libs, .init = make_dir, .fini = remove_dir);

/* A scene of one quad showing the texture in file, filling the image. */
static void put_scene(const char *name, const char *file)
{
    char text[1024];
    snprintf(text, sizeof text,
             "image: {width: 64, height: 64, samples: 1}\n"
             "camera: {projection: orthographic, width: 2, eye: [0, 0, 5], look_at: [0, 0, 0]}\n"
             "ambient: 1\n"
             "lights: [{type: point, position: [0, 0, 9], color: 0}]\n"
             "textures: {t: {type: image, file: %s}}\n"
             "objects: [{type: quad, origin: [-1, -1, 0], edge_u: [2, 0, 0], edge_v: [0, 2, 0],\n"
             "           material: {texture: t, diffuse: 0, specular: 0}}]\n",
             file);
    dir_put(name, text);
}

/* t.jpg and t.exr, written by glint, and jpg.yaml and exr.yaml showing them. */
static void put_jpeg_and_exr(void)
{
    char out[4096];
    cr_assert_eq(glint_run("", "-q -r 48x32 -o t.jpg", out, sizeof out), 0, "%s", out);
    cr_assert_eq(glint_run("", "-q -r 48x32 -o t.exr", out, sizeof out), 0, "%s", out);
    put_scene("jpg.yaml", "t.jpg");
    put_scene("exr.yaml", "t.exr");
}

Test(libs, jpeg_and_openexr_written_and_read_back_as_textures)
{
    char out[4096];
    put_jpeg_and_exr();
    cr_expect_eq(glint_run("", "-q jpg.yaml -o jpg.png", out, sizeof out), 0, "%s", out);
    cr_expect_eq(glint_run("", "-q exr.yaml -o exr.png", out, sizeof out), 0, "%s", out);
    cr_expect(dir_has("jpg.png") && dir_has("exr.png"));
}

/* A folder whose files stand in for the libraries named: copies of
 * libdeflate, which has none of their functions. */
static void fake_libraries(const char *const *sonames, int n)
{
    void *h = dlopen("libdeflate.so.0", RTLD_NOW | RTLD_NOLOAD);
    Dl_info info;
    cr_assert(h && dladdr(dlsym(h, "libdeflate_crc32"), &info) && info.dli_fname);
    char cmd[2048];
    for (int i = 0; i < n; i++) {
        snprintf(cmd, sizeof cmd, "mkdir -p '%s/fake' && cp '%s' '%s/fake/%s'", dir,
                 info.dli_fname, dir, sonames[i]);
        cr_assert_eq(system(cmd), 0, "%s", cmd);
    }
    dlclose(h);
}

#define FAKE "LD_LIBRARY_PATH=\"$PWD/fake\""

static void expect_said(const char *out, const char *start, const char *soname, const char *fn)
{
    char want[512];
    snprintf(want, sizeof want, "glint: %s", start);
    cr_expect(strstr(out, want), "wanted '%s' in: %s", want, out);
    snprintf(want, sizeof want, "/fake/%s: undefined symbol: %s)\n", soname, fn);
    cr_expect(strstr(out, want), "wanted '%s' in: %s", want, out);
}

Test(libs, a_library_that_cannot_be_used_is_said_naming_the_file_and_the_library)
{
    char out[4096];
    put_jpeg_and_exr();
    static const char *const fakes[] = {GLINT_SONAME_JPEG, GLINT_SONAME_EXR};
    fake_libraries(fakes, 2);
    /* reading: bad input, as any unreadable texture */
    cr_expect_eq(glint_run(FAKE, "-q jpg.yaml -o j.png", out, sizeof out), 2);
    expect_said(out, "jpg.yaml:5:35: t.jpg: cannot read JPEG files (", GLINT_SONAME_JPEG,
                "jpeg_std_error");
    cr_expect_eq(glint_run(FAKE, "-q exr.yaml -o e.png", out, sizeof out), 2);
    expect_said(out, "exr.yaml:5:35: t.exr: cannot read OpenEXR files (", GLINT_SONAME_EXR,
                "exr_get_user_data");
    /* writing: a failed write, said before the render (no progress line),
     * and no file */
    cr_expect_eq(glint_run(FAKE, "--progress -r 8x8 -o w.jpg", out, sizeof out), 1);
    expect_said(out, "w.jpg: cannot write JPEG files (", GLINT_SONAME_JPEG, "jpeg_std_error");
    cr_expect(!strstr(out, "%"), "a render was made: %s", out);
    cr_expect_eq(glint_run(FAKE, "--progress -r 8x8 -o w.exr", out, sizeof out), 1);
    expect_said(out, "w.exr: cannot write OpenEXR files (", GLINT_SONAME_EXR,
                "exr_get_user_data");
    cr_expect(!strstr(out, "%"), "a render was made: %s", out);
    cr_expect_not(dir_has("w.jpg") || dir_has("w.exr") || dir_has("j.png") || dir_has("e.png"));
}

/* A 64x64 binary PPM of random levels, eight of them 16 apart: its render
 * is a noisy strip (few of its filtered bytes are zero), compressible
 * (random bytes would be stored as they are, by either library alike). */
static void put_noise(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    cr_assert_not_null(f);
    fprintf(f, "P6\n64 64\n255\n");
    rng s = rng_seed(7, 1);
    for (int i = 0; i < 64 * 64 * 3; i++)
        fputc(64 + 16 * (int)(rng_u32(&s) & 7), f);
    fclose(f);
}

static image load(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    image img;
    glint_error err;
    cr_assert_eq(image_load(path, &img, &err), GLINT_OK, "%s", err.msg);
    return img;
}

Test(libs, without_isa_l_noisy_png_strips_are_compressed_by_libdeflate)
{
    char out[4096];
    put_noise("noise.ppm");
    put_scene("noise.yaml", "noise.ppm");
    static const char *const fakes[] = {GLINT_SONAME_ISAL};
    fake_libraries(fakes, 1);
    cr_assert_eq(glint_run("", "-q noise.yaml -o isal.png", out, sizeof out), 0, "%s", out);
    cr_assert_eq(glint_run(FAKE, "-q noise.yaml -o plain.png", out, sizeof out), 0, "%s", out);
    cr_expect_str_eq(out, "", "nothing said");
    cr_expect_not(dir_same("isal.png", "plain.png"), "the strips went to ISA-L both times");
    image a = load("isal.png"), b = load("plain.png");
    cr_assert(a.rgb && b.rgb && a.width == 64 && b.width == 64 && a.height == 64);
    cr_expect_eq(memcmp(a.rgb, b.rgb, 64 * 64 * 3), 0, "the same pixels");
    image_free(&a);
    image_free(&b);
}
