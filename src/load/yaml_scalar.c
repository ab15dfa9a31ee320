/* The YAML 1.2 core schema's scalar forms (null, booleans, integers,
 * floats, .inf and .nan) and the questions asked of a built tree: values
 * under keys, descriptions for messages, numbers; and freeing it. */
#include "yaml_doc.h"

#include <errno.h>
#include <langinfo.h>
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/spare.h"
#include "core/text.h"

/* Numbers longer than this are taken as strings: no real number needs it,
 * and it keeps conversion in a stack buffer. */
#define NUMBER_MAX_LEN 256

/* ---- scalars ---------------------------------------------------------- */

/* Forms whose first character differs are passed over without measuring
 * them: most scalars are numbers and names, which match none. */
static bool is_one_of(const char *s, size_t n, const char *const *list)
{
    char first = n ? s[0] : '\0';
    for (; *list; list++)
        if ((*list)[0] == first && strlen(*list) == n && memcmp(s, *list, n) == 0)
            return true;
    return false;
}

static const char *const inf_forms[] = {".inf", ".Inf", ".INF", "+.inf", "+.Inf", "+.INF",
                                        "-.inf", "-.Inf", "-.INF", NULL};
static const char *const nan_forms[] = {".nan", ".NaN", ".NAN", NULL};

/* Whether c is a digit in base 8, 10 or 16. */
static bool is_digit(char c, int base)
{
    if (c >= '0' && c <= '9')
        return c - '0' < base;
    return base == 16 && ((c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'));
}

static size_t digits(const char *s, size_t n, size_t i, int base)
{
    size_t j = i;
    while (j < n && is_digit(s[j], base))
        j++;
    return j - i;
}

#define DEC 10
#define HEX 16

/* The core schema's integer forms: [-+]?[0-9]+ | 0o[0-7]+ | 0x[0-9a-fA-F]+. */
static bool is_int_form(const char *s, size_t n)
{
    if (n > 2 && s[0] == '0' && (s[1] == 'o' || s[1] == 'x'))
        return digits(s, n, 2, s[1] == 'o' ? 8 : HEX) == n - 2;
    size_t i = (n > 0 && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
    return n > i && digits(s, n, i, DEC) == n - i;
}

/* [-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)? */
static bool is_float_form(const char *s, size_t n)
{
    size_t i = (n > 0 && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
    size_t whole = digits(s, n, i, DEC);
    i += whole;
    size_t frac = 0;
    if (i < n && s[i] == '.') {
        frac = digits(s, n, i + 1, DEC);
        i += 1 + frac;
    }
    if (whole == 0 && frac == 0)
        return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        if (i < n && (s[i] == '-' || s[i] == '+'))
            i++;
        size_t e = digits(s, n, i, DEC);
        if (e == 0)
            return false;
        i += e;
    }
    return i == n;
}

static bool is_number_form(const char *s, size_t n)
{
    return n <= NUMBER_MAX_LEN && (is_int_form(s, n) || is_float_form(s, n) ||
                                   is_one_of(s, n, inf_forms) || is_one_of(s, n, nan_forms));
}

/* The form most numbers in a scene take, [-+]?[0-9]*(\.[0-9]*)? with a
 * digit somewhere, judged in one pass: 'i' for an integer, 'f' for a
 * float, and 0 for any other text, which the general forms then judge.
 * Each text it types is a float form, and an integer form exactly when it
 * has no point (0o and 0x stop it at their letter). */
static char short_number(const char *s, size_t n)
{
    size_t i = n > 0 && (s[0] == '-' || s[0] == '+') ? 1 : 0;
    size_t start = i;
    while (i < n && s[i] >= '0' && s[i] <= '9')
        i++;
    if (i == n)
        return i > start ? 'i' : 0;
    if (s[i] != '.')
        return 0;
    for (i++; i < n && s[i] >= '0' && s[i] <= '9'; i++)
        ;
    return i == n && n - start > 1 ? 'f' : 0;
}

/* A null or boolean form is "", "~", four letters (null, true) or five
 * (false), each in three spellings: other words are strings at a glance,
 * and a word of the right length is compared with its spellings whole. */
static ynode_kind word_kind(const char *s, size_t len, bool *is_true)
{
    switch (len) {
    case 0:
        return YNODE_NULL;
    case 1:
        return s[0] == '~' ? YNODE_NULL : YNODE_STRING;
    case 4:
        if (!memcmp(s, "null", 4) || !memcmp(s, "Null", 4) || !memcmp(s, "NULL", 4))
            return YNODE_NULL;
        *is_true = !memcmp(s, "true", 4) || !memcmp(s, "True", 4) || !memcmp(s, "TRUE", 4);
        return *is_true ? YNODE_BOOL : YNODE_STRING;
    case 5:
        return !memcmp(s, "false", 5) || !memcmp(s, "False", 5) || !memcmp(s, "FALSE", 5)
                   ? YNODE_BOOL
                   : YNODE_STRING;
    default:
        return YNODE_STRING;
    }
}

/* Every number form starts with a digit, a sign or a point, and no null or
 * boolean form does: the first character says which to look for. */
ynode_kind ydoc_plain_kind(const char *s, size_t len, bool *is_true, bool *is_int)
{
    *is_true = false;
    *is_int = false;
    char c = len ? s[0] : '\0';
    if (!((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.'))
        return word_kind(s, len, is_true);
    char quick = len <= NUMBER_MAX_LEN ? short_number(s, len) : 0;
    if (quick) {
        *is_int = quick == 'i';
        return YNODE_NUMBER;
    }
    if (is_number_form(s, len)) {
        *is_int = len <= NUMBER_MAX_LEN && is_int_form(s, len);
        return YNODE_NUMBER;
    }
    return YNODE_STRING;
}

uint32_t ydoc_get(const ydoc *d, const ynode *map, const char *key)
{
    if (map->kind != YNODE_MAP) /* a caller that goes on after a kind error */
        return YDOC_NONE;
    size_t len = strlen(key);
    for (uint32_t i = 0; i < map->count; i++) {
        const ynode *k = &d->nodes[ydoc_key(d, map, i)];
        if (k->count == len && d->text[k->first] == key[0] &&
            memcmp(d->text + k->first, key, len) == 0)
            return ydoc_value(d, map, i);
    }
    return YDOC_NONE;
}

const char *ydoc_kind_name(ynode_kind kind)
{
    switch (kind) {
    case YNODE_NULL:
        return "null";
    case YNODE_BOOL:
        return "a boolean";
    case YNODE_NUMBER:
        return "a number";
    case YNODE_STRING:
        return "a string";
    case YNODE_SEQ:
        return "a sequence";
    case YNODE_MAP:
        return "a mapping";
    }
    return "a value";
}

void ydoc_describe(const ydoc *d, const ynode *n, char *buf, size_t cap)
{
    switch ((ynode_kind)n->kind) {
    case YNODE_NULL:
        snprintf(buf, cap, "nothing");
        return;
    case YNODE_BOOL:
        snprintf(buf, cap, "%s", n->flags & YNODE_TRUE ? "true" : "false");
        return;
    case YNODE_STRING: {
        char shown[YDOC_SHOW_MAX * 4 + 8];
        ydoc_show(ydoc_text(d, n), n->count, shown, sizeof shown);
        snprintf(buf, cap, "the string '%s'", shown);
        return;
    }
    case YNODE_NUMBER:
    case YNODE_SEQ:
    case YNODE_MAP:
        snprintf(buf, cap, "%s", ydoc_kind_name((ynode_kind)n->kind));
        return;
    }
}

bool ydoc_is_special(const ydoc *d, const ynode *n)
{
    const char *s = ydoc_text(d, n);
    /* each form starts with '.', '+' or '-' and ends with a letter */
    if (n->count < 4 || (s[0] >= '0' && s[0] <= '9') ||
        (s[n->count - 1] >= '0' && s[n->count - 1] <= '9'))
        return false;
    return is_one_of(s, n->count, inf_forms) || is_one_of(s, n->count, nan_forms);
}

/* A plain decimal of at most seven digits ([-+]?, digits, a point
 * anywhere among them): its digits m and 10^k (k digits after the point)
 * are exact floats, so m / 10^k rounds once, to the float nearest the
 * decimal, which is what strtof gives (Clinger, "How to Read Floating
 * Point Numbers Accurately", PLDI 1990). False for any other form. */
static bool short_decimal(const char *s, size_t len, float *out)
{
    static const float tens[] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f, 1e6f, 1e7f};
    size_t i = len > 0 && (s[0] == '-' || s[0] == '+') ? 1 : 0;
    long m = 0;
    int ndig = 0, frac = -1;
    for (; i < len; i++) {
        if (s[i] == '.' && frac < 0) {
            frac = 0;
            continue;
        }
        if (s[i] < '0' || s[i] > '9' || ++ndig > 7)
            return false;
        m = m * 10 + (s[i] - '0');
        frac += frac >= 0;
    }
    if (ndig == 0)
        return false;
    float v = (float)m / tens[frac > 0 ? frac : 0];
    *out = s[0] == '-' ? -v : v;
    return true;
}

float ydoc_float(const ydoc *d, const ynode *n)
{
    const char *s = ydoc_text(d, n);
    size_t len = n->count;
    float quick;
    if (short_decimal(s, len, &quick))
        return quick;
    if (is_one_of(s, len, nan_forms))
        return NAN;
    if (is_one_of(s, len, inf_forms))
        return s[0] == '-' ? -INFINITY : INFINITY;
    if (len > 2 && s[0] == '0' && s[1] == 'o')
        return (float)strtoull(s + 2, NULL, 8);
    /* strtof follows LC_NUMERIC; give it the decimal point it expects. */
    char buf[NUMBER_MAX_LEN + 8];
    const char *point = nl_langinfo(RADIXCHAR);
    size_t o = 0;
    for (size_t i = 0; i < len && o + 4 < sizeof buf; i++) {
        if (s[i] == '.' && point && point[0] && strcmp(point, ".") != 0) {
            size_t pl = strlen(point);
            if (pl > 3 || o + pl + 1 >= sizeof buf)
                return NAN;
            memcpy(buf + o, point, pl);
            o += pl;
        } else {
            buf[o++] = s[i];
        }
    }
    buf[o] = '\0';
    return strtof(buf, NULL);
}

bool ydoc_is_integer(const ydoc *d, const ynode *n)
{
    return n->kind == YNODE_NUMBER && is_int_form(ydoc_text(d, n), n->count);
}

bool ydoc_int(const ydoc *d, const ynode *n, long long *out)
{
    const char *s = ydoc_text(d, n);
    if (n->kind != YNODE_NUMBER || !is_int_form(s, n->count))
        return false;
    int base = 10;
    const char *p = s;
    if (n->count > 2 && s[0] == '0' && (s[1] == 'o' || s[1] == 'x')) {
        base = s[1] == 'o' ? 8 : 16;
        p = s + 2;
    }
    char *end;
    errno = 0;
    long long v = strtoll(p, &end, base);
    if (errno == ERANGE || *end)
        return false;
    *out = v;
    return true;
}

void ydoc_show(const char *text, size_t len, char *buf, size_t cap)
{
    text_escape(text, len, YDOC_SHOW_MAX, buf, cap);
}

void ydoc_free(ydoc *d)
{
    if (!d)
        return;
    if (!ydoc_borrowed(d, d->nodes))
        free(d->nodes);
    if (!ydoc_borrowed(d, d->kids))
        free(d->kids);
    if (!ydoc_borrowed(d, d->text))
        free(d->text);
    spare_give(d->block); /* the next big block (a film) takes its pages */
    free(d);
}
