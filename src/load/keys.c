/* Reading keys and values of the scene format, with the messages that name
 * the file, line and column of what is wrong (loader.h). */
#include "loader.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "core/array.h"

/* ---- messages --------------------------------------------------------- */

static glint_rc vfail_at(loader *L, int file, uint32_t line, uint32_t col, const char *fmt,
                         va_list ap)
{
    char msg[900];
    vsnprintf(msg, sizeof msg, fmt, ap);
    return err_set(L->err, GLINT_ERR_INPUT, "%s:%u:%u: %s", L->files[file].name, line, col, msg);
}

/* Fails with "FILE:LINE:COL: message" at node at of file. */
GLINT_PRINTF(4, 5)
glint_rc load_fail_in(loader *L, int file, uint32_t at, const char *fmt, ...)
{
    const ynode *n = ydoc_node(L->files[file].doc, at);
    va_list ap;
    va_start(ap, fmt);
    glint_rc rc = vfail_at(L, file, n->line, n->col, fmt, ap);
    va_end(ap);
    return rc;
}

/* The same in the file being read. */
GLINT_PRINTF(3, 4)
glint_rc load_fail(loader *L, uint32_t at, const char *fmt, ...)
{
    const ynode *n = ydoc_node(L->files[L->cur].doc, at);
    va_list ap;
    va_start(ap, fmt);
    glint_rc rc = vfail_at(L, L->cur, n->line, n->col, fmt, ap);
    va_end(ap);
    return rc;
}

const ydoc *load_doc(const loader *L) { return L->files[L->cur].doc; }
const ynode *load_node(const loader *L, uint32_t i) { return ydoc_node(load_doc(L), i); }

/* A scalar's text made printable, into buf (SHOWN bytes). */
const char *load_shown(const loader *L, uint32_t i, char *buf)
{
    const ynode *n = load_node(L, i);
    ydoc_show(ydoc_text(load_doc(L), n), n->count, buf, SHOWN);
    return buf;
}

glint_rc load_expected(loader *L, uint32_t v, const char *what, const char *key)
{
    char got[SHOWN + 32];
    ydoc_describe(load_doc(L), load_node(L, v), got, sizeof got);
    return load_fail(L, v, "expected %s for '%s', got %s", what, key, got);
}

/* " (did you mean 'x'?)" or, with no near candidate, " (valid: a, b, c)". */
void load_suggestion(const char *const *valid, const char *word, size_t len, char *buf,
                       size_t cap)
{
    const char *near = names_suggest_list(valid, word, len);
    if (near) {
        snprintf(buf, cap, " (did you mean '%s'?)", near);
        return;
    }
    size_t o = (size_t)snprintf(buf, cap, " (valid: ");
    for (const char *const *k = valid; *k && o < cap; k++)
        o += (size_t)snprintf(buf + o, cap - o, "%s%s", *k, k[1] ? ", " : ")");
}

/* ---- keys of a mapping ------------------------------------------------ */

/* Whether the NUL-terminated text (len bytes) is word: the first bytes
 * are compared first, and most words differ there. */
static bool is_word(const char *word, const char *text, size_t len)
{
    return word[0] == text[0] && strlen(word) == len && memcmp(word, text, len) == 0;
}

/* Refuses the first key of map that is not in valid; the message says
 * where the mapping is, in the words lead, name and tail joined. */
static glint_rc check_keys(loader *L, uint32_t map, const char *const *valid, const char *lead,
                           const char *name, const char *tail)
{
    const ynode *m = load_node(L, map);
    for (uint32_t i = 0; i < m->count; i++) {
        uint32_t k = ydoc_key(load_doc(L), m, i);
        const ynode *kn = load_node(L, k);
        const char *text = ydoc_text(load_doc(L), kn);
        bool known = false;
        for (const char *const *v = valid; *v && !known; v++)
            known = is_word(*v, text, kn->count);
        if (!known) {
            char buf[SHOWN], hint[512];
            load_suggestion(valid, text, kn->count, hint, sizeof hint);
            return load_fail(L, k, "unknown key '%s' %s%s%s%s", load_shown(L, k, buf), lead, name,
                             tail, hint);
        }
    }
    return GLINT_OK;
}

glint_rc load_check_keys(loader *L, uint32_t map, const char *const *valid, const char *where)
{
    return check_keys(L, map, valid, where, "", "");
}

glint_rc load_check_keys_in(loader *L, uint32_t map, const char *const *valid, const char *name,
                            const char *tail)
{
    return check_keys(L, map, valid, "in ", name, tail);
}

uint32_t load_get(const loader *L, uint32_t map, const char *key)
{
    return ydoc_get(load_doc(L), load_node(L, map), key);
}

/* The value under key, which must be there; what names the mapping. */
glint_rc load_need(loader *L, uint32_t map, const char *key, const char *what, uint32_t *v)
{
    *v = load_get(L, map, key);
    if (*v == YDOC_NONE)
        return load_fail(L, map, "%s needs '%s'", what, key);
    return GLINT_OK;
}

glint_rc load_want_map(loader *L, uint32_t v, const char *key)
{
    return load_node(L, v)->kind == YNODE_MAP ? GLINT_OK : load_expected(L, v, "a mapping", key);
}

/* ---- values ----------------------------------------------------------- */

glint_rc load_number(loader *L, uint32_t v, const char *key, float *out)
{
    if (load_node(L, v)->kind != YNODE_NUMBER)
        return load_expected(L, v, "a number", key);
    char buf[SHOWN];
    float f = ydoc_float(load_doc(L), load_node(L, v));
    if (ydoc_is_special(load_doc(L), load_node(L, v)))
        return load_fail(L, v, "%s must be a finite number (got %s)", key, load_shown(L, v, buf));
    if (!isfinite(f))
        return load_fail(L, v, "%s is too large (got %s)", key, load_shown(L, v, buf));
    *out = f;
    return GLINT_OK;
}

glint_rc load_positive(loader *L, uint32_t v, const char *key, float *out)
{
    glint_rc rc = load_number(L, v, key, out);
    char buf[SHOWN];
    if (rc == GLINT_OK && !(*out > 0.0f))
        rc = load_fail(L, v, "%s must be > 0 (got %s)", key, load_shown(L, v, buf));
    return rc;
}

glint_rc load_nonneg(loader *L, uint32_t v, const char *key, float *out)
{
    glint_rc rc = load_number(L, v, key, out);
    char buf[SHOWN];
    if (rc == GLINT_OK && !(*out >= 0.0f))
        rc = load_fail(L, v, "%s must be >= 0 (got %s)", key, load_shown(L, v, buf));
    return rc;
}

glint_rc load_unit(loader *L, uint32_t v, const char *key, float *out)
{
    glint_rc rc = load_number(L, v, key, out);
    char buf[SHOWN];
    if (rc == GLINT_OK && !(*out >= 0.0f && *out <= 1.0f))
        rc = load_fail(L, v, "%s must be between 0 and 1 (got %s)", key, load_shown(L, v, buf));
    return rc;
}

glint_rc load_nonzero(loader *L, uint32_t v, const char *key, float *out)
{
    glint_rc rc = load_number(L, v, key, out);
    char buf[SHOWN];
    if (rc == GLINT_OK && *out == 0.0f)
        rc = load_fail(L, v, "%s must not be 0 (got %s)", key, load_shown(L, v, buf));
    return rc;
}

glint_rc load_int(loader *L, uint32_t v, const char *key, int lo, int hi, int *out)
{
    const ynode *n = load_node(L, v);
    char buf[SHOWN];
    if (n->kind != YNODE_NUMBER)
        return load_expected(L, v, "a whole number", key);
    if (!ydoc_is_integer(load_doc(L), n))
        return load_fail(L, v, "expected a whole number for '%s', got %s", key, load_shown(L, v, buf));
    long long x;
    if (!ydoc_int(load_doc(L), n, &x) || x < lo || x > hi)
        return load_fail(L, v, "%s must be %d to %d (got %s)", key, lo, hi, load_shown(L, v, buf));
    *out = (int)x;
    return GLINT_OK;
}

glint_rc load_bool(loader *L, uint32_t v, const char *key, bool *out)
{
    if (load_node(L, v)->kind != YNODE_BOOL)
        return load_expected(L, v, "true or false", key);
    *out = load_node(L, v)->flags & YNODE_TRUE;
    return GLINT_OK;
}

/* n numbers in a sequence; what describes it ("[x, y, z]"). */
glint_rc load_numbers(loader *L, uint32_t v, const char *key, const char *what, int n,
                             float *out)
{
    const ynode *s = load_node(L, v);
    if (s->kind != YNODE_SEQ)
        return load_expected(L, v, what, key);
    if (s->count != (uint32_t)n)
        return load_fail(L, v, "expected %d numbers for '%s', got %u", n, key, s->count);
    for (int i = 0; i < n; i++) {
        glint_rc rc = load_number(L, ydoc_item(load_doc(L), s, (uint32_t)i), key, &out[i]);
        if (rc != GLINT_OK)
            return rc;
    }
    return GLINT_OK;
}

glint_rc load_vec3(loader *L, uint32_t v, const char *key, vec3 *out)
{
    float f[3];
    glint_rc rc = load_numbers(L, v, key, "[x, y, z]", 3, f);
    if (rc == GLINT_OK)
        *out = v3(f[0], f[1], f[2]);
    return rc;
}

glint_rc load_nonzero_vec3(loader *L, uint32_t v, const char *key, vec3 *out)
{
    glint_rc rc = load_vec3(L, v, key, out);
    if (rc == GLINT_OK && v3_is_zero(*out))
        rc = load_fail(L, v, "%s must not be [0, 0, 0]", key);
    return rc;
}

/* A colour: a number (grey) or [r, g, b], no component below 0. */
glint_rc load_color(loader *L, uint32_t v, const char *key, vec3 *out)
{
    const ynode *n = load_node(L, v);
    char buf[SHOWN];
    if (n->kind == YNODE_NUMBER) {
        float g;
        glint_rc rc = load_nonneg(L, v, key, &g);
        if (rc == GLINT_OK)
            *out = v3s(g);
        return rc;
    }
    if (n->kind != YNODE_SEQ)
        return load_expected(L, v, "a number or [r, g, b]", key);
    float f[3];
    glint_rc rc = load_numbers(L, v, key, "[r, g, b]", 3, f);
    for (int i = 0; rc == GLINT_OK && i < 3; i++)
        if (!(f[i] >= 0.0f)) {
            uint32_t c = ydoc_item(load_doc(L), n, (uint32_t)i);
            rc = load_fail(L, c, "%s components must be >= 0 (got %s)", key, load_shown(L, c, buf));
        }
    if (rc == GLINT_OK)
        *out = v3(f[0], f[1], f[2]);
    return rc;
}

/* A string out of valid; what names the kind of thing ("object type"). */
glint_rc load_enum(loader *L, uint32_t v, const char *key, const char *what,
                          const char *const *valid, int *out)
{
    const ynode *n = load_node(L, v);
    if (n->kind != YNODE_STRING)
        return load_expected(L, v, "a string", key);
    const char *text = ydoc_text(load_doc(L), n);
    for (int i = 0; valid[i]; i++)
        if (is_word(valid[i], text, n->count)) {
            *out = i;
            return GLINT_OK;
        }
    char buf[SHOWN], hint[256];
    load_suggestion(valid, text, n->count, hint, sizeof hint);
    return load_fail(L, v, "unknown %s '%s'%s", what, load_shown(L, v, buf), hint);
}

/* A name (of a material or texture): a non-empty string or a number. */
glint_rc load_name(loader *L, uint32_t v, const char *what)
{
    const ynode *n = load_node(L, v);
    char got[SHOWN + 32];
    if (n->kind != YNODE_STRING && n->kind != YNODE_NUMBER) {
        ydoc_describe(load_doc(L), n, got, sizeof got);
        return load_fail(L, v, "a %s name must be a string, got %s", what, got);
    }
    if (n->count == 0)
        return load_fail(L, v, "a %s name must not be empty", what);
    return GLINT_OK;
}

/* A path written in the file: a non-empty string without NUL bytes. */
glint_rc load_path_key(loader *L, uint32_t v, const char *key)
{
    const ynode *n = load_node(L, v);
    if (n->kind != YNODE_STRING)
        return load_expected(L, v, "a file path", key);
    if (n->count == 0)
        return load_fail(L, v, "%s must not be empty", key);
    if (memchr(ydoc_text(load_doc(L), n), '\0', n->count))
        return load_fail(L, v, "%s must not contain a NUL character", key);
    return GLINT_OK;
}

/* A required vector field of a shape. */
glint_rc load_need_vec3(loader *L, uint32_t map, const char *key, const char *what, vec3 *out)
{
    uint32_t v;
    glint_rc rc = load_need(L, map, key, what, &v);
    return rc == GLINT_OK ? load_vec3(L, v, key, out) : rc;
}

glint_rc load_need_positive(loader *L, uint32_t map, const char *key, const char *what,
                              float *out)
{
    uint32_t v;
    glint_rc rc = load_need(L, map, key, what, &v);
    return rc == GLINT_OK ? load_positive(L, v, key, out) : rc;
}

/* Whether this file may set the setting: no file read before it did. */
bool load_claim(loader *L, unsigned bit)
{
    bool first = !(L->set & bit);
    L->set |= bit;
    return first;
}
glint_rc load_add_ref(loader *L, ref **refs, int *n, int *cap, int index, uint32_t name)
{
    int i = array_push((void **)refs, n, cap, sizeof **refs);
    if (i < 0)
        return err_nomem(L->err);
    (*refs)[i] = (ref){.index = index, .file = L->cur, .node = name};
    return GLINT_OK;
}

glint_rc load_list(loader *L, uint32_t v, const char *key,
                          glint_rc (*item)(loader *, uint32_t))
{
    const ynode *s = load_node(L, v);
    if (s->kind != YNODE_SEQ)
        return load_expected(L, v, "a list", key);
    for (uint32_t i = 0; i < s->count; i++) {
        glint_rc rc = item(L, ydoc_item(load_doc(L), s, i));
        if (rc != GLINT_OK)
            return rc;
    }
    return GLINT_OK;
}
