/* output: PNG writing speed and size (bench/README.md, row 5). The image is
 * row 1's: the built-in scene at 1920x1080 with 2x2 samples, rendered once.
 * glint's encoder (src/io/png_write.c: float film to 8-bit, Up filter, libdeflate
 * level 2, in strips) against libpng with its default settings (adaptive
 * filters, zlib level 6) on the same 8-bit pixels, both into memory on one
 * thread, alternating, median of --runs; then glint's writer on two
 * threads. glint's time includes turning the float film into bytes;
 * libpng's does not. glint's file is left in pieces (its header, its
 * strips where their threads compressed them: io/codec.h's bytelist), as
 * it goes to the file; libpng's is appended to one block. Throughput is
 * counted in raw pixel bytes (width x height x 3). Prints three table
 * rows. */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "glint.h"
#include "io/codec.h"
#include "io/image.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static void sink(png_structp p, png_bytep data, png_size_t n)
{
    bytebuf *b = png_get_io_ptr(p);
    if (!bytes_append(b, data, n))
        png_error(p, "out of memory");
}

static void flush_nothing(png_structp p) { (void)p; }

/* libpng, default settings, into out; false on failure. */
static bool libpng_encode(int w, int h, const uint8_t *px, bytebuf *out)
{
    png_structp p = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = p ? png_create_info_struct(p) : NULL;
    png_bytep *rows = malloc(sizeof *rows * (size_t)h);
    if (!p || !info || !rows || setjmp(png_jmpbuf(p))) {
        png_destroy_write_struct(&p, &info);
        free(rows);
        return false;
    }
    png_set_write_fn(p, out, sink, flush_nothing);
    png_set_IHDR(p, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    for (int y = 0; y < h; y++)
        rows[y] = (png_bytep)px + (size_t)y * (size_t)w * 3;
    png_set_rows(p, info, rows);
    png_write_png(p, info, PNG_TRANSFORM_IDENTITY, NULL);
    png_destroy_write_struct(&p, &info);
    free(rows);
    return true;
}

int main(int argc, char **argv)
{
    int runs = argc > 1 ? atoi(argv[1]) : 5;
    int w = 1920, h = 1080;
    runs = runs > 0 ? runs : 5;
    glint_error err = {0};
    glint_scene *s = NULL;
    glint_film film = {0};
    glint_settings st;
    if (glint_scene_builtin(&s, &err) != GLINT_OK)
        goto fail;
    glint_scene_settings(s, &st, NULL);
    st.width = w;
    st.height = h;
    st.samples = 4;
    st.threads = 0;
    if (glint_render(s, &st, NULL, &film, NULL, &err) != GLINT_OK)
        goto fail;
    size_t raw = (size_t)w * (size_t)h * 3;
    uint8_t *px = malloc(raw);
    double *tg = malloc(sizeof *tg * (size_t)runs), *tp = malloc(sizeof *tp * (size_t)runs);
    if (!px || !tg || !tp)
        return 1;
    image_quantize(film.rgb, (size_t)w * (size_t)h * 3, GLINT_TRANSFER_NONE, px);
    raster r = {w, h, film.rgb, NULL, GLINT_TRANSFER_NONE, 8, 90, 1, "bench"};
    size_t gsize = 0, psize = 0;
    for (int i = 0; i < 2 * runs; i++) {
        bytebuf b = {0};
        bytelist l = {0}; /* glint's file: in pieces, as it goes to the file (codec.h) */
        bool glint_turn = (i % 2) == ((i / 2) % 2); /* alternate, swapping who goes first */
        double t0 = now();
        bool ok = glint_turn ? png_encode(&r, &l, &err) == GLINT_OK : libpng_encode(w, h, px, &b);
        double t = now() - t0;
        if (!ok)
            goto fail;
        if (glint_turn) {
            tg[i / 2] = t;
            gsize = bytelist_len(&l);
        } else {
            tp[i / 2] = t;
            psize = b.len;
        }
        bytes_free(&b);
        bytelist_free(&l);
    }
    /* the same writer on two threads: its strips compressed side by side
     * (the file is the same bytes) */
    double *t2 = malloc(sizeof *t2 * (size_t)runs);
    if (!t2)
        return 1;
    raster r2 = r;
    r2.threads = 2;
    for (int i = 0; i < runs; i++) {
        bytelist l = {0};
        double t0 = now();
        bool ok = png_encode(&r2, &l, &err) == GLINT_OK;
        t2[i] = now() - t0;
        if (!ok || bytelist_len(&l) != gsize)
            goto fail;
        bytelist_free(&l);
    }
    double g = (double)raw / median(tg, runs) * 1e-6, p = (double)raw / median(tp, runs) * 1e-6;
    double g2 = (double)raw / median(t2, runs) * 1e-6;
    printf("| 5 | PNG %dx%d RGB 8-bit (row 1's image), 1 thread, into memory: MB/s of raw pixels "
           "(peer: libpng defaults) | %.0f | %.0f | %.2f (%s) | glint ÷ 250 MB/s ≥ 1 |\n",
           w, h, g, p, g / 250.0, g >= 250.0 ? "met" : "missed");
    printf("| 5 | PNG file size, bytes (peer: libpng defaults) | %zu | %zu | %.2f (%s) | "
           "glint ÷ libpng ≤ 1.3 |\n", gsize, psize, (double)gsize / (double)psize,
           (double)gsize <= 1.3 * (double)psize ? "met" : "missed");
    printf("| 5 | the same, glint on 2 threads (its strips side by side; the same file): MB/s "
           "(peer: libpng, 1 thread) | %.0f | %.0f | %.2f (%s) | glint ÷ 250 MB/s ≥ 1 |\n",
           g2, p, g2 / 250.0, g2 >= 250.0 ? "met" : "missed");
    fprintf(stderr, "output: glint %.1f ms (2 threads %.1f ms), libpng %.1f ms for %dx%d\n",
            median(tg, runs) * 1e3, median(t2, runs) * 1e3, median(tp, runs) * 1e3, w, h);
    free(t2);
    free(px);
    free(tg);
    free(tp);
    glint_film_free(&film);
    glint_scene_free(s);
    return 0;
fail:
    fprintf(stderr, "output: %s\n", err.msg[0] ? err.msg : "libpng failed");
    return 1;
}
