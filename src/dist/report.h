/* report: what rank 0 shows: how it shows progress, the statistics of
 * --stats with each rank's share, and the tile costs of --tile-costs. */
#ifndef GLINT_DIST_REPORT_H
#define GLINT_DIST_REPORT_H

#include <stdbool.h>
#include <stdio.h>

#include "cli/progress.h"
#include "job.h"

/* How rank 0 shows progress: glint's bar (cli/progress.h) when the job
 * runs at a terminal, plain lines with --progress otherwise. */
progress_mode dist_progress_mode(const struct cli *o);

/* --stats: the image, rays, time and speed as glint prints them, then each
 * rank's share (unit: "tiles" or "frames"), busy time and efficiency (busy
 * time / time); images: how many the time covers. */
void dist_print_stats(FILE *out, const dist_job *job, const dist_rank *ranks, double seconds,
                      const char *unit, int images);

/* --tile-costs FILE: one line per tile, "tile x0 y0 x1 y1 seconds rank",
 * after a header of comments naming the image and the settings. */
glint_rc dist_write_costs(const char *path, const dist_job *job, const double *costs,
                          const int *owner, glint_error *err);

#endif
