/* yaml_fast against libyaml, event by event (type, scalar text and
 * style, tags and anchors, and the line and column where each scalar and
 * collection starts, which the tree keeps): on every scene in scenes/, on text
 * shaped like bench/tori.awk's, on hand-written corner cases, and on
 * 60,000 random mutations of them. Wherever the fast reader says it read
 * the text, libyaml must read it without error into the same events; text
 * outside its subset must be declined. */
#include <criterion/criterion.h>
#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

#include "core/rng.h"
#include "load/yaml_doc.h"
#include "load/yaml_fast.h"

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

static void add(evlist *l, const yaml_event_t *y)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 256;
        l->e = realloc(l->e, l->cap * sizeof *l->e);
        cr_assert_not_null(l->e);
    }
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
    l->e[l->n++] = e;
}

static void drop(evlist *l)
{
    for (size_t i = 0; i < l->n; i++)
        free(l->e[i].value);
    free(l->e);
    *l = (evlist){0};
}

static glint_rc take(void *ctx, const struct yaml_event_s *y)
{
    add(ctx, y);
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
