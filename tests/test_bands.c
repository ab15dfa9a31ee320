/* render/bands: every item is taken exactly once, by whichever threads ask
 * and whichever bands they own; a thread takes its own band front to back
 * and then the back of the fullest band; one band is the items in order. */
#include <criterion/criterion.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>

#include "render/bands.h"

Test(bands, one_band_is_the_items_in_order)
{
    bands *b = bands_new(5, 1);
    cr_assert_not_null(b);
    for (int i = 0; i < 5; i++)
        cr_assert_eq(bands_take(b, 0), i);
    cr_assert_eq(bands_take(b, 0), -1);
    cr_assert_eq(bands_take(b, 0), -1);
    bands_free(b);
}

Test(bands, own_band_first_then_the_back_of_the_fullest)
{
    /* 10 items in 3 bands: [0, 3), [3, 6), [6, 10) */
    bands *b = bands_new(10, 3);
    cr_assert_not_null(b);
    cr_assert_eq(bands_take(b, 1), 3);
    cr_assert_eq(bands_take(b, 1), 4);
    cr_assert_eq(bands_take(b, 1), 5);
    cr_assert_eq(bands_take(b, 1), 9); /* band 2 has four left: its last */
    cr_assert_eq(bands_take(b, 1), 2); /* three left in each: the first band's */
    cr_assert_eq(bands_take(b, 1), 8);
    cr_assert_eq(bands_take(b, 0), 0); /* band 0's own thread still starts at its front */
    cr_assert_eq(bands_take(b, 2), 6);
    cr_assert_eq(bands_take(b, 2), 7);
    cr_assert_eq(bands_take(b, 2), 1);
    for (int own = -1; own < 4; own++) /* a band that is not there takes from the others */
        cr_assert_eq(bands_take(b, own), -1);
    bands_free(b);
}

Test(bands, empty_and_more_bands_than_items)
{
    bands *b = bands_new(0, 4);
    cr_assert_not_null(b);
    cr_assert_eq(bands_take(b, 0), -1);
    bands_free(b);
    b = bands_new(2, 5);
    cr_assert_not_null(b);
    int seen = 0;
    for (int i; (i = bands_take(b, 0)) >= 0;)
        seen |= 1 << i;
    cr_assert_eq(seen, 3);
    bands_free(b);
    bands_free(NULL);
}

enum { ITEMS = 20000, THREADS = 6 };

typedef struct taker {
    bands *b;
    int own;
    atomic_int *count;
    int taken, out_of_range; /* checked on the test's thread after the join */
} taker;

static void *take_all(void *arg)
{
    taker *t = arg;
    for (int i; (i = bands_take(t->b, t->own)) >= 0; t->taken++) {
        if (i >= ITEMS)
            t->out_of_range++;
        else
            atomic_fetch_add(&t->count[i], 1);
    }
    return NULL;
}

/* Six threads on six bands, or on three of eight (the other five's items
 * all taken from their backs): each item once. */
Test(bands, each_item_once_from_many_threads)
{
    static const int nbands[2] = {THREADS, 8};
    for (int round = 0; round < 2; round++) {
        bands *b = bands_new(ITEMS, nbands[round]);
        cr_assert_not_null(b);
        atomic_int *count = calloc(ITEMS, sizeof *count);
        cr_assert_not_null(count);
        taker t[THREADS];
        pthread_t th[THREADS];
        for (int k = 0; k < THREADS; k++) {
            t[k] = (taker){b, round == 0 ? k : k % 3, count, 0, 0};
            cr_assert_eq(pthread_create(&th[k], NULL, take_all, &t[k]), 0);
        }
        int total = 0;
        for (int k = 0; k < THREADS; k++) {
            pthread_join(th[k], NULL);
            cr_assert_eq(t[k].out_of_range, 0);
            total += t[k].taken;
        }
        cr_assert_eq(total, ITEMS);
        for (int i = 0; i < ITEMS; i++)
            cr_assert_eq(atomic_load(&count[i]), 1, "item %d taken %d times", i,
                         atomic_load(&count[i]));
        free(count);
        bands_free(b);
    }
}
