/* deflate_walk (src/io/deflate_join.c) against a plain reference walker
 * written here from RFC 1951 alone: one bit at a time, codes decoded bit
 * by bit, the count checked after every symbol. The two must agree on
 * every stream, accepted or not, and on where an accepted one's final
 * block is: libdeflate's streams of every level and of data that makes
 * codes of every length; the same cut short, lengthened, expected to
 * hold a byte more or less, and with bits flipped; random bytes; and
 * copies reaching exactly to the stream's start or one byte before it,
 * near and at the longest distance. */
#include <criterion/criterion.h>
#include <stdlib.h>
#include <string.h>

#include <libdeflate.h>

#include "core/rng.h"
#include "io/deflate_join.h"

/* ---- the reference -------------------------------------------------------- */

typedef struct ref {
    const uint8_t *z;
    size_t n, pos, out, expect; /* pos in bits; bits past the end read as 0 */
} ref;

static unsigned ref_bits(ref *r, unsigned k)
{
    unsigned v = 0;
    for (unsigned i = 0; i < k; i++, r->pos++)
        if (r->pos < r->n * 8)
            v |= (unsigned)(r->z[r->pos / 8] >> (r->pos % 8) & 1) << i;
    return v;
}

typedef struct ref_code {
    int count[16], symbol[288];
} ref_code;

/* False for an over-subscribed code; incomplete ones are kept. */
static bool ref_build(ref_code *h, const int *len, int nsym)
{
    memset(h->count, 0, sizeof h->count);
    for (int s = 0; s < nsym; s++)
        h->count[len[s]]++;
    int left = 1, offs[16] = {0};
    for (int l = 1; l < 16; l++) {
        left = left * 2 - h->count[l];
        if (left < 0)
            return false;
        if (l < 15)
            offs[l + 1] = offs[l] + h->count[l];
    }
    for (int s = 0; s < nsym; s++)
        if (len[s])
            h->symbol[offs[len[s]]++] = s;
    return true;
}

/* The next symbol, or -1 for bits that are no code. */
static int ref_decode(ref *r, const ref_code *h)
{
    int code = 0, first = 0, index = 0;
    for (int l = 1; l < 16; l++) {
        code |= (int)ref_bits(r, 1);
        if (code - h->count[l] < first)
            return h->symbol[index + code - first];
        index += h->count[l];
        first = (first + h->count[l]) << 1;
        code <<= 1;
    }
    return -1;
}

static const int len_base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                 31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const int len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                  2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};

static bool ref_codes(ref *r, const ref_code *lit, const ref_code *dist)
{
    for (;;) {
        if (r->pos > r->n * 8)
            return false;
        int s = ref_decode(r, lit);
        if (s < 0 || s > 285)
            return false;
        if (s == 256)
            return true;
        if (s < 256) {
            if (++r->out > r->expect)
                return false;
            continue;
        }
        size_t len = (size_t)len_base[s - 257] + ref_bits(r, (unsigned)len_extra[s - 257]);
        int d = ref_decode(r, dist);
        if (d < 0 || d > 29)
            return false;
        unsigned extra = d < 4 ? 0 : (unsigned)(d / 2 - 1);
        size_t base = d < 4 ? (size_t)d + 1 : ((size_t)(2 + d % 2) << extra) + 1;
        size_t far = base + ref_bits(r, extra);
        if (far > r->out || len > r->expect - r->out)
            return false;
        r->out += len;
    }
}

static bool ref_dynamic(ref *r, ref_code *lit, ref_code *dist)
{
    static const int order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
    int nlit = (int)ref_bits(r, 5) + 257, ndist = (int)ref_bits(r, 5) + 1, ncl = (int)ref_bits(r, 4) + 4;
    if (nlit > 286 || ndist > 30)
        return false;
    int len[320] = {0};
    for (int i = 0; i < ncl; i++)
        len[order[i]] = (int)ref_bits(r, 3);
    ref_code cl;
    if (!ref_build(&cl, len, 19))
        return false;
    memset(len, 0, sizeof len);
    for (int i = 0; i < nlit + ndist;) {
        int s = ref_decode(r, &cl), rep, v = 0;
        if (s < 0)
            return false;
        if (s < 16) {
            len[i++] = s;
            continue;
        }
        if (s == 16) {
            if (i == 0)
                return false;
            v = len[i - 1];
            rep = 3 + (int)ref_bits(r, 2);
        } else {
            rep = s == 17 ? 3 + (int)ref_bits(r, 3) : 11 + (int)ref_bits(r, 7);
        }
        if (i + rep > nlit + ndist)
            return false;
        while (rep--)
            len[i++] = v;
    }
    return len[256] && ref_build(lit, len, nlit) && ref_build(dist, len + nlit, ndist);
}

static bool ref_stored(ref *r)
{
    r->pos = (r->pos + 7) / 8 * 8;
    size_t len = ref_bits(r, 16), nlen = ref_bits(r, 16);
    if ((len ^ nlen) != 0xffff || len > r->expect - r->out || r->pos / 8 + len > r->n)
        return false;
    r->out += len;
    r->pos += len * 8;
    return true;
}

static bool ref_walk(const uint8_t *z, size_t n, size_t expect, deflate_ends *ends)
{
    ref r = {.z = z, .n = n, .expect = expect};
    for (;;) {
        size_t header = r.pos;
        unsigned final = ref_bits(&r, 1), type = ref_bits(&r, 2);
        ref_code lit, dist;
        bool ok = false;
        if (type == 0) {
            ok = ref_stored(&r);
        } else if (type == 1) {
            int len[288];
            for (int s = 0; s < 288; s++)
                len[s] = s < 144 ? 8 : s < 256 ? 9 : s < 280 ? 7 : 8;
            ref_build(&lit, len, 288);
            for (int s = 0; s < 30; s++)
                len[s] = 5;
            ref_build(&dist, len, 30);
            ok = ref_codes(&r, &lit, &dist);
        } else if (type == 2) {
            ok = ref_dynamic(&r, &lit, &dist) && ref_codes(&r, &lit, &dist);
        }
        if (!ok || r.pos > n * 8)
            return false;
        if (final) {
            ends->final_header = header;
            ends->end = r.pos;
            return r.out == expect && (r.pos + 7) / 8 == n;
        }
    }
}

/* ---- agreement -------------------------------------------------------------- */

/* The walk and the reference on the same stream; returns what they said. */
static bool agree(const uint8_t *z, size_t n, size_t expect, const char *what)
{
    deflate_ends a = {0}, b = {0};
    bool got = deflate_walk(z, n, expect, &a), want = ref_walk(z, n, expect, &b);
    cr_assert_eq(got, want, "%s: walk says %d, reference %d (%zu bytes, expect %zu)", what, got,
                 want, n, expect);
    if (got) {
        cr_assert_eq(a.final_header, b.final_header, "%s", what);
        cr_assert_eq(a.end, b.end, "%s", what);
    }
    return got;
}

/* Bytes of one kind: noise, rendered-like rows, skewed values (a value k
 * about twice as rare as k - 1, which gives codes of every length up to
 * 15), or long runs. */
static void fill(uint8_t *p, size_t n, int kind, uint32_t seed)
{
    rng s = rng_seed(seed, 7);
    for (size_t i = 0; i < n; i++) {
        uint32_t r = rng_u32(&s);
        switch (kind) {
        case 0:
            p[i] = (uint8_t)r;
            break;
        case 1:
            p[i] = (uint8_t)(i % 5761 / 23 + r % 3);
            break;
        case 2:
            p[i] = (uint8_t)(r ? __builtin_ctz(r) * 11 + (r >> 28) : 255);
            break;
        default:
            p[i] = (uint8_t)(i / 700 + (r % 997 == 0));
            break;
        }
    }
}

static uint8_t *compress(int level, const uint8_t *in, size_t n, size_t *zn)
{
    struct libdeflate_compressor *c = libdeflate_alloc_compressor(level);
    cr_assert_not_null(c);
    size_t bound = libdeflate_deflate_compress_bound(c, n);
    uint8_t *z = calloc(1, bound + 1);
    cr_assert_not_null(z);
    *zn = libdeflate_deflate_compress(c, in, n, z, bound);
    cr_assert_gt(*zn, 0);
    libdeflate_free_compressor(c);
    return z;
}

Test(deflate_walk, agrees_on_libdeflate_streams_and_their_near_misses)
{
    const size_t sizes[] = {0, 1, 300, 5000, 70000, 300001};
    static uint8_t data[300001];
    for (int level = 0; level <= 12; level += level < 3 ? 1 : 4)
        for (int kind = 0; kind < 4; kind++)
            for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
                size_t n = sizes[k], zn;
                fill(data, n, kind, (uint32_t)(level * 31 + kind * 7 + (int)k));
                uint8_t *z = compress(level, data, n, &zn);
                cr_assert(agree(z, zn, n, "whole"), "level %d, kind %d, %zu bytes", level, kind, n);
                agree(z, zn, n + 1, "a byte short");
                if (n)
                    agree(z, zn, n - 1, "a byte over");
                agree(z, zn - 1, n, "cut by a byte");
                agree(z, zn / 2, n, "cut in half");
                agree(z, zn + 1, n, "a byte after");
                free(z);
            }
}

Test(deflate_walk, agrees_on_streams_with_bits_flipped)
{
    static uint8_t data[40000];
    rng s = rng_seed(5, 0);
    for (int kind = 0; kind < 4; kind++)
        for (int level = 1; level <= 6; level += 5) {
            fill(data, sizeof data, kind, (uint32_t)(kind + level));
            size_t zn;
            uint8_t *z = compress(level, data, sizeof data, &zn);
            uint8_t *copy = malloc(zn);
            cr_assert_not_null(copy);
            for (int i = 0; i < 1500; i++) {
                memcpy(copy, z, zn);
                for (int f = 0; f < 1 + i % 3; f++)
                    copy[rng_u32(&s) % zn] ^= (uint8_t)(1u << rng_u32(&s) % 8);
                agree(copy, zn, sizeof data, "flipped");
            }
            free(copy);
            free(z);
        }
}

Test(deflate_walk, agrees_on_random_bytes)
{
    uint8_t z[600];
    rng s = rng_seed(11, 0);
    for (int i = 0; i < 20000; i++) {
        size_t n = 1 + rng_u32(&s) % sizeof z;
        for (size_t k = 0; k < n; k++)
            z[k] = (uint8_t)rng_u32(&s);
        z[0] = (uint8_t)((z[0] & ~6u) | (i % 3 == 0 ? 2u : 4u)); /* fixed or dynamic codes */
        agree(z, n, rng_u32(&s) % 3000, "random");
    }
}

/* ---- copies at the stream's start ------------------------------------------------ */

typedef struct bitwriter {
    uint8_t z[70000];
    size_t pos;
} bitwriter;

static void put(bitwriter *w, unsigned v, unsigned k)
{
    for (unsigned i = 0; i < k; i++, w->pos++)
        w->z[w->pos / 8] |= (uint8_t)((v >> i & 1) << (w->pos % 8));
}

/* A Huffman code goes most significant bit first. */
static void put_code(bitwriter *w, unsigned code, unsigned k)
{
    for (unsigned i = k; i-- > 0;)
        put(w, code >> i & 1, 1);
}

/* A stored block of `before` bytes, then a fixed block with one copy of
 * length 3 at distance `far`; the stream's length. */
static size_t copy_stream(bitwriter *w, size_t before, unsigned far)
{
    memset(w, 0, sizeof *w);
    put(w, 0, 3);
    w->pos = (w->pos + 7) / 8 * 8;
    put(w, (unsigned)before, 16);
    put(w, (unsigned)before ^ 0xffff, 16);
    w->pos += before * 8;
    put(w, 1, 1);
    put(w, 1, 2);
    put_code(w, 1, 7); /* length code 257: 3 */
    unsigned d = 0;
    while (d + 1 < 30) {
        unsigned extra = (d + 1) < 4 ? 0 : (d + 1) / 2 - 1;
        unsigned base = (d + 1) < 4 ? d + 2 : ((2 + (d + 1) % 2) << extra) + 1;
        if (base > far)
            break;
        d++;
    }
    unsigned extra = d < 4 ? 0 : d / 2 - 1, base = d < 4 ? d + 1 : ((2 + d % 2) << extra) + 1;
    put_code(w, d, 5);
    put(w, far - base, extra);
    put_code(w, 0, 7); /* end of block */
    return (w->pos + 7) / 8;
}

Test(deflate_walk, copies_reach_back_to_the_start_and_no_further)
{
    static bitwriter w;
    const size_t befores[] = {1, 10, 1000, 24577, 32767, 32768, 40000};
    for (size_t i = 0; i < sizeof befores / sizeof *befores; i++) {
        size_t before = befores[i];
        unsigned longest = before < 32768 ? (unsigned)before : 32768;
        size_t n = copy_stream(&w, before, longest);
        cr_expect(agree(w.z, n, before + 3, "in reach"), "distance %u after %zu bytes", longest,
                  before);
        if (before < 32768) {
            n = copy_stream(&w, before, longest + 1);
            cr_expect_not(agree(w.z, n, before + 3, "out of reach"), "distance %u after %zu bytes",
                          longest + 1, before);
        }
    }
}
