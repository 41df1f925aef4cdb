/* What a latent texture's texel holds, and what its channels and header
 * attributes are called on disk (docs/LATENT-TEXTURE.md is the reference).
 *
 * In memory a texel is a run of floats in "logical order": for each colour
 * channel (Y for mono; R, G, B for RGB, paper §3.2) its latent_dim latents,
 * followed, when the sampling proxy is stored, by that channel's proxy
 * parameters sigma and w. The EXR file stores the same values under names
 * (latent.L00.R, proxy.sigma.R, ...); OpenEXR sorts channels by name, so code
 * maps through names, never through the order of the channel list. */
#ifndef NBRDF_TEXTURE_LATENT_LAYOUT_H
#define NBRDF_TEXTURE_LATENT_LAYOUT_H

#include <stddef.h>

#include "nbrdf/status.h"

/* Bumped when a reader of the previous version would misread a new file.
 * Version 2 textures carry their own decoder (NBRDF_ATTR_DECODER); a texture
 * without one is written as version 1, byte for byte as before version 2
 * existed, so that every reader of version 1 still reads it. */
#define NBRDF_LATENT_FORMAT_VERSION 2
#define NBRDF_LATENT_FORMAT_V1 1
#define NBRDF_LATENT_FORMAT_OWN_DECODER 2
#define NBRDF_LATENT_MAX_DIM 999

/* Header attributes (OpenEXR attribute names, "nbrdf:" namespace). */
#define NBRDF_ATTR_FORMAT_VERSION "nbrdf:formatVersion" /* int */
#define NBRDF_ATTR_LATENT_DIM "nbrdf:latentDim"         /* int */
#define NBRDF_ATTR_COLOUR_MODE "nbrdf:colourMode"       /* string: "mono" | "rgb" */
#define NBRDF_ATTR_PROXY "nbrdf:proxy"                  /* int: 0 | 1 */
#define NBRDF_ATTR_MODEL_NAME "nbrdf:modelName"         /* string */
#define NBRDF_ATTR_MODEL_CHECKSUM "nbrdf:modelChecksum" /* string */
#define NBRDF_ATTR_SOURCES "nbrdf:parameterSources"     /* string */
#define NBRDF_ATTR_SETTINGS "nbrdf:bakeSettings"        /* string */
#define NBRDF_ATTR_MIP_FILTER "nbrdf:mipFilter"         /* string */
#define NBRDF_ATTR_WRITER "nbrdf:writer"                /* string: "nbrdf X.Y.Z" */
/* Optional; only bakes above the fast level write it (docs/LATENT-TEXTURE.md):
 * "level=fitted; budget=120; distinct=N; fitted=N; heldout=N; heldoutError=F; fastError=F" */
#define NBRDF_ATTR_ACCURACY "nbrdf:accuracy" /* string */
/* Optional: the caller's fingerprint of what the texture was made from (a tile set's bake
 * stores one so that a re-run can tell a finished tile from a stale one). */
#define NBRDF_ATTR_INPUTS "nbrdf:inputs" /* string */
/* Version 2 only: the texture's own decoder, the bytes of a decoder.safetensors
 * file in an opaque attribute of this type, and their FNV-1a 64 checksum. */
#define NBRDF_ATTR_DECODER "nbrdf:decoder"                  /* NBRDF_DECODER_ATTR_TYPE */
#define NBRDF_ATTR_DECODER_CHECKSUM "nbrdf:decoderChecksum" /* string: 16 hex digits */
#define NBRDF_DECODER_ATTR_TYPE "nbrdfSafetensors"
/* float, optional: the largest decoded directional albedo of the bake's
 * audited latents over θi; < 0 when the audit did not run. Written
 * as a placeholder with the header and patched in place at the end. */
#define NBRDF_ATTR_MAX_ALBEDO "nbrdf:maxAlbedo"

/* The one mip filter this version writes: the unweighted mean of the
 * level-0 latents in a texel's footprint (see mip_chain.h). */
#define NBRDF_MIP_FILTER_BOX "box-latent-mean"

typedef enum texture_colour_mode {
  NBRDF_COLOUR_MONO = 1, /* one BRDF per texel, channel suffix .Y */
  NBRDF_COLOUR_RGB = 3   /* an independent BRDF per R, G, B channel */
} texture_colour_mode;

typedef struct texture_latent_layout {
  int latent_dim;           /* latents per colour channel (the paper uses 32) */
  texture_colour_mode colour; /* mono or RGB */
  int proxy;                /* 1: sigma and w of the sampling proxy follow each latent */
} texture_latent_layout;

/* A layout the format can hold: 1 <= latent_dim <= NBRDF_LATENT_MAX_DIM, a
 * known colour mode, proxy 0 or 1. */
nbrdf_status texture_latent_layout_check(const texture_latent_layout *layout, nbrdf_error *err);

int texture_latent_colours(const texture_latent_layout *layout);
/* Floats per colour channel: latent_dim, plus 2 with the proxy. */
int texture_latent_block(const texture_latent_layout *layout);
/* Floats per texel. */
int texture_latent_channel_count(const texture_latent_layout *layout);

/* Logical indices of latent k, sigma and w of colour channel c. */
int texture_latent_index_latent(const texture_latent_layout *layout, int c, int k);
int texture_latent_index_sigma(const texture_latent_layout *layout, int c);
int texture_latent_index_w(const texture_latent_layout *layout, int c);

/* The EXR channel name of logical index i ("latent.L07.G", "proxy.w.Y").
 * `buf` needs at most 24 bytes. */
void texture_latent_channel_name(const texture_latent_layout *layout, int i, char *buf, size_t n);
/* The logical index of an EXR channel name, or -1 if the layout has no
 * such channel. */
int texture_latent_channel_index(const texture_latent_layout *layout, const char *name);

const char *texture_colour_mode_name(texture_colour_mode mode);
/* "mono" or "rgb"; returns 0 for anything else. */
int texture_colour_mode_parse(const char *name, texture_colour_mode *out);

#endif
