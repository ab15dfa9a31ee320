/* near: assertions that two numbers or vectors agree within a tolerance,
 * printing both sides when they do not. Shared by the unit tests. */
#ifndef GLINT_TESTS_NEAR_H
#define GLINT_TESTS_NEAR_H

#include <criterion/criterion.h>
#include <math.h>

#define ASSERT_NEAR(a, b, tol)                                                              \
    cr_assert(fabs((double)(a) - (double)(b)) <= (tol), "%s = %.9g, expected %.9g (tol %g)", \
              #a, (double)(a), (double)(b), (double)(tol))

#define ASSERT_V3_NEAR(v, ex, ey, ez, tol)                                                  \
    cr_assert(fabs((double)(v).x - (ex)) <= (tol) && fabs((double)(v).y - (ey)) <= (tol) && \
                  fabs((double)(v).z - (ez)) <= (tol),                                      \
              "%s = (%.9g, %.9g, %.9g), expected (%.9g, %.9g, %.9g) (tol %g)", #v,          \
              (double)(v).x, (double)(v).y, (double)(v).z, (double)(ex), (double)(ey),      \
              (double)(ez), (double)(tol))

#endif
