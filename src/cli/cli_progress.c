#include "cli/cli_progress.h"

#include <stdio.h>

void cli_progress_json(const char *stage, double done, double total, double seconds, double rate) {
  /* done moves within a band / texel: fractional, two decimals */
  printf("{\"event\":\"progress\",\"stage\":\"%s\",\"done\":%.*f,\"total\":%.0f", stage,
         done == (double)(long long)done ? 0 : 2, done, total);
  if (seconds >= 0) {
    double eta = rate > 0 ? (total - done) / rate : -1.0;
    printf(",\"seconds\":%.2f,\"rate\":%.4g,\"eta_s\":%.0f", seconds, rate, eta);
  }
  fputs("}\n", stdout);
  fflush(stdout);
}

int cli_progress(void *user, const char *stage, double done, double total) {
  const cli_progress_state *p = user;
  if (p->json) {
    cli_progress_json(stage, done, total, -1.0, 0.0);
  } else if (p->bar) {
    int width = 40, filled = total > 0 ? (int)(width * done / total) : width;
    fprintf(stderr, "\r%s [", stage);
    for (int i = 0; i < width; i++)
      fputc(i < filled ? '#' : ' ', stderr);
    fprintf(stderr, "] %3.0f%%", total > 0 ? 100.0 * done / total : 100.0);
    if (done >= total) fputc('\n', stderr);
    fflush(stderr);
  }
  return 0;
}
