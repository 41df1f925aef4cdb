/* Latent EXR round trips at odd sizes, every mip level, half and float,
 * mono and RGB, read back through OpenEXRCore (our reader). */
#include <OpenEXR/openexr.h> /* tests do not get OpenEXR's include path */
#include <omp.h>
#include <stdio.h>

#include "latent_fixture.h"

typedef struct {
  int W, H;
} size2;

static const size2 sizes[] = {{67, 45}, {300, 200}, {1, 1}, {1, 17}, {129, 64}};

static void round_trip_seeded(int W, int H, texture_latent_layout layout,
                              texture_latent_storage storage, int tile,
                              texture_latent_compression comp, int band, uint64_t seed) {
  nbrdf_error e, *err = &e;
  char path[512];
  snprintf(path, sizeof path, "%s/rt_%dx%d_%s_%s_%d.exr", testing_tmpdir(), W, H,
           texture_colour_mode_name(layout.colour), texture_latent_storage_name(storage), tile);
  float *l0 = fixture_texels(W, H, &layout, seed);
  texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  opts.storage = storage;
  opts.tile_size = tile;
  opts.compression = comp;
  texture_latent_meta meta = {"test-model", "abc123", "alpha1=0.5", "samples=1", NULL, 0, NULL, NULL};
  CHECK_OK(fixture_write(path, W, H, &layout, &meta, &opts, l0, band, err), err);

  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path, err), err);
  if (!r) {
    free(l0);
    return;
  }
  const texture_latent_info *in = texture_latent_reader_info(r);
  int C = texture_latent_channel_count(&layout);
  CHECK(in->width == W && in->height == H && in->channels == C);
  CHECK(in->levels == texture_mip_level_count(W, H));
  CHECK(in->layout.latent_dim == layout.latent_dim && in->layout.colour == layout.colour &&
        in->layout.proxy == layout.proxy);
  CHECK(in->storage == storage && in->compression == comp);
  CHECK(in->tile_width == tile && in->tile_height == tile);
  CHECK(in->format_version == NBRDF_LATENT_FORMAT_V1 && in->decoder_size == 0); /* no decoder */
  CHECK(strcmp(in->model_name, "test-model") == 0 && strcmp(in->model_checksum, "abc123") == 0);
  CHECK(strcmp(in->sources, "alpha1=0.5") == 0 && strcmp(in->settings, "samples=1") == 0);
  CHECK(strcmp(in->mip_filter, NBRDF_MIP_FILTER_BOX) == 0);
  for (int l = 0; l < in->levels; l++) {
    int lw, lh;
    float *want = fixture_level(l0, W, H, C, l, &lw, &lh);
    float *got = malloc(sizeof(float) * (size_t)lw * lh * C);
    int rw = 0, rh = 0;
    CHECK_OK(texture_latent_reader_level_size(r, l, &rw, &rh, err), err);
    CHECK(rw == lw && rh == lh);
    CHECK_OK(texture_latent_reader_read(r, l, 0, 0, lw, lh, got, err), err);
    double worst = fixture_error(got, want, (size_t)lw * lh * C, storage);
    CHECK_MSG(worst <= 1.0, "%s level %d (%dx%d): error %.3g x tolerance", path, l, lw, lh, worst);
    if (l == 0 && storage == NBRDF_LATENT_FLOAT)
      CHECK_MSG(memcmp(got, l0, sizeof(float) * (size_t)W * H * C) == 0,
                "%s: float level 0 is not bit-exact", path);
    free(want);
    free(got);
  }
  texture_latent_reader_close(r);
  free(l0);
}

static void round_trip(int W, int H, texture_latent_layout layout, texture_latent_storage storage,
                       int tile, texture_latent_compression comp, int band) {
  round_trip_seeded(W, H, layout, storage, tile, comp, band, (uint64_t)(W * 7 + H));
}

static void test_round_trip_every_level(void) {
  texture_latent_layout rgb = {3, NBRDF_COLOUR_RGB, 1}, mono = {5, NBRDF_COLOUR_MONO, 0};
  for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
    for (int s = 0; s < 2; s++) {
      texture_latent_storage st = s ? NBRDF_LATENT_FLOAT : NBRDF_LATENT_HALF;
      /* 16-texel tiles give several tiles, and mis-sized edge tiles, at
       * several mip levels of these small sizes. */
      round_trip(sizes[i].W, sizes[i].H, rgb, st, 16, NBRDF_LATENT_PIZ, 7);
      round_trip(sizes[i].W, sizes[i].H, mono, st, 64, NBRDF_LATENT_ZIP, 64);
    }
}

static void test_paper_layout_and_compressions(void) {
  /* The paper's 32 latents per RGB channel with the proxy: 102 channels. */
  texture_latent_layout paper = {32, NBRDF_COLOUR_RGB, 1};
  static const texture_latent_compression comps[] = {
      NBRDF_LATENT_ZIP, NBRDF_LATENT_PIZ, NBRDF_LATENT_ZIPS, NBRDF_LATENT_RLE, NBRDF_LATENT_NONE};
  for (int c = 0; c < 5; c++)
    round_trip(67, 45, paper, NBRDF_LATENT_HALF, 32, comps[c], 45);
}

/* Small edge tiles of noisy latents do not compress and must be stored raw.
 * OpenEXRCore 3.1.5 gets this wrong when the compressor's output is exactly
 * as large as the raw chunk: it writes the compressor's bytes under the raw
 * size, and readers decode zlib output as pixels. These seeds hit that case
 * with ZIP (a 16x2 tile of level 0 at 75x50, 2x12 of level 4 at 300x200,
 * 4x8 of level 3 at 288x192); the other compressions are checked alike. */
static void test_incompressible_tiles(void) {
  texture_latent_layout mono = {3, NBRDF_COLOUR_MONO, 1};
  static const texture_latent_compression comps[] = {NBRDF_LATENT_ZIP, NBRDF_LATENT_ZIPS,
                                                     NBRDF_LATENT_PIZ, NBRDF_LATENT_RLE};
  static const int odd[][2] = {{75, 50}, {300, 200}, {288, 192}};
  for (int c = 0; c < 4; c++)
    for (int i = 0; i < 3; i++) {
      uint64_t seed = (uint64_t)(odd[i][0] + 31 * odd[i][1]);
      round_trip_seeded(odd[i][0], odd[i][1], mono, NBRDF_LATENT_HALF, 16, comps[c], 13, seed);
    }
}

static void test_default_compression(void) {
  nbrdf_error e, *err = &e;
  texture_latent_layout layout = {2, NBRDF_COLOUR_MONO, 0};
  float *l0 = fixture_texels(9, 9, &layout, 2);
  char path[512];
  snprintf(path, sizeof path, "%s/default.exr", testing_tmpdir());
  CHECK_OK(fixture_write(path, 9, 9, &layout, NULL, NULL, l0, 9, err), err);
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path, err), err);
  if (r) {
    const texture_latent_info *in = texture_latent_reader_info(r);
    CHECK(in->compression == NBRDF_LATENT_ZIP && in->storage == NBRDF_LATENT_HALF);
    CHECK(in->tile_width == 64 && in->levels == 4);
  }
  texture_latent_reader_close(r);
  texture_latent_compression c;
  CHECK(texture_latent_compression_parse("piz", &c) && c == NBRDF_LATENT_PIZ);
  CHECK(strcmp(texture_latent_compression_name(NBRDF_LATENT_ZIPS), "zips") == 0);
  CHECK(!texture_latent_compression_parse("dwaa", &c));
  free(l0);
}

static void test_read_rectangle_and_channels(void) {
  nbrdf_error e, *err = &e;
  texture_latent_layout layout = {4, NBRDF_COLOUR_RGB, 1};
  char path[512];
  snprintf(path, sizeof path, "%s/rect.exr", testing_tmpdir());
  float *l0 = fixture_texels(70, 50, &layout, 5);
  texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  opts.storage = NBRDF_LATENT_FLOAT;
  opts.tile_size = 16;
  CHECK_OK(fixture_write(path, 70, 50, &layout, NULL, &opts, l0, 50, err), err);
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path, err), err);
  if (!r) return;
  int C = texture_latent_channel_count(&layout);
  /* A rectangle straddling tile borders equals the same texels of level 0. */
  float rect[13 * 21 * 18];
  CHECK_OK(texture_latent_reader_read(r, 0, 9, 14, 13, 21, rect, err), err);
  int same = 1;
  for (int y = 0; y < 21; y++)
    for (int x = 0; x < 13; x++)
      same &= memcmp(rect + ((size_t)y * 13 + x) * C, l0 + ((size_t)(y + 14) * 70 + x + 9) * C,
                     sizeof(float) * C) == 0;
  CHECK(same);
  /* Named channels, in the caller's order. */
  const char *names[] = {"proxy.w.B", "latent.L02.G"};
  float two[2 * 3];
  CHECK_OK(texture_latent_reader_read_channels(r, 0, 68, 49, 2, 1, names, 2, two, err), err);
  for (int x = 0; x < 2; x++) {
    const float *t = l0 + ((size_t)49 * 70 + 68 + x) * C;
    CHECK(two[2 * x] == t[texture_latent_index_w(&layout, 2)]);
    CHECK(two[2 * x + 1] == t[texture_latent_index_latent(&layout, 1, 2)]);
  }
  const char *bad[] = {"latent.L09.G"}, *dup[] = {"proxy.w.B", "proxy.w.B"};
  CHECK_FAILS(texture_latent_reader_read_channels(r, 0, 0, 0, 1, 1, bad, 1, two, err),
              NBRDF_ERR_ARGUMENT, err, "no channel 'latent.L09.G'");
  CHECK_FAILS(texture_latent_reader_read_channels(r, 0, 0, 0, 1, 1, dup, 2, two, err),
              NBRDF_ERR_ARGUMENT, err, "twice");
  CHECK_FAILS(texture_latent_reader_read(r, 0, 60, 0, 11, 1, rect, err), NBRDF_ERR_ARGUMENT, err,
              "outside level 0");
  CHECK_FAILS(texture_latent_reader_read(r, 7, 0, 0, 1, 1, rect, err), NBRDF_ERR_ARGUMENT, err,
              "level 7");
  texture_latent_reader_close(r);
  free(l0);
}

static void test_single_level_option(void) {
  nbrdf_error e, *err = &e;
  texture_latent_layout layout = {2, NBRDF_COLOUR_MONO, 0};
  char path[512];
  snprintf(path, sizeof path, "%s/one.exr", testing_tmpdir());
  float *l0 = fixture_texels(40, 30, &layout, 9);
  texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  opts.mip_levels = 1;
  CHECK_OK(fixture_write(path, 40, 30, &layout, NULL, &opts, l0, 30, err), err);
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path, err), err);
  if (r) CHECK(texture_latent_reader_info(r)->levels == 1);
  texture_latent_reader_close(r);
  opts.mip_levels = 3;
  texture_latent_writer *w = NULL;
  CHECK_FAILS(texture_latent_writer_create(&w, path, 40, 30, &layout, NULL, &opts, NULL, 0, err),
              NBRDF_ERR_ARGUMENT, err, "full chain");
  free(l0);
}

/* The mip row hook sees every row of every level >= 1, and what it writes is
 * what is stored. */
static nbrdf_status zero_proxy(void *user, int level, int y, float *row, int width,
                               nbrdf_error *err) {
  int *calls = user;
  (*calls)++;
  for (int x = 0; x < width; x++)
    row[x * 3 + 1] = row[x * 3 + 2] = (float)level;
  return NBRDF_OK;
}

static void test_mip_row_hook(void) {
  nbrdf_error e, *err = &e;
  texture_latent_layout layout = {1, NBRDF_COLOUR_MONO, 1};
  char path[512];
  snprintf(path, sizeof path, "%s/hook.exr", testing_tmpdir());
  float *l0 = fixture_texels(20, 12, &layout, 3);
  int calls = 0;
  texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  opts.mip_row = zero_proxy;
  opts.mip_row_user = &calls;
  CHECK_OK(fixture_write(path, 20, 12, &layout, NULL, &opts, l0, 5, err), err);
  CHECK(calls == 6 + 3 + 1 + 1); /* rows of levels 1..4: 10x6, 5x3, 2x1, 1x1 */
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path, err), err);
  float t[3];
  if (r) {
    CHECK_OK(texture_latent_reader_read(r, 2, 4, 2, 1, 1, t, err), err);
    CHECK(t[1] == 2.0f && t[2] == 2.0f);
  }
  texture_latent_reader_close(r);
  free(l0);
}

/* Why the writer declares RANDOM_Y: with INCREASING_Y, OpenEXRCore refuses a
 * tile of level 1 before every tile of level 0 is written, yet a streaming
 * writer completes level-1 tiles while level 0 is still coming in. */
static void quiet(exr_const_context_t c, exr_result_t code, const char *msg) {
  (void)c;
  (void)code;
  (void)msg;
}

static void test_interleaved_levels_need_random_y(void) {
  char path[512];
  snprintf(path, sizeof path, "%s/order.exr", testing_tmpdir());
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = quiet; /* the refusal below is expected */
  exr_context_t c = NULL;
  int p = 0;
  CHECK(exr_start_write(&c, path, EXR_WRITE_FILE_DIRECTLY, &init) == EXR_ERR_SUCCESS);
  CHECK(exr_add_part(c, "", EXR_STORAGE_TILED, &p) == EXR_ERR_SUCCESS);
  CHECK(exr_initialize_required_attr_simple(c, p, 32, 32, EXR_COMPRESSION_NONE) == 0);
  CHECK(exr_set_tile_descriptor(c, p, 16, 16, EXR_TILE_MIPMAP_LEVELS, EXR_TILE_ROUND_DOWN) == 0);
  CHECK(exr_add_channel(c, p, "Y", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1) == 0);
  exr_lineorder_t order;
  CHECK(exr_get_lineorder(c, p, &order) == 0 && order == EXR_LINEORDER_INCREASING_Y);
  CHECK(exr_write_header(c) == EXR_ERR_SUCCESS);
  static float tile[16 * 16];
  CHECK(exr_write_tile_chunk(c, p, 0, 0, 0, 0, tile, sizeof tile) == EXR_ERR_SUCCESS);
  CHECK(exr_write_tile_chunk(c, p, 1, 0, 0, 0, tile, sizeof tile) == EXR_ERR_SUCCESS);
  CHECK(exr_write_tile_chunk(c, p, 0, 0, 1, 1, tile, sizeof tile) == EXR_ERR_INCORRECT_CHUNK);
  exr_finish(&c);

  /* Our files declare RANDOM_Y. */
  nbrdf_error e, *err = &e;
  texture_latent_layout layout = {1, NBRDF_COLOUR_MONO, 0};
  float *l0 = fixture_texels(32, 32, &layout, 1);
  CHECK_OK(fixture_write(path, 32, 32, &layout, NULL, NULL, l0, 32, err), err);
  c = NULL;
  CHECK(exr_start_read(&c, path, NULL) == EXR_ERR_SUCCESS);
  CHECK(c && exr_get_lineorder(c, 0, &order) == 0 && order == EXR_LINEORDER_RANDOM_Y);
  if (c) exr_finish(&c);
  free(l0);
}

static unsigned char *slurp(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  unsigned char *buf = NULL;
  *n = 0;
  if (f && fseek(f, 0, SEEK_END) == 0) {
    long len = ftell(f);
    rewind(f);
    buf = malloc((size_t)len);
    *n = buf ? fread(buf, 1, (size_t)len, f) : 0;
  }
  if (f) fclose(f);
  return buf;
}

/* Tiles are compressed in parallel but written in order: the same bytes for
 * any number of threads (the Blender add-on's bake must equal the CLI's). */
static void test_bytes_independent_of_threads(void) {
  nbrdf_error e, *err = &e;
  /* Rows of tiles of levels 0 and 1 are large enough (> 1 MiB) to be
   * compressed in parallel. */
  texture_latent_layout layout = {4, NBRDF_COLOUR_RGB, 1};
  float *l0 = fixture_texels(600, 130, &layout, 21);
  char a[512], b[512];
  snprintf(a, sizeof a, "%s/threads1.exr", testing_tmpdir());
  snprintf(b, sizeof b, "%s/threads3.exr", testing_tmpdir());
  texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  opts.storage = NBRDF_LATENT_FLOAT;
  opts.compression = NBRDF_LATENT_ZIP;
  int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  CHECK_OK(fixture_write(a, 600, 130, &layout, NULL, &opts, l0, 9, err), err);
  omp_set_num_threads(3);
  CHECK_OK(fixture_write(b, 600, 130, &layout, NULL, &opts, l0, 9, err), err);
  omp_set_num_threads(saved);
  size_t na = 0, nb = 0;
  unsigned char *ba = slurp(a, &na), *bb = slurp(b, &nb);
  CHECK(ba && bb && na > 0 && na == nb && memcmp(ba, bb, na) == 0);
  free(ba);
  free(bb);
  free(l0);
}

int main(void) {
  RUN(test_round_trip_every_level);
  RUN(test_paper_layout_and_compressions);
  RUN(test_incompressible_tiles);
  RUN(test_default_compression);
  RUN(test_read_rectangle_and_channels);
  RUN(test_single_level_option);
  RUN(test_mip_row_hook);
  RUN(test_interleaved_levels_need_random_y);
  RUN(test_bytes_independent_of_threads);
  return testing_finish();
}
