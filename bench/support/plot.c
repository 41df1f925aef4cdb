#include "support/plot.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "lobe/png_write.h"

/* A 5×7 pixel font: seven rows per glyph, bit 4 is the leftmost column. */
typedef struct glyph {
  char c;
  unsigned char rows[7];
} glyph;
static const glyph FONT[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}},
    {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
    {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}},
    {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
    {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
    {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04}},
    {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}},
    {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
    {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
    {'[', {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E}},
    {']', {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E}},
    {'*', {0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00}},
    {'<', {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02}},
    {'>', {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08}},
    {'|', {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'\'', {0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00}},
    {'#', {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A}},
};

typedef struct rgb8 {
  unsigned char r, g, b;
} rgb8;

/* The tab10 palette: distinguishable, and the default of matplotlib. */
static const rgb8 PALETTE[] = {{31, 119, 180},  {255, 127, 14}, {44, 160, 44},   {214, 39, 40},
                               {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {127, 127, 127},
                               {188, 189, 34},  {23, 190, 207}};
static const rgb8 BLACK = {0, 0, 0}, GRID = {220, 220, 220}, MINOR = {240, 240, 240},
                  WHITE = {255, 255, 255}, FRAME = {160, 160, 160};
enum { TEXT_SCALE = 2, GLYPH_ADVANCE = 6 * TEXT_SCALE, GLYPH_HEIGHT = 7 * TEXT_SCALE };

static rgb8 series_colour(const bench_plot_series *s, int i) {
  int k = s[i].color > 0 ? s[i].color - 1 : i;
  return PALETTE[k % (int)(sizeof PALETTE / sizeof PALETTE[0])];
}

typedef struct canvas {
  int w, h;
  unsigned char *rgb;
} canvas;

static void put(canvas *c, int x, int y, rgb8 col) {
  if (x < 0 || y < 0 || x >= c->w || y >= c->h) return;
  unsigned char *p = c->rgb + ((size_t)y * (size_t)c->w + (size_t)x) * 3;
  p[0] = col.r, p[1] = col.g, p[2] = col.b;
}

static void fill(canvas *c, int x0, int y0, int x1, int y1, rgb8 col) {
  for (int y = y0; y <= y1; y++)
    for (int x = x0; x <= x1; x++)
      put(c, x, y, col);
}

/* A line `thick` pixels wide; dashed lines alternate 10 pixels on, 6 off. */
static void line(canvas *c, double x0, double y0, double x1, double y1, rgb8 col, int thick,
                 int dashed, double *dash_pos) {
  double len = hypot(x1 - x0, y1 - y0);
  int steps = (int)ceil(len * 2) + 1;
  for (int i = 0; i <= steps; i++) {
    double t = (double)i / steps;
    if (dashed && fmod(*dash_pos + t * len, 16.0) >= 10.0) continue;
    int x = (int)lround(x0 + t * (x1 - x0)), y = (int)lround(y0 + t * (y1 - y0));
    fill(c, x - thick / 2, y - thick / 2, x - thick / 2 + thick - 1, y - thick / 2 + thick - 1,
         col);
  }
  *dash_pos += len;
}

static const glyph *find_glyph(char ch) {
  ch = (char)toupper((unsigned char)ch);
  for (size_t i = 0; i < sizeof FONT / sizeof FONT[0]; i++)
    if (FONT[i].c == ch) return &FONT[i];
  return NULL; /* drawn as a space */
}

static int imin(int a, int b) { return a < b ? a : b; }

static int text_width(const char *s) { return s ? (int)strlen(s) * GLYPH_ADVANCE : 0; }

/* Draws text with its top-left corner at (x, y). */
static void text(canvas *c, int x, int y, const char *s, rgb8 col) {
  for (; s && *s; s++, x += GLYPH_ADVANCE) {
    const glyph *g = find_glyph(*s);
    if (!g) continue;
    for (int r = 0; r < 7; r++)
      for (int k = 0; k < 5; k++)
        if (g->rows[r] & (0x10 >> k))
          fill(c, x + k * TEXT_SCALE, y + r * TEXT_SCALE, x + k * TEXT_SCALE + TEXT_SCALE - 1,
               y + r * TEXT_SCALE + TEXT_SCALE - 1, col);
  }
}

/* One axis: the data range, widened to whole decades (log) or nice steps (linear). */
typedef struct axis {
  int log;
  double lo, hi, step; /* in log10 units for a log axis */
} axis;

static int usable(const axis *a, double v) { return isfinite(v) && (!a->log || v > 0); }

static void axis_fit(axis *a, double vmin, double vmax) {
  if (!(vmin <= vmax)) vmin = a->log ? 1 : 0, vmax = a->log ? 10 : 1;
  if (a->log) {
    a->lo = floor(log10(vmin));
    a->hi = ceil(log10(vmax));
    if (a->hi <= a->lo) a->hi = a->lo + 1;
    a->step = ceil((a->hi - a->lo) / 8.0); /* at most ~8 labelled decades */
    return;
  }
  if (vmax == vmin) vmin -= fmax(1.0, fabs(vmin) * 0.1), vmax += fmax(1.0, fabs(vmax) * 0.1);
  double raw = (vmax - vmin) / 5.0, mag = pow(10.0, floor(log10(raw))), f = raw / mag;
  a->step = (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * mag;
  a->lo = floor(vmin / a->step) * a->step;
  a->hi = ceil(vmax / a->step) * a->step;
}

/* Position of v in [0, 1] along the axis. */
static double axis_map(const axis *a, double v) {
  return ((a->log ? log10(v) : v) - a->lo) / (a->hi - a->lo);
}

static void tick_label(const axis *a, double t, char *buf, size_t cap) {
  double v = a->log ? pow(10.0, t) : t;
  if (fabs(v) < 1e-12 * a->step) v = 0; /* no "-1.4e-17" at the origin */
  snprintf(buf, cap, "%g", v);
}

typedef struct frame {
  int left, right, top, bottom; /* the plot area, in pixels */
  axis x, y;
} frame;

static double frame_x(const frame *f, double v) {
  return f->left + axis_map(&f->x, v) * (f->right - f->left);
}
static double frame_y(const frame *f, double v) {
  return f->bottom - axis_map(&f->y, v) * (f->bottom - f->top);
}

/* Grid lines and tick labels of one axis (vertical: the y axis). */
static void draw_ticks(canvas *c, const frame *f, const axis *a, int vertical) {
  char label[32];
  double first = a->log ? a->lo : a->lo, last = a->hi + (a->log ? 0 : a->step * 0.5);
  for (double t = first; t <= last; t += a->log ? 1.0 : a->step) {
    double v = a->log ? pow(10.0, t) : t;
    for (int m = 2; a->log && m <= 9 && t < a->hi; m++) {
      double p = vertical ? frame_y(f, v * m) : frame_x(f, v * m);
      if (vertical)
        fill(c, f->left, (int)lround(p), f->right, (int)lround(p), MINOR);
      else
        fill(c, (int)lround(p), f->top, (int)lround(p), f->bottom, MINOR);
    }
    double p = vertical ? frame_y(f, v) : frame_x(f, v);
    int ip = (int)lround(p);
    if (vertical)
      fill(c, f->left, ip, f->right, ip, GRID);
    else
      fill(c, ip, f->top, ip, f->bottom, GRID);
    if (a->log && fmod(t - a->lo, a->step) != 0.0) continue;
    tick_label(a, t, label, sizeof label);
    if (vertical)
      text(c, f->left - 8 - text_width(label) + TEXT_SCALE, ip - GLYPH_HEIGHT / 2, label, BLACK);
    else
      text(c, imin(ip - text_width(label) / 2, c->w - text_width(label)), f->bottom + 8, label,
           BLACK); /* the last label may not fit centred */
  }
}

static void draw_series(canvas *c, const frame *f, const bench_plot_series *s, rgb8 col) {
  double dash = 0.0, px = 0, py = 0;
  int have_prev = 0;
  for (int k = 0; k < s->n; k++) {
    if (!usable(&f->x, s->x[k]) || !usable(&f->y, s->y[k])) {
      have_prev = 0;
      continue;
    }
    double x = frame_x(f, s->x[k]), y = frame_y(f, s->y[k]);
    if (have_prev) line(c, px, py, x, y, col, 2, s->dashed, &dash);
    px = x, py = y, have_prev = 1;
  }
  for (int k = 0; k < s->n && !s->dashed; k++)
    if (usable(&f->x, s->x[k]) && usable(&f->y, s->y[k])) {
      int x = (int)lround(frame_x(f, s->x[k])), y = (int)lround(frame_y(f, s->y[k]));
      fill(c, x - 3, y - 3, x + 3, y + 3, col);
    }
}

static void draw_legend(canvas *c, const frame *f, int n, const bench_plot_series *s) {
  int rows = 0, wmax = 0;
  for (int i = 0; i < n; i++)
    if (s[i].label) rows++, wmax = wmax > text_width(s[i].label) ? wmax : text_width(s[i].label);
  if (!rows) return;
  const int bw = 52 + wmax, bh = rows * 22 + 8, x0 = f->right - bw - 8, y0 = f->top + 8;
  fill(c, x0, y0, x0 + bw, y0 + bh, FRAME);
  fill(c, x0 + 1, y0 + 1, x0 + bw - 1, y0 + bh - 1, WHITE);
  int y = y0 + 6;
  for (int i = 0; i < n; i++) {
    if (!s[i].label) continue;
    rgb8 col = series_colour(s, i);
    double dash = 0.0;
    line(c, x0 + 8, y + GLYPH_HEIGHT / 2, x0 + 38, y + GLYPH_HEIGHT / 2, col, 2, s[i].dashed,
         &dash);
    if (!s[i].dashed)
      fill(c, x0 + 20, y + GLYPH_HEIGHT / 2 - 3, x0 + 26, y + GLYPH_HEIGHT / 2 + 3, col);
    text(c, x0 + 46, y, s[i].label, BLACK);
    y += 22;
  }
}

nbrdf_status bench_plot_render(const bench_plot_options *options, int n_series,
                               const bench_plot_series *series, unsigned char **rgb, int *width,
                               int *height, nbrdf_error *err) {
  bench_plot_options o = NBRDF_PLOT_OPTIONS_DEFAULT;
  if (options) o = *options;
  const int w = o.width ? o.width : 800, h = o.height ? o.height : 520;
  *rgb = NULL;
  if (w < 200 || h < 150 || w > 8192 || h > 8192)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "plot size %d x %d is outside 200x150 .. 8192²", w,
                     h);
  if (n_series < 0) return core_fail(err, NBRDF_ERR_ARGUMENT, "plot of %d series", n_series);
  frame f = {90, w - 20, 56, h - 64, {o.log_x, 0, 0, 0}, {o.log_y, 0, 0, 0}};
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (int i = 0; i < n_series; i++) {
    if (series[i].n < 0 || (series[i].n > 0 && (!series[i].x || !series[i].y)))
      return core_fail(err, NBRDF_ERR_ARGUMENT, "plot series %d has no data", i);
    for (int k = 0; k < series[i].n; k++) {
      double x = series[i].x[k], y = series[i].y[k];
      if (!usable(&f.x, x) || !usable(&f.y, y)) continue;
      xmin = fmin(xmin, x), xmax = fmax(xmax, x), ymin = fmin(ymin, y), ymax = fmax(ymax, y);
    }
  }
  axis_fit(&f.x, xmin, xmax);
  axis_fit(&f.y, ymin, ymax);

  canvas c = {w, h, malloc((size_t)w * (size_t)h * 3)};
  if (!c.rgb) return core_fail(err, NBRDF_ERR_MEMORY, "plot: out of memory");
  memset(c.rgb, 255, (size_t)w * (size_t)h * 3);
  draw_ticks(&c, &f, &f.x, 0);
  draw_ticks(&c, &f, &f.y, 1);
  fill(&c, f.left, f.top, f.right, f.top, BLACK);
  fill(&c, f.left, f.bottom, f.right, f.bottom, BLACK);
  fill(&c, f.left, f.top, f.left, f.bottom, BLACK);
  fill(&c, f.right, f.top, f.right, f.bottom, BLACK);
  for (int i = 0; i < n_series; i++)
    draw_series(&c, &f, &series[i], series_colour(series, i));
  draw_legend(&c, &f, n_series, series);
  text(&c, (w - text_width(o.title)) / 2, 10, o.title, BLACK);
  text(&c, f.left, f.top - 22, o.y_label, BLACK);
  text(&c, (f.left + f.right - text_width(o.x_label)) / 2, h - 26, o.x_label, BLACK);
  *rgb = c.rgb;
  *width = w;
  *height = h;
  return NBRDF_OK;
}

nbrdf_status bench_plot_write_png(const char *path, const bench_plot_options *options, int n_series,
                                  const bench_plot_series *series, nbrdf_error *err) {
  unsigned char *rgb;
  int w, h;
  nbrdf_status st = bench_plot_render(options, n_series, series, &rgb, &w, &h, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: ", path);
    return st;
  }
  st = lobe_png_write_rgb8(path, w, h, rgb, err);
  free(rgb);
  return st;
}
