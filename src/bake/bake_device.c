#include "bake/bake_device.h"

nbrdf_status bake_device_open(const nbrdf_model *model, const nbrdf_model *audit_model,
                              const nbrdf_bake_options *o, model_gpu **out, nbrdf_error *err) {
  unsigned nets = MODEL_GPU_LAYERING | MODEL_GPU_SAMPLER;
  if (o->energy_audit) nets |= MODEL_GPU_DECODER;
  char note[512];
  nbrdf_status st =
      model_gpu_open(model, audit_model, o->device, nets, out, note, sizeof note, err);
  if (st == NBRDF_OK && note[0] && o->note) o->note(o->user, note);
  return st;
}
