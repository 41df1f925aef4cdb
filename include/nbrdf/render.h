/* A small deterministic renderer for previews and for comparing the neural
 * BRDF with its ground truth (docs/RENDER.md): one object (a unit sphere or
 * a ground plane) carrying a latent texture, lit by an environment and an
 * optional point light, seen through a pinhole camera.
 *
 * The object is convex and alone, so every light path is camera -> surface
 * -> light: the integrator is direct lighting, complete for this scene. Per
 * pixel sample it combines
 *   - the point light (a delta light: next-event estimation only);
 *   - one environment sample (importance-sampled from a tabulated luminance
 *     distribution, for the procedural sky and HDR images alike) and one
 *     BRDF sample, weighted by the power heuristic (MIS).
 * Two material modes run through this same code:
 *   NEURAL     f decoded from the texture's latents (nbrdf_model_decode,
 *              batched per tile); BRDF samples drawn from the proxy (sigma,
 *              w) stored in the texture (one-sample mixture over colour
 *              channels);
 *   REFERENCE  f from the layered Monte Carlo ground truth of constant
 *              parameters (nbrdf_brdf_eval, one random walk per query) and
 *              BRDF samples from its own sampler (nbrdf_brdf_sample), one
 *              per colour channel; the texture's proxy only shapes the MIS
 *              weights (any weights that sum to one keep MIS unbiased).
 *
 * Results are deterministic for a seed whatever the thread count: pixel p
 * owns PCG32 stream p, tiles are fixed, and each tile's network batches are
 * the same in every run. Calls on different option structs may run in
 * several threads at once; the model and BRDF handles are only read.
 *
 * Example (`model` the bundle tex.exr was baked with; tests/docs compiles it):
 *   nbrdf_error err;
 *   nbrdf_render_options opts = NBRDF_RENDER_OPTIONS_DEFAULT;
 *   static float rgb[256 * 256 * 3]; // opts.width x opts.height, RGB
 *   nbrdf_status st = nbrdf_render(model, "tex.exr", &opts, rgb, NULL, &err);
 *   if (st == NBRDF_OK)
 *     st = nbrdf_render_write("preview.exr", "preview.png", opts.width, opts.height, rgb, NULL,
 *                             NULL, &err);
 *   if (st != NBRDF_OK) fprintf(stderr, "render: %s\n", err.message);
 */
#ifndef NBRDF_RENDER_H
#define NBRDF_RENDER_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "nbrdf/brdf.h"
#include "nbrdf/model.h"
#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum nbrdf_render_mode {
  NBRDF_RENDER_NEURAL = 0,   /* decode the latent texture */
  NBRDF_RENDER_REFERENCE = 1 /* Monte Carlo ground truth of `reference` */
} nbrdf_render_mode;

typedef enum nbrdf_render_scene {
  NBRDF_SCENE_SPHERE = 0, /* unit sphere at the origin, lat-long texture coordinates */
  NBRDF_SCENE_PLANE = 1,  /* ground plane y = 0 receding to the horizon, texture repeated */
  NBRDF_SCENE_MESH = 2    /* a triangle mesh with texture coordinates read from mesh_path */
} nbrdf_render_scene;

typedef enum nbrdf_env_kind {
  NBRDF_ENV_SKY = 0,      /* procedural: blue zenith, white horizon, a soft sun, grey ground */
  NBRDF_ENV_CONSTANT = 1, /* env_value in every direction (a furnace) */
  NBRDF_ENV_IMAGE = 2     /* a lat-long HDR/EXR image read by OpenImageIO (env_path) */
} nbrdf_env_kind;

typedef struct nbrdf_render_options {
  nbrdf_render_mode mode;
  nbrdf_render_scene scene;
  nbrdf_env_kind env;
  const char *env_path; /* NBRDF_ENV_IMAGE: linear radiance, +y up, centre column looks at -z */
  float env_value[3];   /* NBRDF_ENV_CONSTANT: radiance */
  float env_scale;      /* multiplies the environment's radiance */
  /* Point light at world position light_pos (y up) with radiant intensity
   * light_intensity (W/sr, white); none when the intensity is 0. */
  double light_pos[3];
  double light_intensity;
  int width, height; /* pixels */
  int spp;           /* samples per pixel, >= 1 */
  uint64_t seed;
  /* Tile worker threads (OpenMP); 0: 1 in NEURAL mode, where OpenBLAS threads the network
   * instead (OpenMP around OpenBLAS measured 3-50x slower, docs/ARCHITECTURE.md), and all
   * cores in REFERENCE mode. The image does not depend on it. */
  int threads;
  /* 1: trilinear across mip levels by pixel footprint (default); 0: level 0 only. */
  int mip;
  double plane_repeat; /* NBRDF_SCENE_PLANE: world units per texture repeat (> 0) */
  /* NBRDF_RENDER_REFERENCE: one BRDF per colour channel of the texture (1 or 3 handles). */
  const nbrdf_brdf *const *reference;
  int reference_channels;
  /* Stage "render", done/total in tiles, at most ~10 times a second (and at
   * the last tile); non-zero return cancels. Called from the tile threads,
   * one call at a time. May be NULL. */
  nbrdf_progress_fn progress;
  void *user;
  /* Cancels when non-zero; checked between tiles and between a tile's
   * batches of samples (docs/RELIABILITY.md). May be NULL. */
  volatile sig_atomic_t *cancel;
  /* NBRDF_SCENE_MESH: glTF 2.0 (.gltf, .glb), PLY (ASCII or binary little-endian) or OBJ,
   * chosen by the extension; every triangle needs texture coordinates. Y up, like glTF. The
   * mesh casts shadows on itself (direct lighting with visibility). */
  const char *mesh_path;
  /* The camera: camera_set 0 keeps each scene's own view (the mesh scene frames the mesh's
   * bounding sphere from +z, a little above); 1 places it at camera_pos looking at
   * camera_target with camera_up (world units, y up). fov_deg: the vertical field of view
   * in degrees, (0, 180); 0 keeps the scene's (40° sphere and mesh, 50° plane). */
  int camera_set;
  double camera_pos[3], camera_target[3], camera_up[3];
  double fov_deg;
  /* Turns the environment about +y by this many degrees (a right-handed rotation:
   * counter-clockwise seen from above); its sampling table turns with it. */
  double env_rotation_deg;
} nbrdf_render_options;

#define NBRDF_RENDER_OPTIONS_DEFAULT                                                               \
  {                                                                                                \
    NBRDF_RENDER_NEURAL, NBRDF_SCENE_SPHERE, NBRDF_ENV_SKY, NULL, {1.0f, 1.0f, 1.0f}, 1.0f,        \
        {3.0, 4.0, 4.0}, 0.0, 256, 256, 16, 0u, 0, 1, 1.0, NULL, 0, NULL, NULL, NULL, NULL, 0,     \
        {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 0.0, 0.0                                \
  }

typedef struct nbrdf_render_stats {
  size_t decoded;    /* decoder queries (one per colour channel) */
  size_t brdf_evals; /* ground-truth evaluations and samples (REFERENCE) */
  int colour_channels;
  int levels;    /* mip levels of the texture */
  int triangles; /* NBRDF_SCENE_MESH: triangles of the mesh */
  /* NEURAL: seconds spent in the decoder (summed over threads), so that
   * decoded / decode_seconds is the decoder's rate inside the renderer. */
  double decode_seconds;
} nbrdf_render_stats;

/* Renders the texture at `latent_path` into `rgb` (width × height × 3 linear
 * floats, rows top to bottom). `model` must be the bundle the texture was
 * baked with (checked) in NEURAL mode; it may be NULL in REFERENCE mode.
 * Pixels that see the environment hold its radiance. `stats` may be NULL. */
nbrdf_status nbrdf_render(const nbrdf_model *model, const char *latent_path,
                          const nbrdf_render_options *options, float *rgb,
                          nbrdf_render_stats *stats, nbrdf_error *err);

/* Writes a rendered image: a linear float RGB EXR at `exr_path` (may be NULL)
 * and an 8-bit PNG through an OpenColorIO view transform at `png_path` (may
 * be NULL): `display` is a colour space name (as the bake's colour maps take)
 * looked up in `ocio_config` (NULL: $OCIO, then the built-in "srgb"), applied
 * in the inverse direction (linear -> display). Both files appear whole or
 * not at all, and together: when either cannot be written, neither is. */
nbrdf_status nbrdf_render_write(const char *exr_path, const char *png_path, int width, int height,
                                const float *rgb, const char *display, const char *ocio_config,
                                nbrdf_error *err);

/* Lobe images (docs/METRICS.md: 64×64 at θi = 0°, 30°, 60°, 80°) of texel
 * (x, y) of mip level `level` of the texture, decoded with `model` (the
 * bundle it was baked with), written to `png_path`: one row per colour
 * channel and θi. With `reference` (1 handle, or one per colour channel of
 * the texture; may be NULL) the rows show ground truth | decoded |
 * difference, the ground truth estimated with `spp` random walks per pixel
 * and `seed`, and *lobe_error (may be NULL) receives the lobe error of all
 * images together (a fraction; NaN without a reference). */
nbrdf_status nbrdf_render_lobes(const nbrdf_model *model, const char *latent_path, int x, int y,
                                int level, const nbrdf_brdf *const *reference,
                                int reference_channels, int spp, uint64_t seed,
                                const char *png_path, double *lobe_error, nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
