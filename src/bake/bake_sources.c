/* The six parameter sources of a bake, opened the one way both nbrdf_bake and
 * nbrdf verify read them, so a verification checks the texels the bake saw. */
#include "bake/bake_sources.h"

nbrdf_status bake_open_sources(const nbrdf_bake_inputs *in, nbrdf_param_source **src,
                               nbrdf_error *err) {
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    const nbrdf_bake_param *p = &in->param[id];
    nbrdf_status st;
    if (p->path) {
      nbrdf_param_map_options o = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
      if (id == NBRDF_BAKE_R0 || id == NBRDF_BAKE_ALBEDO) {
        o.kind = NBRDF_PARAM_COLOUR;
        o.colour_space = p->colour_space;
        o.ocio_config = in->ocio_config;
      }
      o.remap = p->remap, o.lo = p->lo, o.hi = p->hi;
      st = nbrdf_param_source_map(nbrdf_bake_param_name((nbrdf_bake_param_id)id), p->path, &o, &src[id], err);
    } else {
      st = nbrdf_param_source_constant(nbrdf_bake_param_name((nbrdf_bake_param_id)id), p->value, p->channels, &src[id], err);
    }
    if (st != NBRDF_OK) return st;
  }
  if (in->resample != NBRDF_RESAMPLE_BILINEAR) return NBRDF_OK;
  int W = 0, H = 0;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    int w, h;
    nbrdf_param_source_size(src[id], &w, &h);
    W = w > W ? w : W, H = h > H ? h : H;
  }
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    nbrdf_status st = nbrdf_param_source_resample(src[id], W, H, err);
    if (st != NBRDF_OK) return st;
  }
  return NBRDF_OK;
}
