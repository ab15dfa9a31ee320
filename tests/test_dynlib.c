/* Libraries opened at their first use (src/core/dynlib.h): a table filled
 * from a real library, the words when the library or a function is
 * missing, the first use from many threads at once. */
#include <criterion/criterion.h>
#include <math.h>
#include <pthread.h>
#include <string.h>

#include "core/dynlib.h"

/* ---- the mechanism, on libm -------------------------------------------------- */

#define M_FUNCTIONS(X, t) X(t, cos) X(t, ldexp)

static DYNLIB_STRUCT(M_FUNCTIONS) m_fn, missing_fn, shared_fn;
static dynlib m_lib = DYNLIB("libm.so.6", M_FUNCTIONS, m_fn);
static dynlib missing_lib = DYNLIB("libglint-no-such-library.so.7", M_FUNCTIONS, missing_fn);
static dynlib shared_lib = DYNLIB("libm.so.6", M_FUNCTIONS, shared_fn);

Test(dynlib, fills_the_table_once_and_calls_go_through_it)
{
    const char *why = "untouched";
    cr_assert(dynlib_open(&m_lib, &why));
    cr_expect_str_eq(why, "untouched", "why is left alone on success");
    cr_expect_eq(m_fn.cos(0.5), cos(0.5));
    cr_expect_eq(m_fn.ldexp(3.0, 4), 48.0);
    double (*first)(double) = m_fn.cos;
    cr_assert(dynlib_open(&m_lib, NULL));
    cr_expect_eq(m_fn.cos, first);
}

Test(dynlib, a_missing_library_is_said_by_its_name_and_stays_missing)
{
    const char *why = NULL;
    cr_assert_not(dynlib_open(&missing_lib, &why));
    cr_assert_not_null(why);
    cr_expect(strstr(why, "libglint-no-such-library.so.7"), "%s", why);
    cr_expect(strstr(why, "cannot open"), "%s", why);
    const char *again = NULL;
    cr_expect_not(dynlib_open(&missing_lib, &again));
    cr_expect_str_eq(again, why);
    cr_expect_null(missing_fn.cos);
}

Test(dynlib, a_missing_function_is_said_by_its_name)
{
    static struct {
        double (*cos)(double);
        void (*none)(void);
    } t;
    const dynlib_symbol symbols[] = {
        {"cos", &t.cos}, {"glint_no_such_function", &t.none}, {NULL, NULL}};
    dynlib lib = {.soname = "libm.so.6", .symbols = symbols};
    const char *why = NULL;
    cr_assert_not(dynlib_open(&lib, &why));
    cr_expect(strstr(why, "glint_no_such_function"), "%s", why);
    cr_expect(strstr(why, "libm.so.6"), "%s", why);
}

static void *open_and_call(void *arg)
{
    double *got = arg;
    *got = dynlib_open(&shared_lib, NULL) ? shared_fn.cos(1.0) : -2.0;
    return NULL;
}

/* Texture decoding runs a thread per file and the PNG writer a thread per
 * strip: their first uses can come at once. */
Test(dynlib, a_first_use_from_many_threads_at_once)
{
    enum { N = 16 };
    pthread_t th[N];
    double got[N];
    for (int i = 0; i < N; i++)
        cr_assert_eq(pthread_create(&th[i], NULL, open_and_call, &got[i]), 0);
    for (int i = 0; i < N; i++) {
        pthread_join(th[i], NULL);
        cr_expect_eq(got[i], cos(1.0), "thread %d", i);
    }
}
