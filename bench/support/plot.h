/* Line plots as PNG (speed/accuracy trade-offs, docs/METRICS.md: "a plot accompanies
 * each table"), rasterised here so that no plotting tool is needed: axes with
 * linear or logarithmic scales, tick labels, a title, axis labels and a legend
 * in a built-in 5×7 pixel font (ASCII; lower case is drawn as upper case). */
#ifndef NBRDF_EVAL_PLOT_H
#define NBRDF_EVAL_PLOT_H

#include "nbrdf/status.h"

typedef struct bench_plot_series {
  const char *label; /* legend text, or NULL for none */
  int n;
  const double *x, *y; /* n points; non-finite ones (and ≤ 0 on a log axis) are skipped */
  int dashed;          /* a dashed line without markers (e.g. a noise floor) */
  int color;           /* 0: the series' own palette colour; k > 0: that of series k − 1 */
} bench_plot_series;

typedef struct bench_plot_options {
  const char *title, *x_label, *y_label; /* each may be NULL */
  int log_x, log_y;                      /* non-zero: logarithmic axis, ticks at decades */
  int width, height;                     /* pixels; 0 = 800 × 520 */
} bench_plot_options;

#define NBRDF_PLOT_OPTIONS_DEFAULT                                                                 \
  { NULL, NULL, NULL, 0, 0, 0, 0 }

/* Draws the series (colours in order: blue, orange, green, red, purple, ...)
 * and writes the PNG (temporary file + rename). */
nbrdf_status bench_plot_write_png(const char *path, const bench_plot_options *options, int n_series,
                                  const bench_plot_series *series, nbrdf_error *err);

/* The same image in memory: *rgb (malloc'd, width×height×3 bytes, rows top to
 * bottom) for the caller to free. The plot area spans x ∈ [90, width − 20],
 * y ∈ [56, height − 64]; its corners are the axis ranges: the data range
 * widened to whole decades (log) or to steps of 1, 2 or 5 × 10^k (linear). */
nbrdf_status bench_plot_render(const bench_plot_options *options, int n_series,
                               const bench_plot_series *series, unsigned char **rgb, int *width,
                               int *height, nbrdf_error *err);

#endif
