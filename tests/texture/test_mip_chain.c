/* The streaming mip builder against brute-force footprint means written out
 * here independently of src/texture/mip_chain.c. */
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/rng.h"
#include "testing.h"
#include "texture/mip_chain.h"

static void test_level_sizes_match_openexr_round_down(void) {
  /* 67x45: what OpenImageIO reports for an OpenEXR ROUND_DOWN mip-map. */
  static const int w67[] = {67, 33, 16, 8, 4, 2, 1}, h45[] = {45, 22, 11, 5, 2, 1, 1};
  CHECK(texture_mip_level_count(67, 45) == 7);
  for (int l = 0; l < 7; l++) {
    CHECK(texture_mip_level_dim(67, l) == w67[l]);
    CHECK(texture_mip_level_dim(45, l) == h45[l]);
  }
  CHECK(texture_mip_level_count(1, 1) == 1);
  CHECK(texture_mip_level_count(1, 17) == 5);
  CHECK(texture_mip_level_count(129, 64) == 8);
  CHECK(texture_mip_level_count(8192, 8192) == 14);
  CHECK(texture_mip_level_dim(17, 4) == 1 && texture_mip_level_dim(1, 4) == 1);
}

static void test_footprints_partition_level0(void) {
  static const int dims[] = {1, 2, 3, 17, 45, 67, 129, 300};
  for (size_t d = 0; d < sizeof dims / sizeof dims[0]; d++) {
    int n0 = dims[d];
    for (int l = 0; l < texture_mip_level_count(n0, 1); l++) {
      int next = 0, ok = 1;
      for (int i = 0; i < texture_mip_level_dim(n0, l); i++) {
        int b, e;
        texture_mip_footprint(n0, l, i, &b, &e);
        ok = ok && b == next && e > b && e - b < (2 << l);
        next = e;
      }
      CHECK_MSG(ok && next == n0, "footprints of level %d do not tile [0, %d)", l, n0);
    }
  }
}

typedef struct {
  int W, H, C, levels;
  float *got[NBRDF_MIP_MAX_LEVELS];
  int rows_seen[NBRDF_MIP_MAX_LEVELS];
  int order_ok;
} sink;

static nbrdf_status collect(void *user, int level, int y, float *row, nbrdf_error *err) {
  sink *s = user;
  int w = texture_mip_level_dim(s->W, level);
  if (y != s->rows_seen[level]) s->order_ok = 0;
  s->rows_seen[level]++;
  memcpy(s->got[level] + (size_t)y * w * s->C, row, sizeof(float) * (size_t)w * s->C);
  row[0] = -12345.0f; /* the callee may scribble on the row */
  return NBRDF_OK;
}

/* Mean over [x<<l, x==last ? W : (x+1)<<l) x (same for y), in double. */
static double brute_mean(const float *l0, int W, int H, int C, int l, int x, int y, int c) {
  int wl = W >> l < 1 ? 1 : W >> l, hl = H >> l < 1 ? 1 : H >> l;
  int x0 = x << l, x1 = x == wl - 1 ? W : (x + 1) << l;
  int y0 = y << l, y1 = y == hl - 1 ? H : (y + 1) << l;
  double sum = 0;
  for (int yy = y0; yy < y1; yy++)
    for (int xx = x0; xx < x1; xx++)
      sum += l0[((size_t)yy * W + xx) * C + c];
  return sum / ((double)(x1 - x0) * (y1 - y0));
}

static void check_size(int W, int H, int C) {
  nbrdf_error e, *err = &e;
  core_rng rng;
  core_rng_init(&rng, 11, (uint64_t)(W * 1000 + H));
  float *l0 = malloc(sizeof(float) * (size_t)W * H * C);
  for (size_t i = 0; i < (size_t)W * H * C; i++)
    l0[i] = (float)(4 * core_rng_uniform(&rng) - 2);
  sink s = {W, H, C, texture_mip_level_count(W, H), {0}, {0}, 1};
  for (int l = 0; l < s.levels; l++)
    s.got[l] = calloc((size_t)texture_mip_level_dim(W, l) * texture_mip_level_dim(H, l) * C,
                      sizeof(float));
  texture_mip_builder *b = NULL;
  CHECK_OK(texture_mip_builder_create(W, H, C, s.levels, collect, &s, &b, err), err);
  for (int y = 0; b && y < H; y++)
    CHECK_OK(texture_mip_builder_push_row(b, l0 + (size_t)y * W * C, err), err);
  if (b) CHECK_FAILS(texture_mip_builder_push_row(b, l0, err), NBRDF_ERR_ARGUMENT, err, "row");
  texture_mip_builder_free(b);
  CHECK(s.order_ok);
  double worst = 0;
  for (int l = 0; l < s.levels; l++) {
    int wl = texture_mip_level_dim(W, l), hl = texture_mip_level_dim(H, l);
    CHECK_MSG(s.rows_seen[l] == hl, "%dx%d level %d: %d of %d rows", W, H, l, s.rows_seen[l], hl);
    for (int y = 0; y < hl; y++)
      for (int x = 0; x < wl; x++)
        for (int c = 0; c < C; c++) {
          double want = brute_mean(l0, W, H, C, l, x, y, c);
          double got = s.got[l][((size_t)y * wl + x) * C + c];
          worst = fmax(worst, fabs(got - want));
        }
    free(s.got[l]);
  }
  CHECK_MSG(worst < 1e-6, "%dx%d: worst deviation from footprint means %g", W, H, worst);
  free(l0);
}

static void test_levels_are_footprint_means(void) {
  check_size(67, 45, 3);
  check_size(300, 200, 2);
  check_size(1, 1, 4);
  check_size(1, 17, 3);
  check_size(129, 64, 2);
  check_size(5, 3, 1);
}

/* For powers of two the chain is plain 2x2 averaging, level by level. */
static nbrdf_status keep(void *user, int level, int y, float *row, nbrdf_error *err) {
  float **levels = user;
  int w = 16 >> level;
  memcpy(levels[level] + (size_t)y * w, row, sizeof(float) * (size_t)w);
  return NBRDF_OK;
}

static void test_power_of_two_is_2x2_average(void) {
  nbrdf_error e, *err = &e;
  float l0[16 * 16], l1[8 * 8], l2[4 * 4], l3[2 * 2], l4[1];
  float *levels[5] = {l0, l1, l2, l3, l4};
  float input[16 * 16];
  for (int i = 0; i < 256; i++)
    input[i] = (float)((i * 37) % 101) / 7.0f;
  texture_mip_builder *b = NULL;
  CHECK_OK(texture_mip_builder_create(16, 16, 1, 5, keep, levels, &b, err), err);
  for (int y = 0; b && y < 16; y++)
    CHECK_OK(texture_mip_builder_push_row(b, input + 16 * y, err), err);
  texture_mip_builder_free(b);
  for (int l = 1; l < 5; l++) {
    int w = 16 >> l;
    for (int y = 0; y < w; y++)
      for (int x = 0; x < w; x++) {
        const float *p = levels[l - 1];
        double avg = 0.25 * ((double)p[(2 * y) * 2 * w + 2 * x] + p[(2 * y) * 2 * w + 2 * x + 1] +
                             p[(2 * y + 1) * 2 * w + 2 * x] + p[(2 * y + 1) * 2 * w + 2 * x + 1]);
        CHECK_NEAR(levels[l][y * w + x], avg, 1e-5);
      }
  }
}

static nbrdf_status stop_at_level2(void *user, int level, int y, float *row, nbrdf_error *err) {
  (void)user;
  (void)row;
  if (level == 2) return core_fail(err, NBRDF_ERR_CANCELLED, "stopped at level 2 row %d", y);
  return NBRDF_OK;
}

static void test_errors(void) {
  nbrdf_error e, *err = &e;
  texture_mip_builder *b = NULL;
  CHECK_FAILS(texture_mip_builder_create(0, 4, 1, 1, keep, NULL, &b, err), NBRDF_ERR_ARGUMENT, err,
              "0x4");
  CHECK_FAILS(texture_mip_builder_create(8, 8, 1, 5, keep, NULL, &b, err), NBRDF_ERR_ARGUMENT, err,
              "1 to 4");
  CHECK(b == NULL);
  /* A sink's failure reaches the caller of push_row. */
  CHECK_OK(texture_mip_builder_create(8, 8, 1, 4, stop_at_level2, NULL, &b, err), err);
  float row[8] = {0};
  nbrdf_status st = NBRDF_OK;
  int y = 0;
  while (st == NBRDF_OK && y < 8)
    st = texture_mip_builder_push_row(b, row, err), y++;
  CHECK(st == NBRDF_ERR_CANCELLED && y == 4);
  texture_mip_builder_free(b);
}

int main(void) {
  RUN(test_level_sizes_match_openexr_round_down);
  RUN(test_footprints_partition_level0);
  RUN(test_levels_are_footprint_means);
  RUN(test_power_of_two_is_2x2_average);
  RUN(test_errors);
  return testing_finish();
}
