/* The energy audit's slopes as a bundle carries them: model.json's optional
 * "audit_slopes", measured for the bundle's own weights by `nbrdf bundle
 * audit-slopes` (src/bake/bake_audit_slopes.c). The audit clears a tuple near a
 * measured one only with slopes measured for the decoder and layering network
 * that made both; a bundle without them has every distinct tuple measured.
 *
 *   "audit_slopes": {"regions": 8,
 *                    "parameters": ["alpha1", "eta", "alpha2", "r0", "albedo", "sigma_t"],
 *                    "directions": ["up", "down"],
 *                    "note": "...",
 *                    "table": [[[6 x [up, down]] x 8 bins of alpha2] x 8 bins of alpha1]}
 *
 * Every number is a finite slope > 0 (per unit of normalised parameter): how
 * much the audit's value may rise from a measured tuple to one whose parameter
 * is above it (up) or below it (down). The decoded albedo rises steeply with r0,
 * and with alpha2 on the ridge of sharp coats, and much less the other way, so
 * one slope for both ways would cost every material the steep way's. A table of
 * the first form (6 numbers an entry, no "directions", written until 2026-11-29)
 * is read as the same slope both ways. */
#ifndef NBRDF_MODEL_AUDIT_SLOPES_H
#define NBRDF_MODEL_AUDIT_SLOPES_H

#include "model/bundle_parts.h"

struct cJSON;

/* Reads root's "audit_slopes" (absent: m->has_audit_slopes = 0) into m; messages
 * name `path` and the entry. */
nbrdf_status model_audit_slopes_read(const struct cJSON *root, const char *path, nbrdf_model *m,
                                     nbrdf_error *err);

/* The table [MODEL_AUDIT_REGIONS][MODEL_AUDIT_REGIONS][MODEL_AUDIT_PARAMS]
 * [MODEL_AUDIT_DIRS] of m, or NULL when its bundle carries none. */
const double *model_audit_slopes(const nbrdf_model *m);

/* The six parameters' names in the table's order ("alpha1", ..., "sigma_t"). */
extern const char *const model_audit_slopes_params[MODEL_AUDIT_PARAMS];

#endif
