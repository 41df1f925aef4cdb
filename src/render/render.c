/* nbrdf_render: checks the options, loads the texture and the environment,
 * and shades fixed tiles in parallel (render.h). */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/progress.h"
#include "render/mesh_bvh.h"
#include "render/render_tile.h"

static nbrdf_status check_options(const nbrdf_model *model, const nbrdf_render_options *o,
                                  nbrdf_error *err) {
  if (o->mode != NBRDF_RENDER_NEURAL && o->mode != NBRDF_RENDER_REFERENCE)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "render: unknown mode %d", (int)o->mode);
  if (o->scene != NBRDF_SCENE_SPHERE && o->scene != NBRDF_SCENE_PLANE &&
      o->scene != NBRDF_SCENE_MESH)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "render: unknown scene %d", (int)o->scene);
  if (o->scene == NBRDF_SCENE_MESH && !o->mesh_path)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "render: the mesh scene needs a mesh file");
  if (o->fov_deg != 0.0 && !(o->fov_deg > 0.0 && o->fov_deg < 180.0))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "render: field of view %g degrees, expected 0 < fov < 180", o->fov_deg);
  if (o->camera_set) {
    render_camera probe;
    render_camera_setup(&probe, NBRDF_SCENE_SPHERE, 1, 1, 1.0);
    if (!render_camera_look(&probe, o->camera_pos, o->camera_target, o->camera_up, 0.0))
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "render: camera at (%g, %g, %g) looking at (%g, %g, %g) with up (%g, %g, "
                       "%g) is no view (expected position != target, up not along the view)",
                       o->camera_pos[0], o->camera_pos[1], o->camera_pos[2], o->camera_target[0],
                       o->camera_target[1], o->camera_target[2], o->camera_up[0], o->camera_up[1],
                       o->camera_up[2]);
  }
  if (o->width < 1 || o->height < 1 || o->width > 16384 || o->height > 16384)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "render: image %d x %d, expected 1..16384 each",
                     o->width, o->height);
  if (o->spp < 1 || o->spp > (1 << 20))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "render: %d samples per pixel, expected 1..2^20",
                     o->spp);
  if (o->threads < 0) return core_fail(err, NBRDF_ERR_ARGUMENT, "render: %d threads", o->threads);
  if (!(o->light_intensity >= 0.0) || !isfinite(o->light_intensity))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "render: light intensity %g is not finite and >= 0",
                     o->light_intensity);
  for (int k = 0; k < 3; k++)
    if (!isfinite(o->light_pos[k]))
      return core_fail(err, NBRDF_ERR_ARGUMENT, "render: light position is not finite");
  if (o->scene == NBRDF_SCENE_PLANE && !(o->plane_repeat > 0.0 && isfinite(o->plane_repeat)))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "render: plane repeat %g is not finite and > 0",
                     o->plane_repeat);
  if (o->mode == NBRDF_RENDER_NEURAL && !model)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "render: neural mode needs a model");
  if (o->mode == NBRDF_RENDER_REFERENCE) {
    if (!o->reference || (o->reference_channels != 1 && o->reference_channels != 3))
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "render: reference mode needs 1 or 3 ground-truth BRDFs, got %d",
                       o->reference_channels);
    for (int c = 0; c < o->reference_channels; c++)
      if (!o->reference[c])
        return core_fail(err, NBRDF_ERR_ARGUMENT, "render: reference BRDF %d is NULL", c);
  }
  return NBRDF_OK;
}

nbrdf_status nbrdf_render(const nbrdf_model *model, const char *latent_path,
                          const nbrdf_render_options *options, float *rgb,
                          nbrdf_render_stats *stats, nbrdf_error *err) {
  nbrdf_render_options defaults = NBRDF_RENDER_OPTIONS_DEFAULT;
  const nbrdf_render_options *o = options ? options : &defaults;
  nbrdf_status st = check_options(model, o, err);
  if (st != NBRDF_OK) return st;
  texture_latent_image *tex = NULL;
  render_env *env = NULL;
  render_mesh *mesh = NULL;
  render_bvh *bvh = NULL;
  /* Neural: the texture decoded as it asks, with its own decoder if it has one. */
  nbrdf_model *decoding = NULL;
  if (o->mode == NBRDF_RENDER_NEURAL)
    st = texture_latent_image_load_model(latent_path, model, &tex, &decoding, err);
  else
    st = texture_latent_image_load(latent_path, &tex, NULL, 0, err);
  if (st == NBRDF_OK) st = render_env_create(o, &env, err);
  if (st == NBRDF_OK && o->scene == NBRDF_SCENE_MESH) {
    st = render_mesh_load(o->mesh_path, &mesh, err);
    if (st == NBRDF_OK) st = render_bvh_build(mesh, &bvh, err);
  }
  if (st != NBRDF_OK) {
    texture_latent_image_free(tex);
    nbrdf_model_destroy(decoding);
    render_env_free(env);
    render_bvh_free(bvh);
    render_mesh_free(mesh);
    return st;
  }
  render_ctx ctx;
  memset(&ctx, 0, sizeof ctx);
  ctx.opts = o, ctx.model = decoding, ctx.tex = tex, ctx.env = env;
  ctx.colours =
      o->mode == NBRDF_RENDER_NEURAL ? texture_latent_colours(&tex->layout) : o->reference_channels;
  render_camera_setup(&ctx.cam, o->scene, o->width, o->height, o->plane_repeat);
  if (mesh) render_camera_set_mesh(&ctx.cam, mesh, bvh);
  if (o->camera_set)
    render_camera_look(&ctx.cam, o->camera_pos, o->camera_target, o->camera_up, o->fov_deg);
  else if (o->fov_deg > 0.0)
    ctx.cam.tan_half = tan(0.5 * o->fov_deg * M_PI / 180.0);

  int tx = (o->width + RENDER_TILE - 1) / RENDER_TILE;
  int ty = (o->height + RENDER_TILE - 1) / RENDER_TILE;
  int tiles = tx * ty, done = 0, stop = 0;
  int threads =
      o->threads ? o->threads : (o->mode == NBRDF_RENDER_NEURAL ? 1 : omp_get_max_threads());
  size_t decoded = 0, evals = 0;
  double decode_s = 0.0;
  nbrdf_error first = {NBRDF_OK, ""};
  core_ticker ticker; /* ticked inside the critical section below only */
  core_ticker_init(&ticker, o->progress, o->user, o->cancel);
  if (core_ticker_tick(&ticker, "render", 0, tiles, 1))
    core_fail(&first, NBRDF_ERR_CANCELLED, "render: cancelled before the first tile"), stop = 1;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+ : decoded, evals, decode_s)
  for (int t = 0; t < tiles; t++) {
    int halt;
#pragma omp atomic read
    halt = stop;
    if (halt) continue;
    int x0 = (t % tx) * RENDER_TILE, y0 = (t / tx) * RENDER_TILE;
    int w = o->width - x0 < RENDER_TILE ? o->width - x0 : RENDER_TILE;
    int h = o->height - y0 < RENDER_TILE ? o->height - y0 : RENDER_TILE;
    nbrdf_error e = {NBRDF_OK, ""};
    nbrdf_status ts = render_tile(&ctx, t, x0, y0, w, h, rgb, &decoded, &decode_s, &evals, &e);
#pragma omp critical(render_progress)
    {
      if (ts != NBRDF_OK && first.status == NBRDF_OK) first = e, first.status = ts;
      done++;
      if (ts != NBRDF_OK || core_ticker_tick(&ticker, "render", done, tiles, done == tiles)) {
        if (first.status == NBRDF_OK)
          core_fail(&first, NBRDF_ERR_CANCELLED, "render: cancelled after %d of %d tiles", done,
                    tiles);
#pragma omp atomic write
        stop = 1;
      }
    }
  }
  render_env_free(env);
  if (stats) {
    stats->triangles = mesh ? mesh->triangles : 0;
    stats->decoded = decoded, stats->brdf_evals = evals;
    stats->decode_seconds = decode_s;
    stats->colour_channels = ctx.colours, stats->levels = tex->levels;
  }
  texture_latent_image_free(tex);
  nbrdf_model_destroy(decoding);
  render_bvh_free(bvh);
  render_mesh_free(mesh);
  if (first.status != NBRDF_OK) {
    if (err) *err = first;
    return first.status;
  }
  return NBRDF_OK;
}
