/* The bake's public helpers that every layer above it and the lower bake files
 * use: parameter names and values (nbrdf_bake_param_*), accuracy level names. */
#include "nbrdf/bake.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/number.h"
#include "model/material.h"

static const char *const accuracy_names[5] = {"fast", "fitted", "specialised", "compact",
                                              "auto"};

const char *nbrdf_bake_accuracy_name(nbrdf_bake_accuracy a) {
  return (unsigned)a < 5 ? accuracy_names[a] : "unknown";
}

int nbrdf_bake_accuracy_parse(const char *name) {
  for (int k = 0; name && k < 5; k++)
    if (!strcmp(name, accuracy_names[k])) return k;
  return -1;
}

const char *nbrdf_bake_param_name(nbrdf_bake_param_id id) { return model_material_param_name(id); }

void nbrdf_bake_param_constant(nbrdf_bake_param *p, float value) {
  p->path = NULL;
  p->value[0] = p->value[1] = p->value[2] = value;
  p->channels = 1;
}

nbrdf_status nbrdf_bake_param_parse(const char *name, const char *arg, nbrdf_bake_param *p,
                                    nbrdf_error *err) {
  if (!arg || !*arg) return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: empty value", name);
  /* "v" or "v,v,v", each number as core/number.h reads it (white space
   * around it allowed, hex/inf/nan not). */
  float v[3];
  int n = 0, numbers = 1;
  for (const char *s = arg;; n++) {
    const char *comma = strchr(s, ',');
    size_t len = comma ? (size_t)(comma - s) : strlen(s);
    core_number_result r = n < 3 ? core_parse_float(s, len, &v[n]) : NBRDF_NUMBER_SYNTAX;
    if (r == NBRDF_NUMBER_OVERFLOW || r == NBRDF_NUMBER_UNDERFLOW)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "%s: '%.*s' %s as a float; write ./%s for a file of that name", name,
                       (int)len, s, core_number_problem(r), arg);
    if (r != NBRDF_NUMBER_OK) numbers = 0;
    if (!comma) break;
    s = comma + 1;
  }
  n++;
  if (numbers && (n == 1 || n == 3)) {
    p->path = NULL;
    p->channels = n;
    for (int c = 0; c < 3; c++)
      p->value[c] = v[n == 3 ? c : 0];
    return NBRDF_OK;
  }
  /* Not one or three numbers: a file, which must exist (so that a mistyped
   * value, "0x10" or "0.5,0.5", is not reported as a missing image). */
  struct stat sb;
  if (stat(arg, &sb) != 0 && errno == ENOENT)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: '%s' is neither a number (nor three, comma-separated) nor an "
                     "existing file",
                     name, arg);
  p->path = arg;
  return NBRDF_OK;
}
