#include "texture/latent_layout.h"

#include <stdio.h>
#include <string.h>

#include "core/error.h"

static const char *const mono_suffix[] = {"Y"};
static const char *const rgb_suffix[] = {"R", "G", "B"};

nbrdf_status texture_latent_layout_check(const texture_latent_layout *layout, nbrdf_error *err) {
  if (!layout) return core_fail(err, NBRDF_ERR_ARGUMENT, "latent layout is NULL");
  if (layout->latent_dim < 1 || layout->latent_dim > NBRDF_LATENT_MAX_DIM)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "latent dimension %d is outside [1, %d]",
                     layout->latent_dim, NBRDF_LATENT_MAX_DIM);
  if (layout->colour != NBRDF_COLOUR_MONO && layout->colour != NBRDF_COLOUR_RGB)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "colour mode %d is neither mono (1) nor RGB (3)",
                     (int)layout->colour);
  if (layout->proxy != 0 && layout->proxy != 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "proxy flag %d is neither 0 nor 1", layout->proxy);
  return NBRDF_OK;
}

int texture_latent_colours(const texture_latent_layout *layout) { return (int)layout->colour; }

int texture_latent_block(const texture_latent_layout *layout) {
  return layout->latent_dim + (layout->proxy ? 2 : 0);
}

int texture_latent_channel_count(const texture_latent_layout *layout) {
  return texture_latent_colours(layout) * texture_latent_block(layout);
}

int texture_latent_index_latent(const texture_latent_layout *layout, int c, int k) {
  return c * texture_latent_block(layout) + k;
}

int texture_latent_index_sigma(const texture_latent_layout *layout, int c) {
  return c * texture_latent_block(layout) + layout->latent_dim;
}

int texture_latent_index_w(const texture_latent_layout *layout, int c) {
  return c * texture_latent_block(layout) + layout->latent_dim + 1;
}

static const char *colour_suffix(const texture_latent_layout *layout, int c) {
  return layout->colour == NBRDF_COLOUR_MONO ? mono_suffix[0] : rgb_suffix[c];
}

void texture_latent_channel_name(const texture_latent_layout *layout, int i, char *buf, size_t n) {
  int block = texture_latent_block(layout);
  int c = i / block, k = i % block;
  const char *suffix = colour_suffix(layout, c);
  /* Two digits keep names aligned for the paper's 32 latents; wider
   * latents get three so that names still sort in numeric order. */
  int digits = layout->latent_dim > 100 ? 3 : 2;
  if (k < layout->latent_dim)
    snprintf(buf, n, "latent.L%0*d.%s", digits, k, suffix);
  else if (k == layout->latent_dim)
    snprintf(buf, n, "proxy.sigma.%s", suffix);
  else
    snprintf(buf, n, "proxy.w.%s", suffix);
}

static int parse_colour(const texture_latent_layout *layout, const char *suffix) {
  for (int c = 0; c < texture_latent_colours(layout); c++)
    if (strcmp(suffix, colour_suffix(layout, c)) == 0) return c;
  return -1;
}

int texture_latent_channel_index(const texture_latent_layout *layout, const char *name) {
  int block = texture_latent_block(layout), c, k;
  if (strncmp(name, "latent.L", 8) == 0) {
    const char *p = name + 8;
    int digits = layout->latent_dim > 100 ? 3 : 2, value = 0;
    for (int i = 0; i < digits; i++, p++) {
      if (*p < '0' || *p > '9') return -1;
      value = value * 10 + (*p - '0');
    }
    if (*p != '.' || value >= layout->latent_dim) return -1;
    c = parse_colour(layout, p + 1);
    k = value;
  } else if (layout->proxy && strncmp(name, "proxy.sigma.", 12) == 0) {
    c = parse_colour(layout, name + 12);
    k = layout->latent_dim;
  } else if (layout->proxy && strncmp(name, "proxy.w.", 8) == 0) {
    c = parse_colour(layout, name + 8);
    k = layout->latent_dim + 1;
  } else {
    return -1;
  }
  return c < 0 ? -1 : c * block + k;
}

const char *texture_colour_mode_name(texture_colour_mode mode) {
  switch (mode) {
  case NBRDF_COLOUR_MONO:
    return "mono";
  case NBRDF_COLOUR_RGB:
    return "rgb";
  }
  return "unknown";
}

int texture_colour_mode_parse(const char *name, texture_colour_mode *out) {
  if (!name) return 0;
  if (strcmp(name, "mono") == 0) {
    *out = NBRDF_COLOUR_MONO;
    return 1;
  }
  if (strcmp(name, "rgb") == 0) {
    *out = NBRDF_COLOUR_RGB;
    return 1;
  }
  return 0;
}
