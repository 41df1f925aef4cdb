/* The six parameter sources of a bake, opened the one way both nbrdf_bake and
 * nbrdf verify read them, so a verification checks the texels the bake saw. */
#include "bake/bake_sources.h"

#include "core/error.h"
#include "model/material.h"

nbrdf_status bake_check_size(int width, int height, nbrdf_error *err) {
  if ((width == 0) != (height == 0) || width < 0 || height < 0 || width > NBRDF_BAKE_SIZE_MAX ||
      height > NBRDF_BAKE_SIZE_MAX)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "bake: output size %dx%d: width and height are each 1..%d (or both 0: "
                     "the maps' size)",
                     width, height, NBRDF_BAKE_SIZE_MAX);
  return NBRDF_OK;
}

/* Maps to the asked size, or to the largest one among them; without
 * resampling, a map of another size than the asked one is an error that
 * says how to resample. */
static nbrdf_status resize(const nbrdf_bake_inputs *in, texture_param_source **src,
                           nbrdf_error *err) {
  int W = in->width, H = in->height;
  if (W == 0 && in->resample == NBRDF_RESAMPLE_BILINEAR)
    for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
      int w, h;
      texture_param_source_size(src[id], &w, &h);
      W = w > W ? w : W, H = h > H ? h : H;
    }
  if (W == 0) return NBRDF_OK;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    texture_param_map *m = texture_param_source_get_map(src[id]);
    int w, h;
    texture_param_source_size(src[id], &w, &h);
    if (!m || (w == W && h == H)) continue;
    if (in->resample != NBRDF_RESAMPLE_BILINEAR)
      return core_fail(err, NBRDF_ERR_MISMATCH,
                       "%s: %s is %dx%d but the output size is %dx%d" TEXTURE_RESAMPLE_ADVICE,
                       model_material_param_name(id), texture_param_map_path(m), w, h, W, H);
    nbrdf_status st = texture_param_source_resample(src[id], W, H, err);
    if (st != NBRDF_OK) return st;
  }
  return NBRDF_OK;
}

nbrdf_status bake_open_sources(const nbrdf_bake_inputs *in, texture_param_source **src,
                               nbrdf_error *err) {
  nbrdf_status size_st = bake_check_size(in->width, in->height, err);
  if (size_st != NBRDF_OK) return size_st;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    const nbrdf_bake_param *p = &in->param[id];
    nbrdf_status st;
    if (p->path) {
      texture_param_map_options o = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
      if (id == NBRDF_BAKE_R0 || id == NBRDF_BAKE_ALBEDO) {
        o.kind = NBRDF_PARAM_COLOUR;
        o.colour_space = p->colour_space;
        o.ocio_config = in->ocio_config;
      }
      o.remap = p->remap, o.lo = p->lo, o.hi = p->hi;
      st = texture_param_source_map(model_material_param_name(id), p->path, &o, &src[id], err);
    } else {
      st = texture_param_source_constant(model_material_param_name(id), p->value, p->channels,
                                         &src[id], err);
    }
    if (st != NBRDF_OK) return st;
  }
  return resize(in, src, err);
}
