/* Summaries of verify's per-texel errors (docs/METRICS.md reports the median and
 * the 90th percentile), and the report's memory. */
#include <math.h>
#include <stdlib.h>

#include "core/sort.h"
#include "verify/verify_internal.h"

double verify_quantile(double *v, size_t n, double q) {
  if (n == 0) return NAN;
  core_sort_doubles(v, n);
  double pos = q * (double)(n - 1);
  size_t i = (size_t)pos;
  if (i + 1 >= n) return v[n - 1];
  double f = pos - (double)i;
  /* Inf − Inf would make a NaN out of two damaged texels. */
  return f == 0.0 ? v[i] : v[i] + f * (v[i + 1] - v[i]);
}

nbrdf_verify_summary verify_summarise(const nbrdf_verify_texel *t, size_t n, int level) {
  nbrdf_verify_summary s = {level, 0, NAN, NAN, NAN, NAN, NAN};
  double *e = malloc(sizeof *e * (n ? n : 1) * 3);
  if (!e) return s;
  double *a = e + n, *noise = a + n;
  size_t m = 0;
  for (size_t i = 0; i < n; i++) {
    if (level != NBRDF_VERIFY_ALL_LEVELS && t[i].level != level) continue;
    e[m] = t[i].lobe_error, a[m] = t[i].albedo_error, noise[m] = t[i].reference_noise;
    m++;
  }
  s.texels = m;
  if (m) {
    s.median = verify_quantile(e, m, 0.5);
    s.p90 = verify_quantile(e, m, 0.9);
    s.worst = e[m - 1]; /* sorted by verify_quantile */
    s.albedo_median = verify_quantile(a, m, 0.5);
    s.noise_median = verify_quantile(noise, m, 0.5);
  }
  free(e);
  return s;
}

void nbrdf_verify_report_free(nbrdf_verify_report *report) {
  if (!report) return;
  free(report->texels);
  free(report->per_level);
  free(report);
}
