/* model.json and MODEL_CARD.md of a bundle (layout in bundle.h). */
#ifndef NBRDF_MODEL_BUNDLE_JSON_H
#define NBRDF_MODEL_BUNDLE_JSON_H

#include <stdint.h>

#include "model/bundle_parts.h"

struct cJSON;

/* Parses dir/model.json (its path into path[4096]) into a JSON object the
 * caller frees with cJSON_Delete. */
nbrdf_status model_bundle_parse_json(const char *dir, char path[4096], struct cJSON **root,
                                     nbrdf_error *err);

/* Reads dir/model.json into m->name, m->trained, m->latent_dim; copies its
 * "checksum" (16 hex digits, required) into checksum[17]. */
nbrdf_status model_bundle_read_json(const char *dir, nbrdf_model *m, char checksum[17],
                                    nbrdf_error *err);

/* Refuses a model.json whose statements about the networks and tables
 * (presets, sizes, MACs, parameters, encoding, table axes) differ from the
 * loaded weight files `m` (bundle_check.c). */
nbrdf_status model_bundle_check_json(const char *dir, const nbrdf_model *m, nbrdf_error *err);

nbrdf_status model_bundle_write_json(const char *dir, const model_bundle_parts *p,
                                     uint64_t checksum, nbrdf_error *err);

/* parts->card, or a generated card naming the architecture, the checksum and,
 * for an untrained bundle, the warning that its outputs mean nothing. */
nbrdf_status model_bundle_write_card(const char *dir, const model_bundle_parts *p,
                                     uint64_t checksum, nbrdf_error *err);

#endif
