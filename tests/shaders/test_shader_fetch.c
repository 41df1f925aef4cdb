/* shaders/nbrdf_latent_fetch.glsl against the C reference fetch (src/texture/latent_fetch.c):
 * bilinear within a level and trilinear across levels, GL_REPEAT wrapping, an odd-sized
 * mip chain (67 x 45, 7 levels), lods below 0 and past the last level. Then the whole
 * shading kernel (shaders/nbrdf_shade.comp: fetch + decode per colour + proxy pdf) against
 * texture_latent_fetch + nbrdf_model_decode + nbrdf_proxy_pdf on an untrained bundle, for
 * the per-invocation kernel, the tiled fp32 one (within 1e-5) and, where the device has
 * tensor cores (not lavapipe: skipped with a message), the fp16 cooperative-matrix one, and
 * that kernel with its matrix operations emulated (nbrdf_shade_coopemu.spv, lavapipe).
 *
 * Tolerances: the fetch does the C code's float operations in its order (`precise`), so
 * texels agree within 2e-6 absolute (values in [-2, 2]); shading within the decoder's 1e-4
 * (test_shader_decoder.c) and pdfs within 1e-3 relative. */
#include "testing.h"

#ifdef NBRDF_HAVE_VULKAN
#include <stdlib.h>
#include <string.h>

#include "texture/latent_fetch.h"
#include "model/bundle.h"
#include "shader_fixture.h"

static vkh *vk;

/* A random RGB texture with the proxy: latents in [-2, 2], sigma in [0.05, 1], w in [0, 1]. */
static texture_latent_image *random_image(int width, int height, int dim, uint64_t seed) {
  texture_latent_layout layout = {dim, NBRDF_COLOUR_RGB, 1};
  int levels = 1;
  while ((width >> levels) >= 1 || (height >> levels) >= 1)
    levels++;
  texture_latent_image *img = NULL;
  nbrdf_error err = {0};
  CHECK_OK(texture_latent_image_create(&layout, width, height, levels, &img, &err), &err);
  if (!img) return NULL;
  core_rng rng;
  core_rng_init(&rng, seed, 2);
  for (int l = 0; l < img->levels; l++)
    for (size_t t = 0; t < (size_t)img->width[l] * img->height[l]; t++)
      for (int c = 0; c < 3; c++) {
        float *texel = img->data[l] + t * img->channels;
        for (int k = 0; k < dim; k++)
          texel[texture_latent_index_latent(&layout, c, k)] = 4.0f * core_rng_uniformf(&rng) - 2.0f;
        texel[texture_latent_index_sigma(&layout, c)] = 0.05f + 0.95f * core_rng_uniformf(&rng);
        texel[texture_latent_index_w(&layout, c)] = core_rng_uniformf(&rng);
      }
  return img;
}

static uint32_t *pack(const texture_latent_image *img, size_t *n_words) {
  nbrdf_error err = {0};
  const float *data[TEXTURE_LATENT_MAX_LEVELS];
  for (int l = 0; l < img->levels; l++)
    data[l] = img->data[l];
  CHECK_OK(nbrdf_gpu_pack_latents(img->levels, img->width, img->height, img->channels,
                                  img->layout.latent_dim, 3, 1, data, NULL, 0, n_words, &err),
           &err);
  uint32_t *words = malloc(*n_words * 4);
  CHECK_OK(nbrdf_gpu_pack_latents(img->levels, img->width, img->height, img->channels,
                                  img->layout.latent_dim, 3, 1, data, words, *n_words, NULL, &err),
           &err);
  return words;
}

static void test_fetch(void) {
  texture_latent_image *img = random_image(67, 45, 8, 4);
  if (!img) return;
  CHECK(img->levels == 7);
  size_t n_words = 0;
  uint32_t *words = pack(img, &n_words);
  const size_t n = 4096;
  const int C = img->channels;
  float *q = malloc(sizeof(float) * 4 * n), *ref = malloc(sizeof(float) * C * n);
  core_rng rng;
  core_rng_init(&rng, 8, 1);
  for (size_t k = 0; k < n; k++) {
    float *c = q + 4 * k;
    c[0] = 4.0f * core_rng_uniformf(&rng) - 1.5f; /* repeats on both sides */
    c[1] = 4.0f * core_rng_uniformf(&rng) - 1.5f;
    c[2] = (float)(img->levels + 2) * core_rng_uniformf(&rng) - 1.0f;
    if (k % 16 == 0) c[2] = floorf(c[2]); /* exact levels: t = 0 */
    c[3] = k % 2 ? -1.0f : (float)(core_rng_u32(&rng) % (uint32_t)img->levels);
    if (c[3] >= 0)
      texture_latent_fetch_level(img, (int)c[3], c[0], c[1], ref + k * C);
    else
      texture_latent_fetch(img, c[0], c[1], c[2], ref + k * C);
  }
  vkh_buffer qb, lb, rb;
  vkh_kernel kern;
  int rc = vkh_buffer_create(vk, 16 * n, &qb);
  if (!rc) rc = vkh_buffer_create(vk, n_words * 4, &lb);
  if (!rc) rc = vkh_buffer_create(vk, sizeof(float) * C * n, &rb);
  if (!rc) rc = vkh_kernel_create(vk, "fetch.spv", 3, 4, 0, NULL, &kern);
  CHECK_MSG(rc == 0, "fetch kernel: %s", vkh_error(vk));
  if (!rc) {
    memcpy(qb.map, q, 16 * n);
    memcpy(lb.map, words, n_words * 4);
    vkh_buffer *bind[3] = {&qb, &lb, &rb};
    vkh_kernel_bind(vk, &kern, bind);
    uint32_t count = (uint32_t)n;
    CHECK(vkh_run(vk, &kern, &count, (uint32_t)((n + 63) / 64), NULL) == 0);
    const float *g = rb.map;
    double worst = 0;
    size_t bad = 0;
    for (size_t k = 0; k < n * C; k++) {
      double e = fabs(g[k] - ref[k]);
      if (!(e <= worst)) worst = e;
      if (!(e <= 2e-6) && bad++ < 3)
        printf("  query %zu channel %zu: %.9g vs %.9g (u %g v %g lod %g level %g)\n", k / C, k % C,
               g[k], ref[k], q[4 * (k / C)], q[4 * (k / C) + 1], q[4 * (k / C) + 2],
               q[4 * (k / C) + 3]);
    }
    printf("  %zu fetches x %d channels: max |error| %.2e\n", n, C, worst);
    CHECK_MSG(bad == 0, "%zu values differ", bad);
    vkh_kernel_destroy(vk, &kern);
  }
  vkh_buffer_destroy(vk, &qb);
  vkh_buffer_destroy(vk, &lb);
  vkh_buffer_destroy(vk, &rb);
  free(q), free(ref), free(words);
  texture_latent_image_free(img);
}

static void test_pack_refuses(void) {
  nbrdf_error err = {0};
  int w[2] = {8, 3}, h[2] = {4, 2};
  float texel[2 * 8 * 4 * 6];
  const float *data[2] = {texel, texel};
  size_t n;
  CHECK_FAILS(nbrdf_gpu_pack_latents(2, w, h, 6, 4, 1, 1, data, NULL, 0, &n, &err),
              NBRDF_ERR_ARGUMENT, &err, "round-down");
  w[1] = 4;
  CHECK_FAILS(nbrdf_gpu_pack_latents(2, w, h, 7, 4, 1, 1, data, NULL, 0, &n, &err),
              NBRDF_ERR_ARGUMENT, &err, "channels");
  CHECK_OK(nbrdf_gpu_pack_latents(2, w, h, 6, 4, 1, 1, data, NULL, 0, &n, &err), &err);
  CHECK(n == NBRDF_GPU_L_DATA + (8 * 4 + 4 * 2) * 6);
}

/* fetch + decode of R, G, B + proxy pdf of R, as a renderer's material kernel does. */
static void test_shade(void) {
  char dir[1024];
  snprintf(dir, sizeof dir, "%s/bundle", testing_tmpdir());
  nbrdf_error err = {0};
  CHECK_OK(model_bundle_init_random(dir, "shade-test", 7, "medium", &err), &err);
  nbrdf_model *model = NULL;
  CHECK_OK(nbrdf_model_load(dir, &model, &err), &err);
  if (!model) return;
  int dim = nbrdf_model_latent_dim(model);
  texture_latent_image *img = random_image(16, 12, dim, 6);
  size_t nl = 0, nw = 0;
  uint32_t *lwords = pack(img, &nl);
  CHECK_OK(nbrdf_gpu_pack_decoder(model, NULL, 0, &nw, &err), &err);
  uint32_t *wwords = malloc(nw * 4);
  CHECK_OK(nbrdf_gpu_pack_decoder(model, wwords, nw, NULL, &err), &err);
  const size_t n = 2048;
  const int C = img->channels;
  float *q = malloc(sizeof(float) * 9 * n), *texel = malloc(sizeof(float) * C);
  float *lat = malloc(sizeof(float) * 3 * dim * n), *f = malloc(sizeof(float) * 3 * n);
  float *wi = malloc(sizeof(float) * 3 * n), *wo = malloc(sizeof(float) * 3 * n);
  double *pdf = malloc(sizeof(double) * n);
  core_rng rng;
  core_rng_init(&rng, 10, 1);
  for (size_t k = 0; k < n; k++) {
    float *c = q + 9 * k;
    c[0] = core_rng_uniformf(&rng);
    c[1] = core_rng_uniformf(&rng);
    c[2] = 5.0f * core_rng_uniformf(&rng);
    fixture_direction(&rng, c + 3);
    fixture_direction(&rng, c + 6);
    memcpy(wi + 3 * k, c + 3, 12);
    memcpy(wo + 3 * k, c + 6, 12);
    texture_latent_fetch(img, c[0], c[1], c[2], texel);
    for (int ch = 0; ch < 3; ch++)
      for (int i = 0; i < dim; i++)
        lat[(k * 3 + ch) * dim + i] = texel[texture_latent_index_latent(&img->layout, ch, i)];
    double dwi[3] = {c[3], c[4], c[5]}, dwo[3] = {c[6], c[7], c[8]};
    pdf[k] = nbrdf_proxy_pdf(texel[texture_latent_index_sigma(&img->layout, 0)],
                             texel[texture_latent_index_w(&img->layout, 0)], dwi, dwo);
  }
  CHECK_OK(nbrdf_model_decode(model, n, 3, lat, wi, wo, f, &err), &err);
  /* The per-invocation kernel, the tiled fp32 one and (on a device with
   * VK_NV_cooperative_matrix) the tensor-core one, on the same buffers. */
  vkh_buffer wb, lb, qb, rb;
  /* room for the fp16 kernels' weights: the words and their fp16 copy (nbrdf_tiled.h) */
  int rc = vkh_buffer_create(vk, nbrdf_tile_f16_words(wwords, nw) * 4, &wb);
  if (!rc) rc = vkh_buffer_create(vk, nl * 4, &lb);
  if (!rc) rc = vkh_buffer_create(vk, 36 * n, &qb);
  if (!rc) rc = vkh_buffer_create(vk, 16 * n, &rb);
  CHECK_MSG(rc == 0, "buffers: %s", vkh_error(vk));
  for (int kind = 0; kind < 4 && !rc; kind++) {
    const char *names[4] = {"nbrdf_shade.spv", "nbrdf_shade_tiled.spv", "nbrdf_shade_coop.spv",
                            "nbrdf_shade_coopemu.spv"};
    /* fp32: the tiled kernel sums each output in input order like the per-invocation one;
     * fp16 tensor cores: inputs and weights rounded to 11 bits (docs/SHADERS.md). */
    const double tol[4] = {1e-4, 1e-5, 0.25, 0.25};
    if (kind == 2 && !vkh_has_coop(vk)) {
      printf("  nbrdf_shade_coop.spv skipped: %s has no VK_NV_cooperative_matrix (fp16 16x16x16)\n",
             vkh_device_name(vk));
      continue;
    }
    if (kind == 3 && !vkh_has_f16(vk)) {
      printf("  nbrdf_shade_coopemu.spv skipped: no shaderFloat16 / quad operations\n");
      continue;
    }
    uint32_t spec[7] = {wwords[NBRDF_GPU_W_MAX_WIDTH]};
    uint32_t rows = 64, per = 1, n_spec = 1;
    nbrdf_tile_config cfg = {{0}, 64, 64, 0};
    if (kind > 0) {
      CHECK(nbrdf_tile_config_make(wwords, vkh_max_shared(vk), vkh_max_invocations(vk), kind >= 2,
                                   &cfg) == 0);
      memcpy(spec, cfg.spec, sizeof cfg.spec);
      rows = cfg.rows, per = 3, n_spec = 7;
    }
    vkh_kernel kern;
    int krc = vkh_kernel_create(vk, names[kind], 4, 4, (int)n_spec, spec, &kern);
    CHECK_MSG(krc == 0, "%s: %s", names[kind], vkh_error(vk));
    if (krc) continue;
    if (kind >= 2)
      nbrdf_tile_f16_pack(wwords, nw, wb.map);
    else
      memcpy(wb.map, wwords, nw * 4);
    memcpy(lb.map, lwords, nl * 4);
    memcpy(qb.map, q, 36 * n);
    memset(rb.map, 0xff, 16 * n); /* NaN: a value the kernel does not write fails */
    vkh_buffer *bind[4] = {&wb, &lb, &qb, &rb};
    vkh_kernel_bind(vk, &kern, bind);
    uint32_t count = (uint32_t)n;
    CHECK(vkh_run(vk, &kern, &count, (uint32_t)((n * per + rows - 1) / rows), NULL) == 0);
    const float *g = rb.map;
    double worst_f = 0, worst_p = 0;
    size_t bad = 0, positive = 0;
    for (size_t k = 0; k < n; k++) {
      for (int ch = 0; ch < 3; ch++) {
        double e = fabs(g[4 * k + ch] - f[3 * k + ch]) / (1.0 + f[3 * k + ch]);
        if (!(e <= worst_f)) worst_f = e;
        bad += !(e <= tol[kind]);
        positive += f[3 * k + ch] > 1e-3f;
      }
      double ep = fabs(g[4 * k + 3] - pdf[k]) / fmax(pdf[k], 1e-30);
      if (!(ep <= worst_p)) worst_p = ep;
      bad += !(ep <= 1e-3);
    }
    printf("  %-22s %zu shading queries: max error f %.2e, pdf %.2e; %zu of %zu f > 1e-3\n",
           names[kind], n, worst_f, worst_p, positive, 3 * n);
    CHECK_MSG(positive > n / 4, "only %zu values are positive", positive);
    CHECK_MSG(bad == 0, "%s: %zu shaded values differ", names[kind], bad);
    vkh_kernel_destroy(vk, &kern);
  }
  vkh_buffer_destroy(vk, &wb);
  vkh_buffer_destroy(vk, &lb);
  vkh_buffer_destroy(vk, &qb);
  vkh_buffer_destroy(vk, &rb);
  free(q), free(texel), free(lat), free(f), free(wi), free(wo), free(pdf), free(lwords),
      free(wwords);
  texture_latent_image_free(img);
  nbrdf_model_destroy(model);
}

int main(void) {
  char msg[512];
  if (vkh_open(&vk, msg, sizeof msg) != 0) {
    fprintf(stderr, "Vulkan: %s\n", msg);
    return 1;
  }
  printf("device: %s\n", vkh_device_name(vk));
  RUN(test_pack_refuses);
  RUN(test_fetch);
  RUN(test_shade);
  vkh_close(vk);
  return testing_finish();
}
#else
int main(void) {
  puts("shader tests not built: configured with NBRDF_BUILD_SHADERS=OFF");
  return 0;
}
#endif
