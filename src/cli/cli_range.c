#include "cli/cli_range.h"

#include <stdio.h>

#include "cli/cli_progress.h"

/* A JSON number; null for what JSON cannot hold (an infinite or NaN bound). */
static void json_number(const char *key, double v) {
  if (v == v && v - v == 0.0)
    printf(",\"%s\":%.7g", key, v);
  else
    printf(",\"%s\":null", key);
}

static void json_text(const char *key, const char *text) {
  printf(",\"%s\":\"", key);
  for (const char *c = text; *c; c++)
    if (*c == '"' || *c == '\\')
      printf("\\%c", *c);
    else if ((unsigned char)*c >= 0x20)
      putchar(*c);
  putchar('"');
}

void cli_range_report(void *user, const nbrdf_bake_range *r) {
  const cli_progress_state *p = user;
  char msg[768];
  nbrdf_bake_range_message(r, msg, sizeof msg);
  if (p->json) {
    printf("{\"event\":\"range\"");
    json_text("parameter", r->name);
    json_text("units", r->units);
    printf(",\"constant\":%s,\"below\":%zu,\"above\":%zu", r->constant ? "true" : "false", r->below,
           r->above);
    if (r->below) json_number("min", r->min);
    if (r->above) json_number("max", r->max);
    json_number("lo", r->lo);
    json_number("hi", r->hi);
    /* alpha1, alpha2: what the fitting levels take as given, and how many are below even it. */
    if (r->fit_lo > 0.0 && r->fit_lo < r->lo) {
      json_number("fit_lo", r->fit_lo);
      if (r->below) printf(",\"below_fit\":%zu", r->below_fit);
    }
    json_text("accuracy", nbrdf_bake_accuracy_name(r->accuracy));
    json_text("policy", r->policy == NBRDF_RANGE_REFUSE ? "refuse" : "clamp");
    json_text("message", msg);
    printf("}\n");
    fflush(stdout);
  }
  fprintf(stderr, "nbrdf bake: %s\n", msg);
}
