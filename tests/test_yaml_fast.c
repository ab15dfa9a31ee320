/* yaml_fast against libyaml, event by event (type, scalar text and
 * style, tags and anchors, and the line and column where each scalar and
 * collection starts, which the tree keeps): on every scene in scenes/, on text
 * shaped like bench/tori.awk's, on hand-written corner cases, and on
 * 60,000 random mutations of them. Wherever the fast reader says it read
 * the text, libyaml must read it without error into the same events; text
 * outside its subset must be declined. */
#include <criterion/criterion.h>
#include <glob.h>
#include <regex.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

#include "core/rng.h"
#include "load/yaml_doc.h"
#include "load/yaml_fast.h"
#include "ydoc_check.h"

typedef struct ev {
    int type;
    size_t line, col;
    char *value; /* scalars: the text; NULL otherwise */
    int style;
    bool tagged, anchored;
} ev;

typedef struct evlist {
    ev *e;
    size_t n, cap;
} evlist;

static void append(evlist *l, ev e)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 256;
        l->e = realloc(l->e, l->cap * sizeof *l->e);
        cr_assert_not_null(l->e);
    }
    l->e[l->n++] = e;
}

static void add(evlist *l, const yaml_event_t *y)
{
    ev e = {(int)y->type, y->start_mark.line, y->start_mark.column, NULL, 0, false, false};
    if (y->type == YAML_SCALAR_EVENT) {
        e.value = strndup((const char *)y->data.scalar.value, y->data.scalar.length);
        e.style = (int)y->data.scalar.style;
        e.tagged = y->data.scalar.tag != NULL;
        e.anchored = y->data.scalar.anchor != NULL;
    } else if (y->type == YAML_MAPPING_START_EVENT) {
        e.tagged = y->data.mapping_start.tag != NULL;
        e.anchored = y->data.mapping_start.anchor != NULL;
    } else if (y->type == YAML_SEQUENCE_START_EVENT) {
        e.tagged = y->data.sequence_start.tag != NULL;
        e.anchored = y->data.sequence_start.anchor != NULL;
    }
    append(l, e);
}

static void drop(evlist *l)
{
    for (size_t i = 0; i < l->n; i++)
        free(l->e[i].value);
    free(l->e);
    *l = (evlist){0};
}

/* The fast reader's events, which are plain, untagged and unanchored. */
static glint_rc take(void *ctx, const yfast_event *y)
{
    ev e = {y->type, y->line, y->column, NULL, 0, false, false};
    if (y->type == YAML_SCALAR_EVENT) {
        cr_assert_not_null(y->text);
        e.value = strndup(y->text, y->len);
        e.style = YAML_PLAIN_SCALAR_STYLE;
    }
    append(ctx, e);
    return GLINT_OK;
}

/* libyaml's events; false on a parse error. */
static bool by_libyaml(const char *text, size_t len, evlist *l)
{
    yaml_parser_t p;
    cr_assert(yaml_parser_initialize(&p));
    yaml_parser_set_input_string(&p, (const unsigned char *)text, len);
    bool ok = true, done = false;
    while (!done) {
        yaml_event_t y;
        if (!yaml_parser_parse(&p, &y)) {
            ok = false;
            break;
        }
        add(l, &y);
        done = y.type == YAML_STREAM_END_EVENT;
        yaml_event_delete(&y);
    }
    yaml_parser_delete(&p);
    return ok;
}

/* The fast reader's verdict on text; when it read it, the events must be
 * libyaml's. */
static yfast_result check(const char *text, size_t len, const char *what)
{
    evlist fast = {0}, slow = {0};
    yfast_result r = yfast_read(text, len, take, &fast);
    cr_assert_neq(r, YFAST_REFUSED, "%s", what);
    if (r == YFAST_DONE) {
        cr_assert(by_libyaml(text, len, &slow), "%s: read, but libyaml refuses it:\n%.*s", what,
                  (int)len, text);
        cr_assert_eq(fast.n, slow.n, "%s: %zu events, libyaml %zu:\n%.*s", what, fast.n, slow.n,
                     (int)len, text);
        for (size_t i = 0; i < fast.n; i++) {
            const ev *a = &fast.e[i], *b = &slow.e[i];
            /* the marks the tree keeps: where scalars and collections start */
            bool marked = a->type == YAML_SCALAR_EVENT || a->type == YAML_MAPPING_START_EVENT ||
                          a->type == YAML_SEQUENCE_START_EVENT;
            bool same = a->type == b->type &&
                        (!marked || (a->line == b->line && a->col == b->col)) &&
                        a->style == b->style && a->tagged == b->tagged &&
                        a->anchored == b->anchored && !a->value == !b->value &&
                        (!a->value || strcmp(a->value, b->value) == 0);
            cr_assert(same,
                      "%s: event %zu: type %d at %zu:%zu '%s', libyaml type %d at %zu:%zu '%s'",
                      what, i, a->type, a->line, a->col, a->value ? a->value : "", b->type,
                      b->line, b->col, b->value ? b->value : "");
        }
    }
    drop(&fast);
    drop(&slow);
    return r;
}

static const char *const accepted[] = {
    "",
    "# only a comment\n\n",
    "a: 1\n",
    "a: 1",
    "a: 1   \nb: two words  # a comment\n\n# another\nc: -3.5e-2\n",
    "image: {width: 1920, height: 1080, samples: 1, depth: 3}\n"
    "camera: {eye: [0, 28, 52], look_at: [0, 0, -8], fov: 70}\n",
    "objects:\n  - {type: torus, center: [0, 0, 0], major_radius: 0.32, transform: [rotate_x: 12, "
    "rotate_y: 300, translate: [-49.5, 0.42, -48.5]]}\n"
    "  - {type: csg, op: difference, objects: [{type: box, min: [-0.4, -0.4, -0.4]}, {}]}\n",
    "objects:\n- type: sphere\n  center: [0, 1, 0]\n  radius: 1\n- type: plane\n",
    "a:\n  b:\n    c: 1\n    d: [1, 2]\n  e: x\nf: y\n",
    "list:\n  - 1\n  - 2 # two\n  -   three\nafter: []\n",
    "seq:\n- a\n- b\n",
    "- 1\n- [a, b]\n- k: v\n  l: w\n",
    "x: [a: 1, [b, c], {d: e}, f]\n",
    "x: {a: [], b: {}, c: true, d: ~, e: null, f: .inf, g: -.5}\n",
    "key.with-dots_and+plus: 0x1F\n",
    "url: http://example.com/a\n",
    "a: b:c\n",
    "just a scalar\n",
    "[1, 2, 3]\n",
    "  indented: 1\n  again: 2\n",
};

static const char *const declined[] = {
    "a: 'quoted'\n", "a: \"quoted\"\n", "a: &x 1\nb: *x\n", "a: !!str 1\n", "<<: {a: 1}\n",
    "a: |\n  block\n", "a: >\n  folded\n", "a: multi\n  line\n", "a: [1,\n  2]\n", "a:\n",
    "---\na: 1\n", "a: 1\n...\n", "%YAML 1.2\n---\na: 1\n", "a: 1\n---\nb: 2\n", "a:\tb\n",
    "a: 1\r\n", "a: [1, 2,]\n", "a: {b}\n", "? a\n: b\n", "a: caf\xc3\xa9\n", "a: [1]#c\n",
    "a: b#c\n", "-\n  a\n", "- - a\n", "a: x, y\n", "\"k\": 1\n",
};

Test(yaml_fast, reads_the_plain_subset_as_libyaml_does)
{
    for (size_t i = 0; i < sizeof accepted / sizeof *accepted; i++) {
        char what[32];
        snprintf(what, sizeof what, "accepted[%zu]", i);
        cr_assert_eq(check(accepted[i], strlen(accepted[i]), what), YFAST_DONE,
                     "%s was declined:\n%s", what, accepted[i]);
    }
}

Test(yaml_fast, declines_what_it_does_not_read)
{
    for (size_t i = 0; i < sizeof declined / sizeof *declined; i++) {
        char what[32];
        snprintf(what, sizeof what, "declined[%zu]", i);
        cr_assert_eq(check(declined[i], strlen(declined[i]), what), YFAST_DECLINED,
                     "%s was read:\n%s", what, declined[i]);
    }
}

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    cr_assert_not_null(f, "%s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *t = malloc((size_t)n + 1);
    cr_assert_not_null(t);
    cr_assert_eq(fread(t, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    *len = (size_t)n;
    return t;
}

Test(yaml_fast, every_scene_reads_as_libyaml_reads_it)
{
    glob_t g;
    cr_assert_eq(glob(GLINT_SOURCE_DIR "/scenes/*.yaml", 0, NULL, &g), 0);
    cr_assert_gt(g.gl_pathc, 10);
    size_t read = 0;
    for (size_t i = 0; i < g.gl_pathc; i++) {
        size_t len;
        char *t = slurp(g.gl_pathv[i], &len);
        read += check(t, len, g.gl_pathv[i]) == YFAST_DONE;
        free(t);
    }
    globfree(&g);
    cr_assert_gt(read, 0, "no scene in the subset");
}

/* Random insertions, deletions and replacements of YAML's structural
 * characters in the accepted texts. */
Test(yaml_fast, mutated_texts_read_as_libyaml_reads_them_or_are_declined)
{
    static const char alphabet[] = " \n:-,[]{}#.a1_";
    rng g = rng_seed(2024, 7);
    size_t read = 0, n = sizeof accepted / sizeof *accepted;
    for (int k = 0; k < 60000; k++) {
        const char *src = accepted[rng_u32(&g) % n];
        char buf[512];
        size_t len = strlen(src);
        cr_assert_lt(len + 4, sizeof buf);
        memcpy(buf, src, len);
        for (int m = 1 + (int)(rng_u32(&g) % 3); m > 0; m--) {
            size_t at = len ? rng_u32(&g) % (len + 1) : 0;
            char c = alphabet[rng_u32(&g) % (sizeof alphabet - 1)];
            switch (rng_u32(&g) % 3) {
            case 0: /* insert */
                memmove(buf + at + 1, buf + at, len - at);
                buf[at] = c;
                len++;
                break;
            case 1: /* delete */
                if (at < len) {
                    memmove(buf + at, buf + at + 1, len - at - 1);
                    len--;
                }
                break;
            default: /* replace */
                if (at < len)
                    buf[at] = c;
            }
        }
        char what[32];
        snprintf(what, sizeof what, "mutation %d", k);
        read += check(buf, len, what) == YFAST_DONE;
    }
    cr_assert_gt(read, 10000);
}

/* Through ydoc_parse: a text the fast reader reads and the same text made
 * to go through libyaml (by a quoted value at its end) give the same tree,
 * marks included. */
Test(yaml_fast, trees_agree_through_ydoc_parse)
{
    const char *fast = "objects:\n  - {type: torus, transform: [rotate_x: 3, translate: [1, 2, "
                       "3]]}\n  - type: box\n    min: [-1, -1, -1]\nname: x\n";
    const char *slow = "objects:\n  - {type: torus, transform: [rotate_x: 3, translate: [1, 2, "
                       "3]]}\n  - type: box\n    min: [-1, -1, -1]\nname: 'x'\n";
    ydoc *a = NULL, *b = NULL;
    glint_error err = {0};
    cr_assert_eq(ydoc_parse(fast, strlen(fast), "a", &a, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(ydoc_parse(slow, strlen(slow), "b", &b, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(a->nnodes, b->nnodes);
    for (uint32_t i = 0; i < a->nnodes; i++) {
        const ynode *x = ydoc_node(a, i), *y = ydoc_node(b, i);
        cr_assert(x->kind == y->kind && x->line == y->line && x->col == y->col &&
                      x->count == y->count,
                  "node %u", i);
        if (x->kind != YNODE_SEQ && x->kind != YNODE_MAP)
            cr_assert_str_eq(ydoc_text(a, x), ydoc_text(b, y));
    }
    ydoc_free(a);
    ydoc_free(b);
}

/* A document of thousands of lines, whose arrays grow many times while
 * the fast reader's scalars go straight into them, gives the tree libyaml
 * gives it: every node (kind, flags, mark, text), every kid. */
Test(yaml_fast, big_trees_agree_through_ydoc_parse)
{
    static const char *const lines[] = {
        "  - {type: torus, center: [0, -1.5, .5], on: true, off: FALSE, none: ~, x: Null}\n",
        "  - {a: 1, b: 3, list: [k: v, 0x1F, 0o17, -.inf, .NaN, 1e5, word]}\n",
        "  - name: some_longer_words_here\n    n: [12345678, -0.0000001, 3.402823e38]\n",
    };
    size_t cap = 4000 * 120, len = 0;
    char *fast = malloc(cap), *slow = malloc(cap);
    cr_assert(fast && slow);
    len += (size_t)snprintf(fast + len, cap - len, "objects:\n");
    for (int i = 0; i < 4000; i++)
        len += (size_t)snprintf(fast + len, cap - len, "%s", lines[i % 3]);
    memcpy(slow, fast, len);
    size_t flen = len + (size_t)snprintf(fast + len, cap - len, "z: q\n");
    size_t slen = len + (size_t)snprintf(slow + len, cap - len, "z: 'q'\n");
    cr_assert_eq(check(fast, flen, "big"), YFAST_DONE, "the fast reader reads it");
    ydoc *a = NULL, *b = NULL;
    glint_error err = {0};
    cr_assert_eq(ydoc_parse(fast, flen, "a", &a, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(ydoc_parse(slow, slen, "b", &b, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq(a->nnodes, b->nnodes);
    cr_assert_gt(a->nnodes, 40000);
    for (uint32_t i = 0; i + 1 < a->nnodes; i++) { /* the last is 'q' */
        expect_same_node(a, b, i);
        const ynode *x = ydoc_node(a, i), *y = ydoc_node(b, i);
        if (x->kind == YNODE_SEQ || x->kind == YNODE_MAP)
            cr_assert_eq(x->first, y->first, "node %u", i);
    }
    cr_assert_eq(a->nkids, b->nkids);
    cr_assert(memcmp(a->kids, b->kids, a->nkids * sizeof *a->kids) == 0);
    ydoc_free(a);
    ydoc_free(b);
    free(fast);
    free(slow);
}

/* A duplicate key, read by the fast reader and refused by the tree, gets
 * libyaml's path's message, naming the place. */
Test(yaml_fast, a_refused_tree_gets_the_usual_message)
{
    const char *text = "a: 1\nb: [1, 2]\na: 3\n";
    ydoc *d = NULL;
    glint_error err = {0};
    cr_assert_eq(ydoc_parse(text, strlen(text), "t.yaml", &d, &err), GLINT_ERR_INPUT);
    cr_assert(strncmp(err.msg, "t.yaml:3:1:", 11) == 0, "%s", err.msg);
}

/* ---- plain scalar typing ---------------------------------------------- */

/* The YAML 1.2 core schema's forms as regular expressions
 * (https://yaml.org/spec/1.2.2/#1032-tag-resolution), the oracle for
 * ydoc_plain_kind's quick paths. */
static const char *const null_re = "^(~|null|Null|NULL|)$";
static const char *const true_re = "^(true|True|TRUE)$";
static const char *const false_re = "^(false|False|FALSE)$";
static const char *const int_re = "^([-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+)$";
static const char *const float_re = "^([-+]?(\\.[0-9]+|[0-9]+(\\.[0-9]*)?)([eE][-+]?[0-9]+)?|"
                                    "[-+]?\\.(inf|Inf|INF)|\\.(nan|NaN|NAN))$";

typedef struct oracle {
    regex_t null, yes, no, integer, real;
} oracle;

static void oracle_init(oracle *o)
{
    cr_assert_eq(regcomp(&o->null, null_re, REG_EXTENDED | REG_NOSUB), 0);
    cr_assert_eq(regcomp(&o->yes, true_re, REG_EXTENDED | REG_NOSUB), 0);
    cr_assert_eq(regcomp(&o->no, false_re, REG_EXTENDED | REG_NOSUB), 0);
    cr_assert_eq(regcomp(&o->integer, int_re, REG_EXTENDED | REG_NOSUB), 0);
    cr_assert_eq(regcomp(&o->real, float_re, REG_EXTENDED | REG_NOSUB), 0);
}

static void oracle_free(oracle *o)
{
    regfree(&o->null);
    regfree(&o->yes);
    regfree(&o->no);
    regfree(&o->integer);
    regfree(&o->real);
}

static bool matches(const regex_t *re, const char *s) { return regexec(re, s, 0, NULL, 0) == 0; }

/* ydoc_plain_kind on s (NUL-terminated, no NUL inside) against the oracle. */
static void check_kind(const oracle *o, const char *s)
{
    size_t len = strlen(s);
    bool is_true, is_int;
    ynode_kind k = ydoc_plain_kind(s, len, &is_true, &is_int);
    bool integer = len <= 256 && matches(&o->integer, s);
    bool number = len <= 256 && (integer || matches(&o->real, s));
    ynode_kind want = matches(&o->null, s)                          ? YNODE_NULL
                      : matches(&o->yes, s) || matches(&o->no, s) ? YNODE_BOOL
                      : number                                     ? YNODE_NUMBER
                                                                   : YNODE_STRING;
    cr_assert_eq(k, want, "'%s': kind %d, the core schema says %d", s, (int)k, (int)want);
    cr_assert_eq(is_true, k == YNODE_BOOL && matches(&o->yes, s), "'%s': is_true", s);
    cr_assert_eq(is_int, k == YNODE_NUMBER && integer, "'%s': is_int", s);
}

/* Every text of up to three characters over the characters the forms are
 * made of, and random longer ones, typed as the core schema types them. */
Test(yaml_scalar, plain_kinds_follow_the_core_schema)
{
    static const char alphabet[] = "0179.+-eExXoaAfFnNtTuUlLrRsSiI~ _";
    const size_t na = sizeof alphabet - 1;
    oracle o;
    oracle_init(&o);
    char s[64];
    check_kind(&o, "");
    for (size_t a = 0; a < na; a++) {
        s[0] = alphabet[a], s[1] = '\0';
        check_kind(&o, s);
        for (size_t b = 0; b < na; b++) {
            s[1] = alphabet[b], s[2] = '\0';
            check_kind(&o, s);
            for (size_t c = 0; c < na; c++) {
                s[2] = alphabet[c], s[3] = '\0';
                check_kind(&o, s);
            }
        }
    }
    static const char *const tricky[] = {
        "-.5",   "+.5",   ".5",    "5.",    "-5.",   "0x",     "0o",    "0x1F",  "0o17",
        "0o8",   "0xg",   "007",   "+0",    "-0.0",  "1e5",    "1E+5",  "1.e-5", ".e5",
        "1.2.3", "--1",   "+-1",   "1-",    ".inf",  "-.Inf",  "+.INF", ".nan",  "-.nan",
        ".NaN",  "true",  "True",  "tRue",  "TRUE",  "false",  "FALSE", "fALSE", "null",
        "nULL",  "~",     "~~",    "type",  "torus", "normal", "Null",  "nulls", "-49.5",
        "0.42",  "0.320", "117",   "-1",    "1_000", "1 2",    "+",     "-",     ".",
    };
    for (size_t i = 0; i < sizeof tricky / sizeof *tricky; i++)
        check_kind(&o, tricky[i]);
    rng g = rng_seed(99, 4);
    static const char digits[] = "0123456789.-+eE";
    for (int k = 0; k < 50000; k++) {
        size_t n = 1 + rng_u32(&g) % 12;
        for (size_t i = 0; i < n; i++)
            s[i] = rng_u32(&g) % 8 ? digits[rng_u32(&g) % 11] : digits[rng_u32(&g) % 15];
        s[n] = '\0';
        check_kind(&o, s);
    }
    char longer[300];
    memset(longer, '7', sizeof longer - 1);
    longer[sizeof longer - 1] = '\0';
    check_kind(&o, longer); /* beyond 256 characters numbers are strings */
    longer[256] = '\0';
    check_kind(&o, longer);
    oracle_free(&o);
}

/* Mappings that stand as read and mappings that need the general way
 * (repeats, merge keys, more than 16 pairs, keys alike but for their first
 * or last byte) give the same trees through both readers. */
Test(yaml_scalar, mappings_read_alike_through_both_readers)
{
    static const char *const texts[] = {
        "a: {ab: 1, bb: 2, ab1: 3}\n",
        "a: {k1: 1, k2: 2, k3: 3, k4: 4, k5: 5, k6: 6, k7: 7, k8: 8, k9: 9, k10: 10, k11: 11, "
        "k12: 12, k13: 13, k14: 14, k15: 15, k16: 16, k17: 17}\n",
        "a: {x: 1, y: 2}\nb: [{x: 1}, {y: 2, x: 3}]\n",
        "a: {<<: {b: 1}, c: 2}\n",
    };
    for (size_t i = 0; i < sizeof texts / sizeof *texts; i++) {
        size_t len = strlen(texts[i]);
        char slow[512];
        cr_assert_lt(len + 16, sizeof slow);
        snprintf(slow, sizeof slow, "%sz: 'q'\n", texts[i]); /* the quotes make it libyaml's */
        char fast[512];
        snprintf(fast, sizeof fast, "%sz: q\n", texts[i]);
        ydoc *a = NULL, *b = NULL;
        glint_error err = {0};
        cr_assert_eq(ydoc_parse(fast, strlen(fast), "a", &a, &err), GLINT_OK, "%s", err.msg);
        cr_assert_eq(ydoc_parse(slow, strlen(slow), "b", &b, &err), GLINT_OK, "%s", err.msg);
        cr_assert_eq(a->nnodes, b->nnodes, "text %zu", i);
        cr_assert_eq(a->nkids, b->nkids, "text %zu", i);
        for (uint32_t n = 0; n < a->nnodes; n++) {
            const ynode *x = ydoc_node(a, n), *y = ydoc_node(b, n);
            cr_assert(x->kind == y->kind && x->flags == y->flags && x->line == y->line &&
                          x->col == y->col && x->count == y->count && x->first == y->first,
                      "text %zu, node %u", i, n);
        }
        cr_assert(memcmp(a->kids, b->kids, a->nkids * sizeof *a->kids) == 0, "text %zu", i);
        ydoc_free(a);
        ydoc_free(b);
    }
    static const char *const refused[] = {"a: {ab: 1, ab: 2}\n", "a: {k: 1, j: 2, k: 3}\n"};
    for (size_t i = 0; i < sizeof refused / sizeof *refused; i++) {
        ydoc *d = NULL;
        glint_error err = {0};
        cr_assert_eq(ydoc_parse(refused[i], strlen(refused[i]), "t.yaml", &d, &err),
                     GLINT_ERR_INPUT, "%s", refused[i]);
        cr_assert(strstr(err.msg, "duplicate key") != NULL, "%s", err.msg);
    }
}
