/* png_write: the PNG writer (codec.h). PNG: ISO/IEC 15948:2004 (chunks,
 * filters section 9, CRC annex D); zlib's wrapper: RFC 1950.
 *
 * Every row gets one fixed filter, Up, and the rows are compressed by
 * libdeflate at level 2: on rendered images about 5 times faster than
 * libpng's defaults (zlib level 6, adaptive filters) for files about 1.16
 * times their size. ISA-L's igzip is faster still, but on such smooth
 * images its files come out 1.34-1.5 times libpng's whatever the filter
 * (bench/README.md, row 5); on noisy strips, where matches are few and
 * short, it costs a third of libdeflate's time for streams 2% larger, and
 * it compresses those (PNG_NOISY_LEVEL).
 *
 * The work is spread over threads in strips of whole rows, cut by the
 * image's size alone (png_strip_rows), so the file is the same for any
 * number of threads. Threads take the strips in turn from a shared
 * counter; each turns its strip's film rows into samples, filters them
 * (the row above the strip's first is made again, for the filter, into a
 * row of the thread's own) and compresses them into a raw deflate stream
 * of their own. Every libdeflate stream but the last is then walked to
 * its final block, made non-final and brought to a byte boundary with an
 * empty stored block (deflate_join.h, as pigz does with zlib); an igzip
 * stream (a noisy strip) already ends so, by a full flush. The streams,
 * in order, make the one zlib stream of the IDAT chunks, with the Adler-32
 * of the whole combined from the strips'. A strip's stream refers to
 * nothing before it (a zlib full flush): a few hundred bytes more on a
 * 1080p image. Should a walk not find what it should, or igzip fail, the
 * rows, already filtered, are compressed again as one stream.
 *
 * ISA-L is opened at the first noisy strip (core/dynlib.h), not linked.
 * Where it cannot be opened, noisy strips are compressed by libdeflate
 * like the smooth ones: the file is still a valid PNG with the same
 * pixels, the same for any number of threads, but not the bytes written
 * where ISA-L is (no other deflate encoder makes igzip's); a finished
 * render is better written so than refused at its last step. */
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include <isa-l/igzip_lib.h>
#include <libdeflate.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "codec.h"
#include "core/cpus.h"
#include "core/dynlib.h"
#include "core/error.h"
#include "deflate_join.h"
#include "image.h"

#define ISAL_FUNCTIONS(X, t) X(t, isal_deflate_stateless_init) X(t, isal_deflate_stateless)

static DYNLIB_STRUCT(ISAL_FUNCTIONS) isal_fn;
static dynlib isal_lib = DYNLIB(GLINT_SONAME_ISAL, ISAL_FUNCTIONS, isal_fn);

#define isal_deflate_stateless_init (isal_fn.isal_deflate_stateless_init)
#define isal_deflate_stateless (isal_fn.isal_deflate_stateless)

/* Chunks hold at most 2^31 - 1 bytes; pixel data is split at 1 GiB. */
#define PNG_CHUNK_MAX (1u << 30)

/* The deflate level, 1 to 12 in libdeflate: on rendered images 2 is as
 * fast as 1 with files a few percent smaller; higher levels cost more
 * time than they save bytes. But on noisy strips (one sample per pixel,
 * fine detail: less than PNG_FAST_ZEROS of the filtered bytes are zero,
 * the rows above no longer foretelling the rows below) a longer search
 * for matches finds few and costs more: there ISA-L's igzip at its level
 * 2 takes a third of the time of libdeflate's fastest level for streams
 * 2% larger (bench row 8's tori: 10.6 ms against 30.1 for the whole
 * image on one thread, a file of 2,346,298 bytes against 2,303,366). Smooth strips
 * keep libdeflate (row 5's image is all smooth strips). The choice rests
 * on the strip's bytes alone, so the file is still the same for any
 * number of threads. */
#define PNG_DEFLATE_LEVEL 2
#define PNG_NOISY_LEVEL 2
#define PNG_NOISY_BUF ISAL_DEF_LVL2_DEFAULT
#define PNG_FAST_ZEROS 0.75

/* Raw bytes in a strip: enough that a fresh start costs little, few
 * enough that two threads finish close together. */
#define PNG_STRIP_BYTES ((size_t)1 << 19)
#define PNG_MAX_STRIPS 1024
#define PNG_MAX_THREADS 1024

static void put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* A chunk's CRC covers its type and data (annex D: the reflected CRC-32
 * of ISO 3309, the one gzip uses). */
static bool put_chunk(bytelist *out, const char type[4], const uint8_t *data, uint32_t n)
{
    uint8_t head[8], crc[4];
    put_be32(head, n);
    memcpy(head + 4, type, 4);
    uint32_t c = libdeflate_crc32(0, type, 4);
    put_be32(crc, n ? libdeflate_crc32(c, data, n) : c); /* (NULL would start it again) */
    return bytelist_own(out, head, 8) && bytelist_own(out, data, n) && bytelist_own(out, crc, 4);
}

/* The zlib stream into IDAT chunks of at most `max` bytes, piece by piece
 * as it comes (idat_put): each chunk's length and type before its first
 * byte, its CRC after its last. */
typedef struct idat_writer {
    bytelist *out;
    size_t max, left, in_chunk; /* the stream's bytes still to come, the chunk's */
    uint32_t crc;
} idat_writer;

/* n bytes of the stream at p, copied into out's own bytes or (copy
 * false) left where they are. */
static bool idat_put(idat_writer *w, const uint8_t *p, size_t n, bool copy)
{
    while (n > 0) {
        if (w->in_chunk == 0) {
            uint8_t head[8];
            if (w->left == 0) /* more bytes than the stream was said to hold */
                return false;
            w->in_chunk = w->left < w->max ? w->left : w->max;
            put_be32(head, (uint32_t)w->in_chunk);
            memcpy(head + 4, "IDAT", 4);
            if (!bytelist_own(w->out, head, 8))
                return false;
            w->crc = libdeflate_crc32(0, "IDAT", 4);
        }
        size_t take = n < w->in_chunk ? n : w->in_chunk;
        if (!(copy ? bytelist_own(w->out, p, take) : bytelist_ref(w->out, p, take)))
            return false;
        w->crc = libdeflate_crc32(w->crc, p, take);
        p += take, n -= take;
        w->in_chunk -= take, w->left -= take;
        if (w->in_chunk == 0) {
            uint8_t crc[4];
            put_be32(crc, w->crc);
            if (!bytelist_own(w->out, crc, 4))
                return false;
        }
    }
    return true;
}

/* ---- rows ------------------------------------------------------------------ */

/* Where the samples come from: a film, or packed pixels. */
typedef struct png_source {
    int width, height, channels, bits;
    const raster *film;  /* or NULL: */
    const void *pixels;  /* packed, 16-bit samples in native order */
} png_source;

/* 16-bit samples go big-endian. */
static void put_be16(uint8_t *dst, const uint16_t *src, size_t count)
{
    for (size_t i = 0; i < count; i++) {
        dst[2 * i] = (uint8_t)(src[i] >> 8);
        dst[2 * i + 1] = (uint8_t)src[i];
    }
}

/* One row of the film into PNG samples: RGB, or RGBA with the coverage as
 * alpha (linear: no transfer function); 16-bit ones big-endian, through
 * tmp (width x 4 samples). */
static void quantize_row(const raster *r, int y, uint8_t *dst, uint16_t *tmp)
{
    size_t w = (size_t)r->width, at = (size_t)y * w;
    const float *rgb = r->rgb + at * 3;
    if (!r->alpha) {
        if (r->bits == 8) {
            image_quantize(rgb, w * 3, r->transfer, dst);
            return;
        }
        image_quantize16(rgb, w * 3, r->transfer, tmp);
        put_be16(dst, tmp, w * 3);
        return;
    }
    if (r->bits == 16) {
        for (size_t x = 0; x < w; x++) {
            image_quantize16(rgb + x * 3, 3, r->transfer, tmp + x * 4);
            image_quantize16(r->alpha + at + x, 1, GLINT_TRANSFER_NONE, tmp + x * 4 + 3);
        }
        put_be16(dst, tmp, w * 4);
        return;
    }
    uint8_t px[4];
    for (size_t x = 0; x < w; x++) {
        image_quantize(rgb + x * 3, 3, r->transfer, px);
        image_quantize(r->alpha + at + x, 1, GLINT_TRANSFER_NONE, px + 3);
        memcpy(dst + x * 4, px, 4);
    }
}

static void fill_row(const png_source *s, int y, uint8_t *dst, uint16_t *tmp)
{
    if (s->film) {
        quantize_row(s->film, y, dst, tmp);
        return;
    }
    size_t samples = (size_t)s->width * (size_t)s->channels;
    if (s->bits == 16)
        put_be16(dst, (const uint16_t *)s->pixels + (size_t)y * samples, samples);
    else
        memcpy(dst, (const uint8_t *)s->pixels + (size_t)y * samples, samples);
}

/* Up filter (section 9.2, type 2) of row against the row above it, in
 * place: each byte minus the one above. It compresses flat and vertically
 * smooth areas to almost nothing. Returns how many filtered bytes are
 * zero, which tells smooth rows from noisy ones. */
static size_t filter_up(uint8_t *row, const uint8_t *above, size_t n)
{
    row[-1] = 2;
    size_t i = 0, zeros = 0;
#if defined(__SSE2__)
    const __m128i zero = _mm_setzero_si128(), one = _mm_set1_epi8(1);
    __m128i count = zero; /* zero bytes: two sums, one per half */
    for (; i + 16 <= n; i += 16) {
        __m128i a = _mm_loadu_si128((const __m128i *)(const void *)(row + i));
        __m128i b = _mm_loadu_si128((const __m128i *)(const void *)(above + i));
        __m128i d = _mm_sub_epi8(a, b);
        _mm_storeu_si128((__m128i *)(void *)(row + i), d);
        __m128i is_zero = _mm_and_si128(_mm_cmpeq_epi8(d, zero), one);
        count = _mm_add_epi64(count, _mm_sad_epu8(is_zero, zero));
    }
    uint64_t sums[2];
    _mm_storeu_si128((__m128i *)(void *)sums, count);
    zeros = (size_t)(sums[0] + sums[1]);
#endif
    for (; i < n; i++) {
        row[i] = (uint8_t)(row[i] - above[i]);
        zeros += row[i] == 0;
    }
    return zeros;
}

/* ---- strips ---------------------------------------------------------------- */

typedef struct strip {
    int y0, y1;
    uint8_t *z;  /* its raw deflate stream; made non-final unless the last */
    size_t zlen;
    uint32_t adler; /* of its filtered rows */
    bool joined;    /* ready to be followed by the next strip's stream */
} strip;

/* The strips of an image, and where the threads are in them. */
typedef struct png_job {
    const png_source *src;
    size_t stride; /* 1 + bytes of a row */
    strip *strips;
    int nstrips, strip_rows;
    atomic_int next;  /* the next strip to take */
    atomic_int nomem; /* a thread could not get its memory */
} png_job;

/* A thread's own memory: its compressor, igzip's working memory for noisy
 * strips once it meets one, a strip's rows as PNG wants them before
 * compression (each row a filter-type byte, then its samples), made again
 * for each strip it takes (so they stay in the cache), two more rows, and
 * room for a strip's stream at its longest, which it is compressed into
 * and joined in before it is copied out at its length: a block that long
 * for each strip had its few written pages spread over 6 MB for a 1080p
 * image, each a page fault, or a fresh huge page to clear. */
typedef struct strip_tools {
    struct libdeflate_compressor *c;
    uint8_t *noisy;
    uint8_t *rows, *above;
    uint16_t *tmp;
    uint8_t *z;
    size_t zcap;
} strip_tools;

/* The longest stream igzip may make of n bytes: stored blocks, the
 * worst, add 5 bytes in 65535. */
static size_t noisy_bound(size_t n) { return n + n / 8 + 1024; }

static bool tools_get(strip_tools *t, const png_job *j, int rows)
{
    size_t n = j->stride * (size_t)rows;
    *t = (strip_tools){.c = libdeflate_alloc_compressor(PNG_DEFLATE_LEVEL),
                       .rows = malloc(n),
                       .above = malloc(j->stride),
                       .tmp = malloc((size_t)j->src->width * 4 * sizeof *t->tmp)};
    if (!t->c)
        return false;
    size_t bound = libdeflate_zlib_compress_bound(t->c, n); /* (compress_whole's zlib stream) */
    t->zcap = (bound > noisy_bound(n) ? bound : noisy_bound(n)) + DEFLATE_UNFINAL_EXTRA;
    t->z = malloc(t->zcap);
    return t->rows && t->above && t->tmp && t->z;
}

static void tools_free(strip_tools *t)
{
    libdeflate_free_compressor(t->c);
    free(t->noisy);
    free(t->rows);
    free(t->above);
    free(t->tmp);
    free(t->z);
}

/* The strip's stream, t->z's first s->zlen bytes, copied out to s->z at
 * its length; false when memory runs out. */
static bool strip_keep(strip *s, const strip_tools *t)
{
    s->z = malloc(s->zlen ? s->zlen : 1);
    if (s->z && s->zlen)
        memcpy(s->z, t->z, s->zlen);
    return s->z != NULL;
}

/* The strip's rows into samples in t->rows, filtered: row 0 of the image
 * unfiltered (type 0), every other row Up against the row above, from the
 * last up so that the rows above are still unfiltered. Returns how many
 * of the filtered samples are zero. */
static size_t strip_rows(const png_job *j, const strip *s, strip_tools *t)
{
    size_t n = j->stride - 1, zeros = 0;
    for (int y = s->y0; y < s->y1; y++)
        fill_row(j->src, y, t->rows + (size_t)(y - s->y0) * j->stride + 1, t->tmp);
    for (int y = s->y1 - 1; y > s->y0; y--) {
        uint8_t *row = t->rows + (size_t)(y - s->y0) * j->stride + 1;
        zeros += filter_up(row, row - j->stride, n);
    }
    if (s->y0 == 0) {
        t->rows[0] = 0;
        return zeros;
    }
    fill_row(j->src, s->y0 - 1, t->above, t->tmp);
    return zeros + filter_up(t->rows + 1, t->above, n);
}

/* A noisy strip's n filtered bytes by igzip (PNG_NOISY_LEVEL): ended by a
 * full flush, on a byte boundary and not final, so that the next strip's
 * stream follows it as it is; the image's last strip final. Not joined
 * should igzip fail, which leaves the whole image to compress_whole. */
static bool strip_compress_noisy(strip *s, strip_tools *t, size_t n, bool last)
{
    if (!t->noisy && !(t->noisy = malloc(PNG_NOISY_BUF)))
        return false;
    /* (the init leaves some fields, hist_bits among them, as they were:
     * zeroed first, the window is the default 32 KiB and the stream
     * depends on the strip alone) */
    struct isal_zstream zs = {0};
    isal_deflate_stateless_init(&zs);
    zs.level = PNG_NOISY_LEVEL;
    zs.level_buf = t->noisy;
    zs.level_buf_size = PNG_NOISY_BUF;
    zs.next_in = t->rows;
    zs.avail_in = (uint32_t)n;
    zs.next_out = t->z;
    zs.avail_out = (uint32_t)noisy_bound(n);
    zs.end_of_stream = last;
    zs.flush = last ? NO_FLUSH : FULL_FLUSH;
    s->joined = n <= UINT32_MAX / 2 && isal_deflate_stateless(&zs) == COMP_OK;
    s->zlen = s->joined ? zs.total_out : 0;
    return strip_keep(s, t);
}

/* Compresses the strip's filtered rows, `zeros` of them zero; false
 * when memory runs out. */
static bool strip_compress(png_job *j, strip *s, strip_tools *t, size_t zeros)
{
    size_t n = (size_t)(s->y1 - s->y0) * j->stride;
    s->adler = libdeflate_adler32(1, t->rows, n);
    bool last = s == &j->strips[j->nstrips - 1];
    if ((double)zeros < PNG_FAST_ZEROS * (double)n && dynlib_open(&isal_lib, NULL))
        return strip_compress_noisy(s, t, n, last);
    s->zlen = libdeflate_deflate_compress(t->c, t->rows, n, t->z, t->zcap - DEFLATE_UNFINAL_EXTRA);
    if (last) {
        s->joined = s->zlen > 0;
        return strip_keep(s, t);
    }
    deflate_ends ends;
    s->joined = s->zlen > 0 && deflate_walk(t->z, s->zlen, n, &ends);
    if (s->joined)
        deflate_unfinal(t->z, &s->zlen, &ends);
    return strip_keep(s, t);
}

static void *strip_worker(void *arg)
{
    png_job *j = arg;
    strip_tools t = {0};
    bool ok = true, have = false;
    for (;;) {
        int i = atomic_fetch_add(&j->next, 1);
        if (i >= j->nstrips || atomic_load(&j->nomem))
            break;
        if (!have)
            ok = have = tools_get(&t, j, j->strip_rows);
        if (ok) {
            size_t zeros = strip_rows(j, &j->strips[i], &t);
            ok = strip_compress(j, &j->strips[i], &t, zeros);
        }
        if (!ok)
            atomic_store(&j->nomem, 1);
    }
    tools_free(&t);
    return NULL;
}

int png_strip_rows(int width, int height, int channels, int bits)
{
    size_t stride = 1 + (size_t)width * (size_t)channels * (size_t)(bits / 8);
    size_t per = PNG_STRIP_BYTES / stride;
    int rows = per < 1 ? 1 : per > (size_t)height ? height : (int)per;
    int min_rows = (height + PNG_MAX_STRIPS - 1) / PNG_MAX_STRIPS;
    return rows < min_rows ? min_rows : rows;
}

/* Runs strip_worker on up to `threads` threads, the calling one included;
 * threads that cannot be started leave their share to the others. */
static void run_strips(png_job *j, int threads)
{
    threads = cpus_threads(threads, PNG_MAX_THREADS);
    if (threads > j->nstrips)
        threads = j->nstrips;
    cpus_share(threads, strip_worker, j);
}

/* ---- the file ------------------------------------------------------------------ */

/* The strips' streams as one zlib stream into IDAT chunks: header, the
 * streams where their threads left them (out then holds their blocks),
 * the Adler-32 of the whole. */
static bool join_strips(png_job *j, idat_writer *w)
{
    /* CMF: deflate, 32 KiB window; FLG: level "fast" (as libdeflate marks
     * level 2), check bits making CMF * 256 + FLG a multiple of 31 */
    static const uint8_t header[2] = {0x78, 0x5e};
    w->left = 2 + 4;
    for (int i = 0; i < j->nstrips; i++)
        w->left += j->strips[i].zlen;
    if (!idat_put(w, header, 2, true))
        return false;
    uint32_t adler = 1;
    for (int i = 0; i < j->nstrips; i++) {
        strip *s = &j->strips[i];
        uint8_t *z = s->z;
        s->z = NULL;
        if (!bytelist_hold(w->out, z) || !idat_put(w, z, s->zlen, false))
            return false;
        size_t n = (size_t)(s->y1 - s->y0) * j->stride;
        adler = i == 0 ? s->adler : deflate_adler32_combine(adler, s->adler, n);
    }
    uint8_t end[4];
    put_be32(end, adler);
    return idat_put(w, end, 4, true);
}

/* The whole image as one strip and one zlib stream into IDAT chunks:
 * what is left when a strip's stream cannot be joined to the next
 * (deflate_walk found what it did not expect). */
static bool compress_whole(const png_job *j, idat_writer *w)
{
    strip_tools t;
    strip s = {.y0 = 0, .y1 = j->src->height};
    size_t n = j->stride * (size_t)j->src->height, z = 0;
    uint8_t *block = NULL;
    if (tools_get(&t, j, j->src->height)) {
        strip_rows(j, &s, &t);
        z = libdeflate_zlib_compress(t.c, t.rows, n, t.z, t.zcap);
        block = t.z;
        t.z = NULL;
    }
    tools_free(&t);
    if (z == 0) {
        free(block);
        return false;
    }
    w->left = z;
    return bytelist_hold(w->out, block) && idat_put(w, block, z, false);
}

/* The rows, filtered and compressed, as one zlib stream in IDAT chunks. */
static bool compress_rows(const png_source *src, int threads, idat_writer *w)
{
    png_job j = {.src = src};
    j.stride = 1 + (size_t)src->width * (size_t)src->channels * (size_t)(src->bits / 8);
    j.strip_rows = png_strip_rows(src->width, src->height, src->channels, src->bits);
    j.nstrips = (src->height + j.strip_rows - 1) / j.strip_rows;
    j.strips = calloc((size_t)j.nstrips, sizeof *j.strips);
    bool ok = j.strips != NULL;
    if (ok) {
        for (int i = 0; i < j.nstrips; i++) {
            j.strips[i].y0 = i * j.strip_rows;
            j.strips[i].y1 = i + 1 < j.nstrips ? (i + 1) * j.strip_rows : src->height;
        }
        atomic_init(&j.next, 0);
        atomic_init(&j.nomem, 0);
        run_strips(&j, threads);
        ok = !atomic_load(&j.nomem);
    }
    bool joined = ok;
    for (int i = 0; ok && i < j.nstrips; i++)
        joined = joined && j.strips[i].joined;
    if (ok)
        ok = joined ? join_strips(&j, w) : compress_whole(&j, w);
    for (int i = 0; j.strips && i < j.nstrips; i++)
        free(j.strips[i].z);
    free(j.strips);
    return ok;
}

/* Signature, IHDR, the rows as IDAT chunks of at most chunk_max bytes,
 * IEND. */
static glint_rc encode(const png_source *src, int threads, size_t chunk_max, bytelist *out,
                       glint_error *err)
{
    static const uint8_t color_type[5] = {0, 0, 4, 2, 6}; /* grey, grey+alpha, RGB, RGBA */
    uint8_t ihdr[13];
    put_be32(ihdr, (uint32_t)src->width);
    put_be32(ihdr + 4, (uint32_t)src->height);
    ihdr[8] = (uint8_t)src->bits;
    ihdr[9] = color_type[src->channels];
    ihdr[10] = ihdr[11] = ihdr[12] = 0; /* deflate, adaptive filtering, no interlace */
    idat_writer w = {.out = out, .max = chunk_max};
    bool ok = bytelist_own(out, "\x89PNG\r\n\x1a\n", 8) && put_chunk(out, "IHDR", ihdr, 13) &&
              compress_rows(src, threads, &w) && w.left == 0 && w.in_chunk == 0 &&
              put_chunk(out, "IEND", NULL, 0);
    return ok ? GLINT_OK : err_nomem(err);
}

static glint_rc check_pixels(int width, int height, int channels, int bits, glint_error *err)
{
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || (bits != 8 && bits != 16))
        return err_set(err, GLINT_ERR_INPUT, "PNG: cannot write %dx%d, %d channels, %d bits",
                       width, height, channels, bits);
    return GLINT_OK;
}

glint_rc png_encode_chunked(int width, int height, int channels, int bits, const void *pixels,
                            int threads, size_t chunk_max, bytelist *out, glint_error *err)
{
    glint_rc rc = check_pixels(width, height, channels, bits, err);
    if (rc != GLINT_OK)
        return rc;
    if (chunk_max < 1 || chunk_max > PNG_CHUNK_MAX)
        return err_set(err, GLINT_ERR_INPUT, "PNG: IDAT chunks of 1 to %u bytes", PNG_CHUNK_MAX);
    png_source src = {width, height, channels, bits, NULL, pixels};
    return encode(&src, threads, chunk_max, out, err);
}

glint_rc png_encode_pixels(int width, int height, int channels, int bits, const void *pixels,
                           int threads, bytebuf *out, glint_error *err)
{
    bytelist l = {0};
    glint_rc rc =
        png_encode_chunked(width, height, channels, bits, pixels, threads, PNG_CHUNK_MAX, &l, err);
    if (rc == GLINT_OK && !bytelist_flatten(&l, out))
        rc = err_nomem(err);
    bytelist_free(&l);
    return rc;
}

glint_rc png_encode(const raster *r, bytelist *out, glint_error *err)
{
    png_source src = {r->width, r->height, r->alpha ? 4 : 3, r->bits, r, NULL};
    return encode(&src, r->threads, PNG_CHUNK_MAX, out, err);
}
