/* Proxy mixture sampling over colour channels (render_sampling.h). */
#include "render/render_sampling.h"

#include "nbrdf/model.h"

double render_proxy_mix_pdf(int channels, const float *sigma, const float *w, vec3 wi, vec3 wo) {
  double a[3] = {wi.x, wi.y, wi.z}, b[3] = {wo.x, wo.y, wo.z}, sum = 0.0;
  for (int c = 0; c < channels; c++)
    sum += nbrdf_proxy_pdf(sigma[c], w[c], a, b);
  return sum / channels;
}

int render_proxy_mix_sample(int channels, const float *sigma, const float *w, vec3 wi,
                            const double u[4], vec3 *wo, double *pdf) {
  int c = (int)(u[0] * channels);
  if (c >= channels) c = channels - 1;
  double a[3] = {wi.x, wi.y, wi.z}, b[3], p;
  if (!nbrdf_proxy_sample(sigma[c], w[c], a, u + 1, b, &p)) {
    *pdf = 0.0;
    return 0;
  }
  *wo = v3(b[0], b[1], b[2]);
  *pdf = channels == 1 ? p : render_proxy_mix_pdf(channels, sigma, w, wi, *wo);
  return *pdf > 0.0;
}
