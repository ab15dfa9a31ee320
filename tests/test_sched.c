/* The batch scheduler of glint-mpi (src/dist/sched.h): every tile handed
 * out once, in order, in batches that shrink as the image fills, held
 * between the smallest and the largest size. */
#include <criterion/criterion.h>

#include "dist/sched.h"

static void check_run(int ntiles, int ranks, int lo, int hi)
{
    sched s;
    sched_init(&s, ntiles, ranks, lo, hi);
    int next = 0, last = hi + 1, first, n, batches = 0;
    while ((n = sched_take(&s, &first)) > 0) {
        cr_assert_eq(first, next, "%d tiles, %d ranks: batch starts at %d, not %d", ntiles, ranks, first, next);
        cr_assert_leq(n, hi);
        cr_assert(n >= lo || first + n == ntiles, "a batch of %d below the smallest (%d) before the end", n, lo);
        cr_assert_leq(n, last, "batches never grow (%d after %d)", n, last);
        int left = ntiles - first;
        cr_assert(n <= lo || n <= (left + SCHED_FACTOR * ranks - 1) / (SCHED_FACTOR * ranks),
                  "a batch of %d takes more than its share of %d tiles left among %d ranks", n, left, ranks);
        next += n;
        last = n;
        batches++;
    }
    cr_assert_eq(next, ntiles, "every tile handed out");
    cr_assert_eq(sched_take(&s, &first), 0, "and nothing after");
    cr_assert_geq(batches, ntiles > 0 ? 1 : 0);
}

Test(sched, every_tile_once_in_shrinking_batches)
{
    int sizes[] = {0, 1, 7, 130, 8160, 32400};
    int ranks[] = {1, 2, 3, 16, 64, 1024};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++)
        for (size_t j = 0; j < sizeof ranks / sizeof *ranks; j++) {
            check_run(sizes[i], ranks[j], 1, 1024);
            check_run(sizes[i], ranks[j], sched_min_batch(2), 64);
        }
}

Test(sched, first_batches_are_a_share_of_the_image)
{
    sched s;
    cr_assert_eq(SCHED_FACTOR, 16);
    sched_init(&s, 100000, 2, 8, 1024);
    int first, n = sched_take(&s, &first);
    cr_expect_eq(n, 1024, "100000 / 32 tiles is held to the largest batch");
    sched_init(&s, 8160, 4, 8, 1024);
    cr_expect_eq(sched_take(&s, &first), 128, "8160 / (16 x 4)");
    cr_expect_eq(sched_take(&s, &first), 126, "8032 / 64, rounded up");
    sched_init(&s, 100, 4, 8, 1024);
    cr_expect_eq(sched_take(&s, &first), 8, "100 / 64 is below the smallest batch");
    cr_expect_eq(sched_min_batch(1), 4);
    cr_expect_eq(sched_min_batch(8), 32);
}

/* A resumed render: tiles final already are never handed out, and no batch
 * runs across one. */
Test(sched, skipped_tiles_are_left_out)
{
    unsigned char skip[100] = {0};
    for (int t = 0; t < 100; t++)
        skip[t] = t < 10 || (t >= 40 && t < 45) || t % 17 == 0;
    sched s;
    sched_init(&s, 100, 2, 4, 64);
    sched_skip(&s, skip);
    int seen[100] = {0}, first, n;
    while ((n = sched_take(&s, &first)) > 0)
        for (int t = first; t < first + n; t++) {
            cr_assert(!skip[t], "tile %d was final already", t);
            seen[t]++;
        }
    for (int t = 0; t < 100; t++)
        cr_expect_eq(seen[t], !skip[t], "tile %d handed out %d times", t, seen[t]);
}
