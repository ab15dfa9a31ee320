/* ydoc_check: node i of two parse trees the same (kind, flags, mark,
 * count, and a scalar's text), for the tests that compare trees built two
 * ways (test_yaml_fast.c, test_spare.c). */
#ifndef GLINT_TESTS_YDOC_CHECK_H
#define GLINT_TESTS_YDOC_CHECK_H

#include <criterion/criterion.h>

#include "load/yaml_doc.h"

static inline void expect_same_node(const ydoc *a, const ydoc *b, uint32_t i)
{
    const ynode *x = ydoc_node(a, i), *y = ydoc_node(b, i);
    cr_assert(x->kind == y->kind && x->flags == y->flags && x->line == y->line &&
                  x->col == y->col && x->count == y->count,
              "node %u", i);
    if (x->kind != YNODE_SEQ && x->kind != YNODE_MAP)
        cr_assert_str_eq(ydoc_text(a, x), ydoc_text(b, y), "node %u", i);
}

#endif
