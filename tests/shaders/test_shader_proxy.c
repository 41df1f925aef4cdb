/* shaders/nbrdf_proxy.glsl against src/model/proxy.c (nbrdf_proxy_sample / _pdf): the same
 * uniforms must give the same direction and pdf, and the pdf of given direction pairs must
 * agree. σ spans the sampler's range (1e-3 .. 4, log-uniform), w ∈ [0, 1] with the
 * endpoints, ωi down to cos θ = 1e-4.
 *
 * Tolerances (float32 shader vs double C, on float-rounded inputs): directions within
 * 1e-4 (|Δω|, unit vectors; measured max 2.8e-5); the pdf returned with a sample within
 * 1e-3 relative of the C pdf at that direction, for σ >= 0.01. For σ < 0.01 the
 * Gaussian lobe is so narrow that the ~1e-7 rounding of ωo moves the density by
 * |∂ log p/∂ω| · 1e-7 ≈ 1e-7 / σ² · r: pdfs there are held to 2 %; samples whose reflected
 * direction lies within 1e-4 of the horizon may be valid on one side only and are skipped. */
#include "testing.h"

#ifdef NBRDF_HAVE_VULKAN
#include <stdlib.h>
#include <string.h>

#include "nbrdf/model.h"
#include "shader_fixture.h"

static vkh *vk;

static void test_sample_and_pdf(void) {
  const size_t n = 20000;
  core_rng rng;
  core_rng_init(&rng, 77, 3);
  float *cases = calloc(12 * n, sizeof(float));
  for (size_t k = 0; k < n; k++) {
    float *c = cases + 12 * k;
    c[0] = (float)(1e-3 * pow(4000.0, core_rng_uniform(&rng)));
    double uw = core_rng_uniform(&rng);
    c[1] = uw < 0.1 ? 0.0f : uw < 0.2 ? 1.0f : (float)core_rng_uniform(&rng);
    fixture_direction(&rng, c + 2);
    for (int j = 0; j < 3; j++)
      c[5 + j] = core_rng_uniformf(&rng);
    fixture_direction(&rng, c + 8);
  }
  vkh_buffer cb, rb;
  vkh_kernel kern;
  int rc = vkh_buffer_create(vk, 12 * n * 4, &cb);
  if (!rc) rc = vkh_buffer_create(vk, 8 * n * 4, &rb);
  if (!rc) rc = vkh_kernel_create(vk, "proxy.spv", 2, 4, 0, NULL, &kern);
  CHECK_MSG(rc == 0, "proxy kernel: %s", vkh_error(vk));
  if (rc) return;
  memcpy(cb.map, cases, 12 * n * 4);
  vkh_buffer *bind[2] = {&cb, &rb};
  vkh_kernel_bind(vk, &kern, bind);
  uint32_t count = (uint32_t)n;
  CHECK(vkh_run(vk, &kern, &count, (uint32_t)((n + 63) / 64), NULL) == 0);
  const float *r = rb.map;
  size_t valid = 0, lost = 0, skipped = 0, bad_dir = 0, bad_pdf = 0, bad_eval = 0;
  double worst_dir = 0, worst_pdf = 0, worst_eval = 0;
  for (size_t k = 0; k < n; k++) {
    const float *c = cases + 12 * k;
    double sigma = c[0], w = c[1], wi[3] = {c[2], c[3], c[4]}, u[3] = {c[5], c[6], c[7]};
    double wo_eval[3] = {c[8], c[9], c[10]};
    double wo[3], pdf;
    int ok = nbrdf_proxy_sample(sigma, w, wi, u, wo, &pdf);
    double tol = sigma >= 0.01 ? 1e-3 : 2e-2;
    /* pdf of given pairs: no sampling involved. */
    double pe = nbrdf_proxy_pdf(sigma, w, wi, wo_eval), ge = r[8 * k + 4];
    double ee = fabs(ge - pe) / fmax(pe, 1e-30);
    if (pe == 0.0) ee = ge == 0.0 ? 0.0 : 1.0;
    if (ee > worst_eval) worst_eval = ee;
    if (!(ee <= tol) && bad_eval++ < 3)
      printf("  pdf case %zu: sigma %g w %g: %.9g vs %.9g\n", k, sigma, w, ge, pe);
    int gpu_ok = r[8 * k + 3] > 0.0f;
    if (gpu_ok != ok) {
      /* Only at the horizon may float and double disagree on validity. */
      if (fabs(ok ? wo[2] : r[8 * k + 2]) < 1e-4) {
        skipped++;
        continue;
      }
      if (bad_dir++ < 3)
        printf("  case %zu: valid %d vs %d (wo.z %g vs %g)\n", k, gpu_ok, ok, r[8 * k + 2], wo[2]);
      continue;
    }
    if (!ok) {
      lost++;
      continue;
    }
    valid++;
    double d = 0;
    for (int j = 0; j < 3; j++)
      d += (r[8 * k + j] - wo[j]) * (r[8 * k + j] - wo[j]);
    d = sqrt(d);
    if (d > worst_dir) worst_dir = d;
    if (!(d <= 1e-4) && bad_dir++ < 3)
      printf("  case %zu: sigma %g w %g u (%g %g %g): |dwo| %g\n", k, sigma, w, u[0], u[1], u[2],
             d);
    /* The pdf the shader returns must be the density at the direction it returned: near
     * grazing reflections p ∝ 1 / (4 |ωo·h|) turns the 1e-7 rounding of ωo into
     * 1e-3 of pdf, so comparing with the C sample's own pdf would test float conditioning,
     * not the shader. */
    double wg[3] = {r[8 * k], r[8 * k + 1], r[8 * k + 2]};
    double pg = nbrdf_proxy_pdf(sigma, w, wi, wg);
    double ep = fabs(r[8 * k + 3] - pg) / pg;
    if (ep > worst_pdf && sigma >= 0.01) worst_pdf = ep;
    if (!(ep <= tol) && bad_pdf++ < 3)
      printf("  case %zu: sigma %g w %g: pdf %.9g vs %.9g (C sample's own %.9g)\n", k, sigma, w,
             r[8 * k + 3], pg, pdf);
  }
  printf("  %zu cases: %zu valid, %zu lost below the horizon, %zu at the horizon skipped; "
         "max |dwo| %.2e, pdf rel. error (sigma >= 0.01) %.2e, pdf of given pairs %.2e\n",
         n, valid, lost, skipped, worst_dir, worst_pdf, worst_eval);
  CHECK_MSG(bad_dir == 0, "%zu directions differ", bad_dir);
  CHECK_MSG(bad_pdf == 0, "%zu sample pdfs differ", bad_pdf);
  CHECK_MSG(bad_eval == 0, "%zu pdfs of given pairs differ", bad_eval);
  CHECK(valid > n / 2 && lost > 0 && skipped < n / 1000);
  vkh_kernel_destroy(vk, &kern);
  vkh_buffer_destroy(vk, &cb);
  vkh_buffer_destroy(vk, &rb);
  free(cases);
}

int main(void) {
  char msg[512];
  if (vkh_open(&vk, msg, sizeof msg) != 0) {
    fprintf(stderr, "Vulkan: %s\n", msg);
    return 1;
  }
  printf("device: %s\n", vkh_device_name(vk));
  RUN(test_sample_and_pdf);
  vkh_close(vk);
  return testing_finish();
}
#else
int main(void) {
  puts("shader tests not built: configured with NBRDF_BUILD_SHADERS=OFF");
  return 0;
}
#endif
