/* bands: a render's work items (tiles) shared among its threads so that
 * they work on parts of the image far apart. Items 0 .. n-1 (row by row)
 * are cut into one band of consecutive items per thread; a thread takes
 * the items of its own band from the front, in order, and once its band
 * is empty, takes the last item of the band with the most left, so that
 * every item is rendered once and no thread waits while any is left.
 *
 * Two threads rendering neighbouring tiles of the same rows at the same
 * time cost each other: the built-in scene at 1280x720 took 15-21% more
 * CPU time on two threads taking tiles in turn than on one, against 1-6%
 * for two threads rendering halves of the image apart, and 0-5% in bands
 * (bench/README.md, third round of 2026-12-06). A tile's pixels do not
 * depend on the thread or the order. */
#ifndef GLINT_RENDER_BANDS_H
#define GLINT_RENDER_BANDS_H

typedef struct bands bands;

/* n items in nbands bands (nbands >= 1); NULL when out of memory. */
bands *bands_new(int n, int nbands);
void bands_free(bands *b);

/* The next item for the thread of band `own`: the front of its band, else
 * the back of the band with the most left (the first of those that tie);
 * -1 when every item is taken. Safe from any number of threads at once. */
int bands_take(bands *b, int own);

#endif
