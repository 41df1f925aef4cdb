#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli_common.h"
#include "core/number.h"
#include "texture/latent_exr.h"

int cli_usage_error(const char *cmd, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fprintf(stderr, "nbrdf %s: ", cmd);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fprintf(stderr, "\n(see 'nbrdf %s --help')\n", cmd);
  return CLI_EXIT_USAGE;
}

int cli_fail(const char *cmd, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fprintf(stderr, "nbrdf %s: ", cmd);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fputc('\n', stderr);
  return CLI_EXIT_FAILURE;
}

int cli_fail_error(const char *cmd, const nbrdf_error *err) {
  const char *m = err->message[0] ? err->message : nbrdf_status_name(err->status);
  /* The library names its call ("bake: cancelled ..."), which the CLI's own prefix already
   * says: "nbrdf bake: bake: ..." reads as a stutter. */
  size_t n = strlen(cmd);
  if (!strncmp(m, cmd, n) && !strncmp(m + n, ": ", 2)) m += n + 2;
  return cli_fail(cmd, "%s", m);
}

int cli_parse_double(const char *text, double *out) {
  return text && core_parse_number(text, strlen(text), out) == NBRDF_NUMBER_OK;
}

int cli_parse_float(const char *text, float *out) {
  return text && core_parse_float(text, strlen(text), out) == NBRDF_NUMBER_OK;
}

int cli_parse_int(const char *text, long lo, long hi, long *out) {
  /* Decimal digits only (strtol would take "0x10" with base 0, and "12abc"
   * up to the letters), white space around them allowed as for numbers. */
  double v;
  if (!cli_parse_double(text, &v) || v != floor(v) || strpbrk(text, ".eE")) return 0;
  if (v < (double)lo || v > (double)hi) return 0;
  *out = (long)v;
  return 1;
}

int cli_parse_u64(const char *text, uint64_t *out) {
  /* Decimal digits only: seeds and counts are exact 64-bit integers, which a
   * double would round, and "0x10" or "-1" are refused as elsewhere. */
  if (!text || !isdigit((unsigned char)text[0])) return 0;
  char *end;
  errno = 0;
  unsigned long long v = strtoull(text, &end, 10);
  if (*end || errno == ERANGE) return 0;
  *out = (uint64_t)v;
  return 1;
}

int cli_parse_index(const char *text, uint64_t *out) {
  if (!text || !text[0]) return 0;
  for (const char *c = text; *c; c++)
    if (!isdigit((unsigned char)*c)) return 0;
  if (!cli_parse_u64(text, out)) *out = UINT64_MAX;
  return 1;
}

int cli_texture_levels(const char *path, int level, int *width, int *height) {
  nbrdf_error err = {0};
  texture_latent_reader *r = NULL;
  if (texture_latent_reader_open(&r, path, &err) != NBRDF_OK) return 0;
  int levels = texture_latent_reader_info(r)->levels;
  if (level >= 0 && level < levels &&
      texture_latent_reader_level_size(r, level, width, height, &err) != NBRDF_OK)
    levels = 0;
  texture_latent_reader_close(r);
  return levels;
}

int cli_level_error(const char *cmd, const char *option, const char *texture, int levels,
                    const char *level) {
  return cli_usage_error(cmd, "%s: %s has %d mip level%s (0..%d); there is no level %s", option,
                         texture, levels, levels == 1 ? "" : "s", levels - 1, level);
}

int cli_parse_compact(const char *text, int *k, int *width) {
  char *end = NULL;
  long kk = strtol(text, &end, 10), w = 0;
  int ok = end != text && kk >= 1 && kk <= 8;
  if (ok && *end == ',') {
    const char *ws = end + 1;
    w = strtol(ws, &end, 10);
    ok = end != ws && w >= 4 && w <= 256;
  }
  if (!ok || *end) return 0;
  *k = (int)kk, *width = (int)w;
  return 1;
}

int cli_is_help(const char *arg) { return !strcmp(arg, "-h") || !strcmp(arg, "--help"); }
