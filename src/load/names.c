#include "names.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Words longer than this are never given suggestions (keeps the distance
 * computation on the stack and bounded). */
#define SUGGEST_MAX_LEN 128

static uint64_t hash(const char *key, size_t len)
{
    uint64_t h = 14695981039346656037u;
    for (size_t i = 0; i < len; i++) {
        h ^= (unsigned char)key[i];
        h *= 1099511628211u;
    }
    return h;
}

static names_slot *slot_for(const names_slot *slots, size_t cap, const char *key, size_t len)
{
    size_t i = (size_t)hash(key, len) & (cap - 1);
    for (;;) {
        const names_slot *s = &slots[i];
        if (!s->key || (s->len == len && memcmp(s->key, key, len) == 0))
            return (names_slot *)s;
        i = (i + 1) & (cap - 1);
    }
}

int names_find(const names *t, const char *key, size_t len)
{
    if (t->cap == 0)
        return -1;
    const names_slot *s = slot_for(t->slots, t->cap, key, len);
    return s->key ? s->value : -1;
}

/* Doubles the table, keeping it at most half full. */
static bool grow(names *t)
{
    size_t ncap = t->cap ? t->cap * 2 : 16;
    if (ncap > SIZE_MAX / sizeof(names_slot))
        return false;
    names_slot *slots = calloc(ncap, sizeof *slots);
    if (!slots)
        return false;
    for (size_t i = 0; i < t->cap; i++)
        if (t->slots[i].key)
            *slot_for(slots, ncap, t->slots[i].key, t->slots[i].len) = t->slots[i];
    free(t->slots);
    t->slots = slots;
    t->cap = ncap;
    return true;
}

bool names_put(names *t, const char *key, size_t len, int value)
{
    if ((t->count + 1) * 2 > t->cap && !grow(t))
        return false;
    names_slot *s = slot_for(t->slots, t->cap, key, len);
    if (s->key) {
        s->value = value;
        return true;
    }
    char *copy = malloc(len + 1);
    if (!copy)
        return false;
    memcpy(copy, key, len);
    copy[len] = '\0';
    *s = (names_slot){copy, len, value};
    t->count++;
    return true;
}

void names_free(names *t)
{
    for (size_t i = 0; i < t->cap; i++)
        free(t->slots[i].key);
    free(t->slots);
    *t = (names){0};
}

static char lower(char c) { return c >= 'A' && c <= 'Z' ? (char)(c - 'A' + 'a') : c; }

/* Edit distance between a and b, ignoring ASCII case, counting a swap of
 * two neighbouring letters as one edit (the optimal string alignment
 * distance: Wagner and Fischer, "The String-to-String Correction Problem",
 * JACM 1974, with Damerau's transpositions), or limit + 1 when it exceeds
 * limit. Only the cells within limit of the diagonal can stay within limit
 * (Ukkonen, "Algorithms for approximate string matching", 1985), so each
 * row costs O(limit), not O(length). */
static size_t distance(const char *a, size_t na, const char *b, size_t nb, size_t limit)
{
    if (na > SUGGEST_MAX_LEN || nb > SUGGEST_MAX_LEN)
        return limit + 1;
    if ((na > nb ? na - nb : nb - na) > limit)
        return limit + 1;
    /* rows[i % 3][j]: distance of a[0..i) to b[0..j); cells outside the
     * band hold limit + 1. */
    size_t rows[3][SUGGEST_MAX_LEN + 1];
    for (size_t j = 0; j <= nb; j++)
        rows[0][j] = j <= limit ? j : limit + 1;
    for (size_t i = 1; i <= na; i++) {
        size_t *row = rows[i % 3], *up = rows[(i - 1) % 3], *up2 = rows[(i + 1) % 3];
        size_t lo = i > limit ? i - limit : 1, hi = i + limit < nb ? i + limit : nb;
        for (size_t j = 0; j <= nb; j++)
            row[j] = limit + 1;
        if (lo == 1)
            row[0] = i <= limit ? i : limit + 1;
        size_t best = row[lo - 1];
        for (size_t j = lo; j <= hi; j++) {
            size_t v = up[j - 1] + (lower(a[i - 1]) != lower(b[j - 1]));
            if (up[j] + 1 < v)
                v = up[j] + 1;
            if (row[j - 1] + 1 < v)
                v = row[j - 1] + 1;
            if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
                lower(a[i - 2]) == lower(b[j - 1]) && up2[j - 2] + 1 < v)
                v = up2[j - 2] + 1;
            row[j] = v > limit ? limit + 1 : v;
            if (row[j] < best)
                best = row[j];
        }
        if (best > limit)
            return limit + 1;
    }
    return rows[na % 3][nb];
}

/* Whether candidate (c, nc) at distance d beats the best so far. */
static bool better(const char *c, size_t nc, size_t d, const char *best, size_t best_d)
{
    if (!best || d < best_d)
        return true;
    if (d > best_d)
        return false;
    size_t nb = strlen(best);
    int cmp = memcmp(c, best, nc < nb ? nc : nb);
    return cmp < 0 || (cmp == 0 && nc < nb);
}

/* Edits allowed for a word of len characters (names.h). */
static size_t suggest_limit(size_t len)
{
    return len >= NAMES_SUGGEST_LONG ? NAMES_SUGGEST_DISTANCE : 1;
}

const char *names_suggest(const names *t, const char *word, size_t len)
{
    const char *best = NULL;
    size_t best_d = 0, limit = suggest_limit(len);
    for (size_t i = 0; i < t->cap; i++) {
        const names_slot *s = &t->slots[i];
        if (!s->key || memchr(s->key, '\0', s->len))
            continue;
        size_t d = distance(word, len, s->key, s->len, limit);
        if (d <= limit && better(s->key, s->len, d, best, best_d)) {
            best = s->key;
            best_d = d;
        }
    }
    return best;
}

const char *names_suggest_list(const char *const *list, const char *word, size_t len)
{
    const char *best = NULL;
    size_t limit = suggest_limit(len), best_d = limit + 1;
    for (; *list; list++) {
        size_t d = distance(word, len, *list, strlen(*list), limit);
        if (d < best_d) {
            best = *list;
            best_d = d;
        }
    }
    return best;
}
