/* Records a bundle's measured audit slopes in its model.json (the format:
 * audit_slopes.h); apart from the reader so that the loader's model.json reader
 * (bundle_json.c) and this writer, which parses model.json with it, are not a cycle. */
#ifndef NBRDF_MODEL_AUDIT_SLOPES_WRITE_H
#define NBRDF_MODEL_AUDIT_SLOPES_WRITE_H

#include "nbrdf/status.h"

/* Replaces dir/model.json's "audit_slopes" with `table` (the layout of audit_slopes.h) and
 * `note` (may be NULL), through a temporary file; the rest of model.json is kept.
 * `checksum` (16 hex digits): the weights the table was measured with; refused
 * when model.json records another. */
nbrdf_status model_audit_slopes_write(const char *dir, const char *checksum, const double *table,
                                      const char *note, nbrdf_error *err);

#endif
