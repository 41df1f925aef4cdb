/* verify's two outputs written into open temporary files, so that `nbrdf verify --json
 * --heatmap` puts both in place or neither (core_output_file_commit_all). The public
 * nbrdf_verify_write_json / _heatmap are these plus their own open and commit. */
#ifndef NBRDF_VERIFY_VERIFY_WRITE_H
#define NBRDF_VERIFY_VERIFY_WRITE_H

#include <stddef.h>

#include "core/output_file.h"
#include "nbrdf/verify.h"

nbrdf_status verify_write_json_to(const nbrdf_verify_report *report, const char *texture,
                                 size_t worst, core_output_file *f, nbrdf_error *err);
nbrdf_status verify_write_heatmap_to(const nbrdf_verify_report *report, int level, double scale,
                                    core_output_file *f, nbrdf_error *err);

#endif
