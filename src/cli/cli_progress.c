#include "cli/cli_progress.h"

#include <stdio.h>

int cli_progress(void *user, const char *stage, double done, double total) {
  const cli_progress_state *p = user;
  if (p->json) {
    /* done moves within a band / texel: fractional, two decimals */
    printf("{\"event\":\"progress\",\"stage\":\"%s\",\"done\":%.*f,\"total\":%.0f}\n", stage,
           done == (double)(long long)done ? 0 : 2, done, total);
    fflush(stdout);
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
