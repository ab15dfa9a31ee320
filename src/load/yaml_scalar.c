/* The YAML 1.2 core schema's scalar forms (null, booleans, integers,
 * floats, .inf and .nan) and the questions asked of a built tree: values
 * under keys, descriptions for messages, numbers. */
#include "yaml_doc.h"

#include <errno.h>
#include <langinfo.h>
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Numbers longer than this are taken as strings: no real number needs it,
 * and it keeps conversion in a stack buffer. */
#define NUMBER_MAX_LEN 256

/* ---- scalars ---------------------------------------------------------- */

static bool is_one_of(const char *s, size_t n, const char *const *list)
{
    for (; *list; list++)
        if (strlen(*list) == n && memcmp(s, *list, n) == 0)
            return true;
    return false;
}

static const char *const null_forms[] = {"", "~", "null", "Null", "NULL", NULL};
static const char *const true_forms[] = {"true", "True", "TRUE", NULL};
static const char *const false_forms[] = {"false", "False", "FALSE", NULL};
static const char *const inf_forms[] = {".inf", ".Inf", ".INF", "+.inf", "+.Inf", "+.INF",
                                        "-.inf", "-.Inf", "-.INF", NULL};
static const char *const nan_forms[] = {".nan", ".NaN", ".NAN", NULL};

static size_t digits(const char *s, size_t n, size_t i, const char *set)
{
    size_t j = i;
    while (j < n && s[j] && strchr(set, s[j]))
        j++;
    return j - i;
}

#define DEC "0123456789"
#define HEX "0123456789abcdefABCDEF"

/* The core schema's integer forms: [-+]?[0-9]+ | 0o[0-7]+ | 0x[0-9a-fA-F]+. */
static bool is_int_form(const char *s, size_t n)
{
    if (n > 2 && s[0] == '0' && (s[1] == 'o' || s[1] == 'x'))
        return digits(s, n, 2, s[1] == 'o' ? "01234567" : HEX) == n - 2;
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

ynode_kind ydoc_plain_kind(const char *s, size_t len, bool *is_true, bool *is_int)
{
    *is_true = false;
    *is_int = false;
    if (is_one_of(s, len, null_forms))
        return YNODE_NULL;
    if (is_one_of(s, len, true_forms)) {
        *is_true = true;
        return YNODE_BOOL;
    }
    if (is_one_of(s, len, false_forms))
        return YNODE_BOOL;
    if (is_number_form(s, len)) {
        *is_int = len <= NUMBER_MAX_LEN && is_int_form(s, len);
        return YNODE_NUMBER;
    }
    return YNODE_STRING;
}

uint32_t ydoc_get(const ydoc *d, const ynode *map, const char *key)
{
    size_t len = strlen(key);
    for (uint32_t i = 0; i < map->count; i++) {
        const ynode *k = &d->nodes[ydoc_key(d, map, i)];
        if (k->count == len && memcmp(d->text + k->first, key, len) == 0)
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
    return is_one_of(s, n->count, inf_forms) || is_one_of(s, n->count, nan_forms);
}

float ydoc_float(const ydoc *d, const ynode *n)
{
    const char *s = ydoc_text(d, n);
    size_t len = n->count;
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
