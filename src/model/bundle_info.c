/* A human-readable description of a loaded bundle (`nbrdf bundle info`). */
#include <inttypes.h>
#include <stdio.h>

#include "model/bundle.h"
#include "model/proxy.h"

static void net_line(FILE *out, const char *what, const char *preset, const nn_network *nn) {
  const nn_spec *spec = nn_get_spec(nn);
  /* The first layer lifts the inputs to the width; count only the blocks after it. */
  int plain = 0, residual = 0, width = spec->layers[0].width;
  for (int i = 1; i < spec->n_layers; i++) {
    if (spec->layers[i].kind == NBRDF_NN_RESIDUAL) residual++;
    if (spec->layers[i].kind == NBRDF_NN_PLAIN) plain++;
  }
  fprintf(out,
          "%-10s preset %s: %d -> %d, width %d, %d residual + %d plain blocks, %" PRId64
          " MACs per query, %zu parameters\n",
          what, preset, nn_inputs(nn), nn_outputs(nn), width, residual, plain, nn_spec_macs(spec),
          nn_param_count(nn));
}

void model_bundle_describe(const nbrdf_model *m, FILE *out) {
  const model_decoder_config *dc = &m->decoder->cfg;
  fprintf(out, "name:      %s\n", m->name);
  fprintf(out, "trained:   %s\n",
          m->trained ? "yes" : "NO (random initial weights: values are meaningless)");
  fprintf(out, "checksum:  %s\n", m->checksum_hex);
  for (int k = 0; k < m->n_reads; k++)
    fprintf(out, "reads textures of: %s (checksum %s; the same decoder)\n", m->reads[k].name,
            m->reads[k].checksum_hex);
  fprintf(out, "latent:    %d floats per colour channel\n", m->latent_dim);
  net_line(out, "decoder:", dc->preset, m->decoder->nn);
  fprintf(out, "           encoding %s, %d octaves; output %s\n",
          model_encoding_kind_name(dc->encoding.kind), dc->encoding.octaves,
          model_output_name(dc->output));
  net_line(out, "layering:", m->layering->preset, m->layering->nn);
  fprintf(out, "           input sigma_t as log1p(sigma_t)\n");
  net_line(out, "sampler:", m->sampler->preset, m->sampler->nn);
  fprintf(out, "           sigma = %g + softplus, w = sigmoid\n", MODEL_PROXY_SIGMA_MIN);
  fprintf(out, "audit:     %s\n",
          !m->has_audit_slopes
              ? "no slopes: a bake's energy audit measures every distinct tuple (`nbrdf bundle "
                "audit-slopes DIR` measures them)"
          : m->audit_slopes_both_ways
              ? "slopes measured for these weights (model.json \"audit_slopes\"), one per "
                "parameter both ways (the first form; `nbrdf bundle audit-slopes DIR` measures "
                "them per direction, which clears more)"
              : "slopes measured for these weights (model.json \"audit_slopes\"), per direction");
  for (int k = 0; k < 2; k++) {
    const model_base_table *t = &m->tables[k];
    fprintf(out, "table %s: %d x %d grid\n", model_table_name(t->kind), t->n[0], t->n[1]);
    for (int a = 0; a < 2; a++) {
      fprintf(out, "  %-7s", model_table_param(t->kind, a));
      for (int i = 0; i < t->n[a]; i++)
        fprintf(out, " %.4g", t->axis[a][i]);
      fputc('\n', out);
    }
  }
}
