/* `nbrdf eval --texture FILE.exr [--level K]`: point queries of a baked latent
 * texture, decoded the way a renderer decodes it: the latents fetched
 * bilinearly at (u, v) in one mip level (texture/latent_fetch.h, the
 * renderer's and the shaders' convention), then the texture's own decoder
 * when it carries one (format version 2), else the bundle's. */
#ifndef NBRDF_CLI_EVAL_TEXTURE_H
#define NBRDF_CLI_EVAL_TEXTURE_H

#include <stdio.h>

#include "core/csv.h"
#include "nbrdf/model.h"

typedef struct cli_eval_texture_options {
  const char *texture;
  const char *bundle;     /* NULL: the default bundle (cli_model_load) */
  int level;              /* mip level to fetch from */
  const char *level_text; /* --level as typed (NULL: "0"), for messages */
  nbrdf_device device;    /* where the decoder runs (docs/GPU.md) */
  const char *input;      /* the CSV's name in messages ("stdin", a path) */
} cli_eval_texture_options;

/* Reads the columns u, v, theta_i, phi_i, theta_o, phi_o of every row of `t`
 * (a header and the queries), decodes, and writes the rows with f (mono) or
 * f_r, f_g, f_b (RGB) appended to `out`. Errors name the input, line and column.
 * Returns a CLI exit status. */
int cli_eval_texture(const cli_eval_texture_options *o, const core_csv_table *t, FILE *out);

#endif
