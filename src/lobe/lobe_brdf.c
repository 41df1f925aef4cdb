/* The ground truth as a lobe callback. Kept apart from lobe.c so that the
 * metrics link without the physics. */
#include "lobe/lobe.h"

nbrdf_status lobe_brdf_fn(void *user, size_t n, const nbrdf_query *queries, double *f,
                          nbrdf_error *err) {
  const lobe_brdf *b = user;
  return nbrdf_brdf_eval(b->brdf, n, queries, &b->options, f, NULL, err);
}
