/* core/spare: the one block of pages a process keeps between a scene's
 * parse tree and the film after it. Without a spare nothing changes; with
 * one, a block taken keeps the pages (and, grown, the bytes) it had,
 * aligned to a huge page, and comes back when given; a parse tree built
 * in it, outgrowing it, and freed gives the same nodes and leaves the
 * spare for the film; films made in it are the same pixels. Each test
 * runs in a process of its own (Criterion), so each starts without a
 * spare. */
#include <criterion/criterion.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/spare.h"
#include "glint.h"
#include "load/yaml_doc.h"
#include "ydoc_check.h"

#define MIB ((size_t)1 << 20)

static bool huge_aligned(const void *p) { return ((uintptr_t)p & (2 * MIB - 1)) == 0; }

Test(spare, none_until_made)
{
    cr_assert_null(spare_take(MIB, NULL));
    cr_assert_not(spare_give(NULL));
    int x;
    cr_assert_not(spare_give(&x), "a pointer that is not from the spare is not taken back");
    unsigned char *p = spare_calloc(3 * MIB, 2); /* array_calloc_big_on's block */
    cr_assert_not_null(p);
    cr_assert_eq(spare_size(p), 0);
    for (size_t i = 0; i < 3 * MIB; i += 4093)
        cr_assert_eq(p[i], 0);
    spare_free(p); /* free() */
}

Test(spare, made_once_taken_once_given_back)
{
    char *s = spare_make(3 * MIB);
    cr_assert_not_null(s);
    cr_assert(huge_aligned(s));
    cr_assert_null(spare_make(MIB), "a second spare while there is one");
    size_t had = 0;
    char *p = spare_take(MIB, &had);
    cr_assert_eq(p, s);
    cr_assert_eq(had, 4 * MIB, "3 MiB in whole huge pages");
    cr_assert_eq(spare_size(p), 4 * MIB);
    cr_assert_null(spare_take(MIB, NULL), "the spare is out");
    memset(p, 0x5a, 4 * MIB);
    cr_assert(spare_give(p));
    cr_assert_not(spare_give(p), "given back twice");
    cr_assert_eq(spare_take(2 * MIB, NULL), s, "the same pages again");
}

Test(spare, grown_keeps_its_bytes_and_alignment)
{
    unsigned char *s = spare_make(4 * MIB);
    cr_assert_not_null(s);
    for (size_t i = 0; i < 4 * MIB; i++)
        s[i] = (unsigned char)(i * 7 + 3);
    size_t had = 0;
    unsigned char *p = spare_take(11 * MIB, &had);
    cr_assert_not_null(p);
    cr_assert_eq(had, 4 * MIB);
    cr_assert_eq(spare_size(p), 12 * MIB);
    cr_assert(huge_aligned(p), "moved to %p", (void *)p);
    for (size_t i = 0; i < 4 * MIB; i++)
        cr_assert_eq(p[i], (unsigned char)(i * 7 + 3), "byte %zu", i);
    for (size_t i = 4 * MIB; i < 12 * MIB; i += 4096)
        cr_assert_eq(p[i], 0, "fresh byte %zu", i);
    cr_assert(spare_give(p));
}

Test(spare, calloc_clears_what_the_spare_held)
{
    unsigned char *s = spare_make(8 * MIB);
    cr_assert_not_null(s);
    cr_assert_eq(spare_take(8 * MIB, NULL), s);
    memset(s, 0xff, 8 * MIB);
    cr_assert(spare_give(s));
    unsigned char *p = spare_calloc(5 * MIB + 17, 2);
    cr_assert_eq(p, s);
    for (size_t i = 0; i < 5 * MIB + 17; i++)
        cr_assert_eq(p[i], 0, "byte %zu", i);
    spare_free(p);
    cr_assert_eq(spare_take(MIB, NULL), s, "freed, it is the spare again");
}

/* A spare never taken is the kernel's zeros, which spare_calloc only
 * maps; a block taken may then be written as far as spare_size reports
 * (a parse tree's, or a film's), and the next spare_calloc clears all of
 * that. */
Test(spare, calloc_clears_every_page_handed_out_before)
{
    unsigned char *s = spare_make(16 * MIB);
    cr_assert_not_null(s);
    unsigned char *film = spare_calloc(12 * MIB + 5, 2); /* never taken: mapped only */
    cr_assert_eq(film, s);
    for (size_t i = 0; i < 12 * MIB + 5; i += 61)
        cr_assert_eq(film[i], 0, "byte %zu", i);
    cr_assert_eq(spare_size(film), 16 * MIB);
    memset(film, 0x3c, spare_size(film));
    spare_free(film);
    film = spare_calloc(14 * MIB, 1);
    cr_assert_eq(film, s);
    for (size_t i = 0; i < 14 * MIB; i += 61)
        cr_assert_eq(film[i], 0, "byte %zu of the second film", i);
    spare_free(film);
    unsigned char *tree = spare_take(3 * MIB, NULL);
    cr_assert_eq(tree, s);
    memset(tree, 0xa5, spare_size(tree));
    cr_assert(spare_give(tree));
    film = spare_calloc(16 * MIB, 2);
    cr_assert_eq(film, s);
    for (size_t i = 0; i < 16 * MIB; i += 61)
        cr_assert_eq(film[i], 0, "byte %zu after a tree", i);
    spare_free(film);
}

Test(spare, small_blocks_leave_it)
{
    char *s = spare_make(4 * MIB);
    cr_assert_not_null(s);
    char *p = spare_calloc(1000, 1);
    cr_assert_not_null(p);
    cr_assert_neq(p, s);
    spare_free(p);
    cr_assert_eq(spare_take(MIB, NULL), s);
}

Test(spare, one_block_at_most)
{
    char *a = spare_make(2 * MIB);
    cr_assert_not_null(a);
    cr_assert_eq(spare_take(MIB, NULL), a);
    cr_assert_null(spare_make(6 * MIB), "a second block while the first is taken");
    cr_assert(spare_give(a));
    cr_assert_null(spare_make(6 * MIB), "a second block while the first is kept");
    cr_assert_eq(spare_take(MIB, NULL), a);
}

/* A flow sequence of n small numbers: a node for every 2 bytes, more than
 * the tree's arrays are made for up front (a node a 5 bytes), so that
 * every array outgrows its room in the spare. */
static char *numbers(size_t n, size_t *len)
{
    char *t = malloc(2 * n + 16);
    cr_assert_not_null(t);
    size_t k = 0;
    t[k++] = '[';
    for (size_t i = 0; i < n; i++) {
        t[k++] = (char)('0' + i % 10);
        t[k++] = ',';
    }
    t[k - 1] = ']';
    t[k++] = '\n';
    t[k] = 0;
    *len = k;
    return t;
}

Test(spare, a_parse_tree_outgrows_it_and_gives_it_back)
{
    if (YDOC_SANITIZED)
        cr_skip_test("under AddressSanitizer the tree keeps to the heap, where overruns show");
    char *s = spare_make(4 * MIB);
    cr_assert_not_null(s);
    size_t len, n = 1500000;
    char *text = numbers(n, &len);
    ydoc *d = NULL;
    glint_error err = {0};
    cr_assert_eq(ydoc_parse(text, len, "numbers", &d, &err), GLINT_OK, "%s", err.msg);
    cr_assert_geq(spare_size(d->block), len * 5, "the tree was made in the spare, grown");
    cr_assert_not(ydoc_borrowed(d, d->nodes), "the nodes outgrew it");
    cr_assert_not(ydoc_borrowed(d, d->kids), "the items outgrew it");
    const ynode *root = ydoc_node(d, d->root);
    cr_assert_eq(root->kind, YNODE_SEQ);
    cr_assert_eq(root->count, n);
    for (uint32_t i = 0; i < n; i += 997) {
        const ynode *x = ydoc_node(d, ydoc_item(d, root, i));
        cr_assert_eq(x->kind, YNODE_NUMBER);
        char want[2] = {(char)('0' + i % 10), 0};
        cr_assert_str_eq(ydoc_text(d, x), want, "item %u", i);
        cr_assert_eq(x->col, 2 + 2 * i);
    }
    cr_assert_null(spare_take(MIB, NULL), "the tree holds it");
    ydoc_free(d);
    cr_assert_not_null(spare_take(MIB, NULL), "freed, the tree gave it back");
    free(text);
}

/* A tree built in the spare is the tree built on the heap: the same
 * nodes (kind, flags, mark, count), texts and items, for a scene-like
 * text of 2 MB with every kind of scalar (the other test above has its
 * arrays outgrow the spare). */
Test(spare, trees_in_it_are_the_trees_on_the_heap)
{
    if (YDOC_SANITIZED)
        cr_skip_test("under AddressSanitizer the tree keeps to the heap, where overruns show");
    static const char *const items[] = {
        "  - {type: torus, center: [0, -1.5, .5], on: true, off: FALSE, none: ~, x: Null}\n",
        "  - {a: 1, b: 3, list: [k: v, 0x1F, 0o17, -.inf, .NaN, 1e5, word]}\n",
        "  - {name: 'a quoted name, with: commas', n: [1, 2], s: \"esc\\tape\"}\n",
    };
    size_t cap = (size_t)3 << 20, len = 0;
    char *text = malloc(cap);
    cr_assert_not_null(text);
    len += (size_t)snprintf(text, cap, "objects:\n");
    for (int i = 0; len + 400 < cap - (1 << 20); i++)
        len += (size_t)snprintf(text + len, cap - len, "%s", items[i % 3]);
    cr_assert_not_null(spare_make(8 * MIB));
    ydoc *a = NULL, *b = NULL;
    glint_error err = {0};
    cr_assert_eq(ydoc_parse(text, len, "a", &a, &err), GLINT_OK, "%s", err.msg);
    cr_assert_gt(spare_size(a->block), 0, "the first tree is in the spare");
    cr_assert_eq(ydoc_parse(text, len, "b", &b, &err), GLINT_OK, "%s", err.msg);
    cr_assert_null(b->block, "the second, while the first holds it, is on the heap");
    cr_assert_eq(a->nnodes, b->nnodes);
    cr_assert_eq(a->nkids, b->nkids);
    cr_assert_eq(a->root, b->root);
    for (uint32_t i = 0; i < a->nnodes; i++)
        expect_same_node(a, b, i);
    cr_assert_eq(memcmp(a->kids, b->kids, a->nkids * sizeof *a->kids), 0);
    ydoc_free(a);
    ydoc_free(b);
    cr_assert_not_null(spare_take(MIB, NULL), "freed, the first tree gave it back");
    free(text);
}

/* The library's face of it: glint_memory_spare, then films rendered in
 * it are the pixels of one rendered without it, and each freed film
 * leaves it for the next. */
Test(spare, films_in_it_are_the_same_pixels)
{
    glint_scene *s = NULL;
    glint_error err = {0};
    cr_assert_eq(glint_scene_builtin(&s, &err), GLINT_OK, "%s", err.msg);
    glint_settings st;
    glint_scene_settings(s, &st, NULL);
    st.width = 320;
    st.height = 240; /* 900 KiB: below 1 MiB a film leaves the spare alone */
    st.threads = 2;
    glint_film small = {0};
    char *spare = glint_memory_spare(8 * MIB);
    cr_assert_not_null(spare);
    cr_assert_null(glint_memory_spare(8 * MIB));
    cr_assert_eq(glint_render(s, &st, NULL, &small, NULL, &err), GLINT_OK, "%s", err.msg);
    cr_assert_neq((char *)small.rgb, spare);
    glint_film_free(&small);
    st.width = 640;
    st.height = 480; /* 3.5 MiB */
    glint_film a = {0}, b = {0};
    glint_settings one = st;
    cr_assert_eq(glint_render(s, &one, NULL, &a, NULL, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq((char *)a.rgb, spare, "the film took the spare");
    cr_assert_eq(glint_render(s, &one, NULL, &b, NULL, &err), GLINT_OK, "%s", err.msg);
    cr_assert_neq((char *)b.rgb, spare, "a second film at once has pages of its own");
    cr_assert_eq(memcmp(a.rgb, b.rgb, sizeof(float) * 3 * 640 * 480), 0);
    glint_film_free(&a);
    glint_film c = {0};
    cr_assert_eq(glint_render(s, &one, NULL, &c, NULL, &err), GLINT_OK, "%s", err.msg);
    cr_assert_eq((char *)c.rgb, spare, "freed, the first film left it for the next");
    cr_assert_eq(memcmp(c.rgb, b.rgb, sizeof(float) * 3 * 640 * 480), 0);
    glint_film_free(&b);
    glint_film_free(&c);
    glint_scene_free(s);
}
