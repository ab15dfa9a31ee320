/* api_test: what the tests of the public API share. OK and REFUSED read
 * the including file's `static glint_error err`. */
#ifndef GLINT_TESTS_API_TEST_H
#define GLINT_TESTS_API_TEST_H

#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "glint.h"

/* Asserts a call succeeded, showing why not. */
#define OK(call) cr_assert_eq((call), GLINT_OK, "%s: %s", #call, err.msg)

/* Each call is refused with GLINT_ERR_INPUT and a message holding words. */
#define REFUSED(call, words)                                                                 \
    do {                                                                                     \
        err = (glint_error){0};                                                              \
        cr_expect_eq((call), GLINT_ERR_INPUT, "%s was not refused", #call);                  \
        cr_expect_eq(err.code, GLINT_ERR_INPUT, "%s", #call);                                \
        cr_expect_not_null(strstr(err.msg, words), "%s: '%s'", #call, err.msg);              \
    } while (0)

/* The same picture: every value within 1e-5 (relative above 1). Two
 * scenes built through different front ends may differ in the last bit of
 * a few values; anything larger is a real difference. */
static inline void test_expect_same_film(const glint_film *a, const glint_film *b)
{
    cr_assert_eq(a->width, b->width);
    cr_assert_eq(a->height, b->height);
    size_t n = (size_t)a->width * (size_t)a->height * 3, bad = 0, first = n;
    for (size_t i = 0; i < n; i++)
        if (!(fabsf(a->rgb[i] - b->rgb[i]) <= 1e-5f * fmaxf(1.0f, fabsf(a->rgb[i])))) {
            bad++;
            if (first == n)
                first = i;
        }
    cr_expect_eq(bad, 0, "the films differ in %zu of %zu values, first at pixel (%zu, %zu): %.9g vs %.9g",
                 bad, n, first / 3 % (size_t)a->width, first / 3 / (size_t)a->width,
                 first < n ? a->rgb[first] : 0.0, first < n ? b->rgb[first] : 0.0);
}

#endif
