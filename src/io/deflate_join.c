/* deflate_join: finding a deflate stream's final block, and joining
 * streams (deflate_join.h). RFC 1951: blocks (3.2.3), Huffman codes
 * (3.2.2), stored blocks (3.2.4), fixed codes (3.2.6), dynamic ones (3.2.7);
 * RFC 1950 (8.2) for Adler-32. */
#include "deflate_join.h"

#include <string.h>

/* ---- reading bits, least significant first ------------------------------- */

/* Bytes past the end read as zeros; `at` counts them all the same, so a
 * stream that runs past its end is seen by its bit position. */
typedef struct bitreader {
    const uint8_t *z;
    size_t n, at;  /* length; next byte to load */
    uint64_t buf;  /* bits not yet used, the next one lowest */
    unsigned have; /* how many */
} bitreader;

#define INLINE static inline __attribute__((always_inline))

/* Tops up the buffer to at least 56 bits. Its parts are passed one by one
 * so that the hot loop keeps them in registers. */
INLINE void refill_bits(const uint8_t *z, size_t n, size_t *at, uint64_t *buf, unsigned *have)
{
    if (*at + 8 <= n) {
        uint64_t w;
        memcpy(&w, z + *at, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
        w = __builtin_bswap64(w);
#endif
        *buf |= w << *have;
        *at += (63 - *have) >> 3;
        *have |= 56;
        return;
    }
    for (; *have <= 56; *have += 8, ++*at)
        *buf |= (uint64_t)(*at < n ? z[*at] : 0) << *have;
}

INLINE void refill(bitreader *b) { refill_bits(b->z, b->n, &b->at, &b->buf, &b->have); }

/* k <= 32 bits. */
INLINE uint32_t take(bitreader *b, unsigned k)
{
    if (b->have < k)
        refill(b);
    uint32_t v = (uint32_t)(b->buf & ((1ull << k) - 1));
    b->buf >>= k;
    b->have -= k;
    return v;
}

static size_t bit_position(const bitreader *b) { return b->at * 8 - b->have; }

/* ---- Huffman codes ---------------------------------------------------------- */

#define TABLE_BITS 10
#define MAX_BITS 15

/* What a symbol means, as an entry of a code's table: its value (a
 * literal byte, the base of a length or distance, or a code length), its
 * kind, and how many extra bits follow its code; in a table the code's
 * length is added, on its own and into the bits the entry uses:
 *
 *   bit 31       a literal byte of the literal/length code
 *   bits 16-30   value
 *   bit 15       anything but a literal or a copy: an end of block, a
 *                symbol no block may hold, a code longer than TABLE_BITS
 *   bits 12-14   kind
 *   bits 8-11    the code's length
 *   bits 0-7     bits the symbol uses: its code and its extra bits
 *
 * so that a literal is told by one test and used up by one shift. */
enum { KIND_LITERAL, KIND_COPY, KIND_END, KIND_BAD, KIND_LONG };
#define ENTRY_LITERAL (1u << 31)
#define ENTRY_OTHER (1u << 15)
#define MEANING(kind, extra, value)                                                 \
    ((uint32_t)(value) << 16 | (uint32_t)(kind) << 12 | (uint32_t)(extra) |         \
     ((kind) >= KIND_END ? ENTRY_OTHER : 0))
#define ENTRY_USES(e) ((e) & 0xff)
#define ENTRY_CODE(e) ((e) >> 8 & 15)
#define ENTRY_KIND(e) ((e) >> 12 & 7)
#define ENTRY_VALUE(e) ((e) >> 16 & 0x7fff)
/* In a table, where a longer code starts. */
#define ENTRY_LONG MEANING(KIND_LONG, 0, 0)

/* A canonical code: codes up to TABLE_BITS long are found in one look-up
 * of the next TABLE_BITS bits (ENTRY_LONG for the prefix of a longer
 * code), longer ones bit by bit from the counts. */
typedef struct huffman {
    uint32_t table[1 << TABLE_BITS];
    uint16_t count[MAX_BITS + 1];
    uint16_t sorted[288]; /* symbols by code length, then by value */
    const uint32_t *meaning;
} huffman;

/* A meaning with a code of l bits. */
static uint32_t with_code(uint32_t meaning, unsigned l) { return meaning + (l << 8) + l; }

/* False for a code with more codes than its lengths have room for. */
static bool huffman_build(huffman *h, const uint8_t *len, int nsym, const uint32_t *meaning)
{
    h->meaning = meaning;
    memset(h->count, 0, sizeof h->count);
    for (int s = 0; s < nsym; s++)
        h->count[len[s]]++;
    h->count[0] = 0;
    int left = 1;
    for (int l = 1; l <= MAX_BITS; l++) {
        left = left * 2 - h->count[l];
        if (left < 0)
            return false;
    }
    uint16_t offs[MAX_BITS + 2] = {0};
    for (int l = 1; l <= MAX_BITS; l++)
        offs[l + 1] = (uint16_t)(offs[l] + h->count[l]);
    for (int s = 0; s < nsym; s++)
        if (len[s])
            h->sorted[offs[len[s]]++] = (uint16_t)s;
    for (unsigned j = 0; j < (1u << TABLE_BITS); j++)
        h->table[j] = ENTRY_LONG;
    unsigned code = 0;
    int k = 0;
    for (unsigned l = 1; l <= TABLE_BITS; l++, code <<= 1)
        for (int c = 0; c < h->count[l]; c++, k++, code++) {
            unsigned rev = 0;
            for (unsigned i = 0; i < l; i++)
                rev |= (code >> i & 1u) << (l - 1 - i);
            uint32_t e = with_code(meaning[h->sorted[k]], l);
            for (unsigned j = rev; j < (1u << TABLE_BITS); j += 1u << l)
                h->table[j] = e;
        }
    return true;
}

/* A code longer than TABLE_BITS, read bit by bit from buf: its symbol's
 * meaning with the code's length, or KIND_BAD for bits that are no code. */
static uint32_t decode_long(uint64_t buf, const huffman *h)
{
    int code = 0, first = 0, index = 0;
    for (unsigned l = 1; l <= MAX_BITS; l++, buf >>= 1) {
        code |= (int)(buf & 1);
        int count = h->count[l];
        if (code - count < first)
            return with_code(h->meaning[h->sorted[index + (code - first)]], l);
        index += count;
        first = (first + count) << 1;
        code <<= 1;
    }
    return with_code(MEANING(KIND_BAD, 0, 0), 1);
}

/* The entry of the next symbol, looked up. */
INLINE uint32_t look_up(uint64_t buf, const huffman *h)
{
    uint32_t e = h->table[buf & ((1u << TABLE_BITS) - 1)];
    return __builtin_expect(ENTRY_KIND(e) == KIND_LONG, 0) ? decode_long(buf, h) : e;
}

/* Uses up the symbol of entry e: its value with its extra bits added. */
INLINE uint32_t use(uint64_t *buf, unsigned *have, uint32_t e)
{
    uint32_t extra = (uint32_t)((*buf & ((1ull << ENTRY_USES(e)) - 1)) >> ENTRY_CODE(e));
    *buf >>= ENTRY_USES(e);
    *have -= ENTRY_USES(e);
    return ENTRY_VALUE(e) + extra;
}

/* The next symbol's kind, its value with its extra bits added into
 * *value. The buffer must hold MAX_BITS bits and the extra ones. */
INLINE unsigned decode_bits(uint64_t *buf, unsigned *have, const huffman *h, uint32_t *value)
{
    uint32_t e = look_up(*buf, h);
    *value = use(buf, have, e);
    return ENTRY_KIND(e);
}

INLINE unsigned decode(bitreader *b, const huffman *h, uint32_t *value)
{
    return decode_bits(&b->buf, &b->have, h, value);
}

/* ---- blocks --------------------------------------------------------------- */

static const uint16_t len_base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                      31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const uint8_t len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                      2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const uint16_t dist_base[30] = {1,    2,    3,    4,    5,    7,     9,     13,    17,  25,
                                       33,   49,   65,   97,   129,  193,   257,   385,   513, 769,
                                       1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
static const uint8_t dist_extra[30] = {0, 0, 0, 0, 1, 1, 2, 2,  3,  3,  4,  4,  5,  5,  6,
                                       6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

typedef struct walk {
    bitreader b;
    size_t out, expect; /* bytes decoded so far; bytes the stream must hold */
    huffman lit, dist;
    uint32_t lit_meaning[288], dist_meaning[32], length_meaning[19];
} walk;

static void meanings(walk *w)
{
    for (int s = 0; s < 288; s++)
        w->lit_meaning[s] = s < 256    ? MEANING(KIND_LITERAL, 0, s) | ENTRY_LITERAL
                            : s == 256 ? MEANING(KIND_END, 0, 0)
                            : s < 286  ? MEANING(KIND_COPY, len_extra[s - 257], len_base[s - 257])
                                       : MEANING(KIND_BAD, 0, 0);
    for (int s = 0; s < 32; s++)
        w->dist_meaning[s] = s < 30 ? MEANING(KIND_COPY, dist_extra[s], dist_base[s])
                                    : MEANING(KIND_BAD, 0, 0);
    for (int s = 0; s < 19; s++)
        w->length_meaning[s] = MEANING(KIND_LITERAL, 0, s);
}

/* Uses up a symbol without its value. */
INLINE void skip(uint64_t *buf, unsigned *have, uint32_t e)
{
    *buf >>= ENTRY_USES(e);
    *have -= ENTRY_USES(e);
}

/* The symbols of a compressed block, counted; false on a broken one. The
 * reader's parts are local, which the compiler keeps in registers, and
 * the buffer is topped up on every turn (one load while the stream lasts)
 * rather than tested: after it, two literals of the table, or a literal,
 * a length and a distance, are in it (10 + 15 + 28 of at least 56 bits;
 * a longer code tops it up again). Literals, most symbols of a noisy
 * image, take the shortest path, two to a turn. The count is checked
 * against expect at each copy, and by the caller after the block, rather
 * than at each literal; a stream that runs on past its end is stopped
 * when the reader is 8 bytes past it (its bit position is then past the
 * end, which fails the walk all the same). */
static bool walk_codes(walk *w)
{
    const uint8_t *z = w->b.z;
    const size_t n = w->b.n, expect = w->expect;
    size_t at = w->b.at, out = w->out;
    uint64_t buf = w->b.buf;
    unsigned have = w->b.have;
    bool ok = false;
    for (;;) {
        refill_bits(z, n, &at, &buf, &have);
        if (at > n + 8)
            break;
        uint32_t e = w->lit.table[buf & ((1u << TABLE_BITS) - 1)];
        if (e & ENTRY_LITERAL) {
            skip(&buf, &have, e);
            out++;
            e = w->lit.table[buf & ((1u << TABLE_BITS) - 1)];
            if (e & ENTRY_LITERAL) {
                skip(&buf, &have, e);
                out++;
                continue;
            }
        }
        if (e & ENTRY_OTHER) {
            if (have < 48)
                refill_bits(z, n, &at, &buf, &have);
            e = look_up(buf, &w->lit);
            if (ENTRY_KIND(e) != KIND_COPY) {
                skip(&buf, &have, e);
                out += ENTRY_KIND(e) == KIND_LITERAL;
                if (ENTRY_KIND(e) == KIND_LITERAL)
                    continue;
                ok = ENTRY_KIND(e) == KIND_END;
                break;
            }
        }
        size_t len = use(&buf, &have, e);
        if (have < 28)
            refill_bits(z, n, &at, &buf, &have);
        uint32_t d = look_up(buf, &w->dist);
        if (ENTRY_KIND(d) != KIND_COPY || out + len > expect)
            break;
        if (out >= 32768) /* past the longest distance: only its bits matter */
            skip(&buf, &have, d);
        else if (use(&buf, &have, d) > out)
            break;
        out += len;
    }
    w->b.at = at;
    w->b.buf = buf;
    w->b.have = have;
    w->out = out;
    return ok;
}

/* A dynamic block's code lengths (3.2.7) into the two codes. */
static bool walk_dynamic(walk *w)
{
    static const uint8_t order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
    unsigned nlit = take(&w->b, 5) + 257, ndist = take(&w->b, 5) + 1, ncl = take(&w->b, 4) + 4;
    if (nlit > 286 || ndist > 30)
        return false;
    uint8_t len[286 + 30] = {0};
    for (unsigned i = 0; i < ncl; i++)
        len[order[i]] = (uint8_t)take(&w->b, 3);
    huffman *cl = &w->dist; /* free until the lengths are read */
    if (!huffman_build(cl, len, 19, w->length_meaning))
        return false;
    memset(len, 0, 19);
    for (unsigned i = 0; i < nlit + ndist;) {
        if (w->b.have < MAX_BITS)
            refill(&w->b);
        uint32_t sym;
        if (decode(&w->b, cl, &sym) != KIND_LITERAL)
            return false;
        if (sym < 16) {
            len[i++] = (uint8_t)sym;
            continue;
        }
        unsigned rep = sym == 16 ? 3 + take(&w->b, 2) : sym == 17 ? 3 + take(&w->b, 3)
                                                                  : 11 + take(&w->b, 7);
        if ((sym == 16 && i == 0) || i + rep > nlit + ndist)
            return false;
        uint8_t v = sym == 16 ? len[i - 1] : 0;
        for (unsigned k = 0; k < rep; k++)
            len[i++] = v;
    }
    return len[256] != 0 && huffman_build(&w->lit, len, (int)nlit, w->lit_meaning) &&
           huffman_build(&w->dist, len + nlit, (int)ndist, w->dist_meaning);
}

static void fixed_codes(walk *w)
{
    uint8_t len[288];
    memset(len, 8, 144);
    memset(len + 144, 9, 112);
    memset(len + 256, 7, 24);
    memset(len + 280, 8, 8);
    huffman_build(&w->lit, len, 288, w->lit_meaning);
    memset(len, 5, 32);
    huffman_build(&w->dist, len, 32, w->dist_meaning);
}

/* A stored block (3.2.4): its length, then skipped over. */
static bool walk_stored(walk *w)
{
    take(&w->b, w->b.have % 8);
    uint32_t len = take(&w->b, 16), nlen = take(&w->b, 16);
    size_t at = bit_position(&w->b) / 8;
    if ((len ^ nlen) != 0xffff || len > w->expect - w->out || at + len > w->b.n)
        return false;
    w->out += len;
    w->b.at = at + len;
    w->b.buf = 0;
    w->b.have = 0;
    return true;
}

bool deflate_walk(const uint8_t *z, size_t n, size_t expect, deflate_ends *ends)
{
    walk w = {.b = {.z = z, .n = n}, .expect = expect};
    meanings(&w);
    for (;;) {
        size_t header = bit_position(&w.b);
        uint32_t final = take(&w.b, 1), type = take(&w.b, 2);
        bool ok = false;
        if (type == 0) {
            ok = walk_stored(&w);
        } else if (type == 1) {
            fixed_codes(&w);
            ok = walk_codes(&w);
        } else if (type == 2) {
            ok = walk_dynamic(&w) && walk_codes(&w);
        }
        size_t at = bit_position(&w.b);
        if (!ok || at > n * 8 || w.out > expect)
            return false;
        if (final) {
            ends->final_header = header;
            ends->end = at;
            return w.out == expect && (at + 7) / 8 == n;
        }
    }
}

void deflate_unfinal(uint8_t *z, size_t *n, const deflate_ends *ends)
{
    z[ends->final_header / 8] &= (uint8_t)~(1u << ends->final_header % 8);
    size_t m = (ends->end + 7) / 8;
    unsigned r = (unsigned)(ends->end % 8); /* bits used in the last byte; 0: all 8 */
    if (r)
        z[m - 1] &= (uint8_t)((1u << r) - 1);
    /* an empty stored block: header 000 (not final, stored), up to the
     * byte boundary, then LEN 0 and NLEN 0xffff */
    if (r == 0 || r > 5)
        z[m++] = 0; /* the header does not fit in what is left of the byte */
    z[m++] = 0;
    z[m++] = 0;
    z[m++] = 0xff;
    z[m++] = 0xff;
    *n = m;
}

uint32_t deflate_adler32_combine(uint32_t a, uint32_t b, size_t len_b)
{
    const uint64_t base = 65521;
    uint64_t rem = len_b % base;
    uint64_t s1 = (a & 0xffff) + (b & 0xffff) + base - 1;
    uint64_t s2 = (rem * (a & 0xffff)) % base + (a >> 16) + (b >> 16) + base - rem;
    s1 %= base;
    s2 %= base;
    return (uint32_t)(s1 | s2 << 16);
}
