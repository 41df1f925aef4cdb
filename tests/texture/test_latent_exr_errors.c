/* What a failed, cancelled or refused latent texture write leaves behind
 * (nothing), and how the reader refuses files that are not latent textures
 * of this version. */
#include <OpenEXR/openexr.h> /* tests do not get OpenEXR's include path */
#include <dirent.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include "latent_fixture.h"

static const texture_latent_layout mono2 = {2, NBRDF_COLOUR_MONO, 0};

/* Entries of a directory, "." and ".." excluded. */
static int count_entries(const char *dir) {
  DIR *d = opendir(dir);
  int n = 0;
  for (struct dirent *e; d && (e = readdir(d));)
    n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
  if (d) closedir(d);
  return n;
}

static void fresh_dir(char *buf, size_t n, const char *name) {
  snprintf(buf, n, "%s/%s", testing_tmpdir(), name);
  mkdir(buf, 0755);
}

static void test_abort_and_incomplete_leave_nothing(void) {
  nbrdf_error e, *err = &e;
  char dir[512], path[600];
  fresh_dir(dir, sizeof dir, "abort");
  snprintf(path, sizeof path, "%s/t.exr", dir);
  float *l0 = fixture_texels(30, 10, &mono2, 1);
  texture_latent_writer *w = NULL;
  CHECK_OK(texture_latent_writer_create(&w, path, 30, 10, &mono2, NULL, NULL, NULL, 0, err), err);
  /* The temporary file has no name (O_TMPFILE), or a hidden one where the file system
   * lacks O_TMPFILE. */
  CHECK(count_entries(dir) <= 1);
  if (w) CHECK_OK(texture_latent_writer_write_rows(w, l0, 4, err), err);
  texture_latent_writer_abort(w);
  CHECK(count_entries(dir) == 0);

  CHECK_OK(texture_latent_writer_create(&w, path, 30, 10, &mono2, NULL, NULL, NULL, 0, err), err);
  if (w) CHECK_OK(texture_latent_writer_write_rows(w, l0, 3, err), err);
  if (w)
    CHECK_FAILS(texture_latent_writer_finish(w, err), NBRDF_ERR_ARGUMENT, err, "only 3 of 10 rows");
  CHECK(count_entries(dir) == 0);

  CHECK_OK(texture_latent_writer_create(&w, path, 30, 10, &mono2, NULL, NULL, NULL, 0, err), err);
  if (w)
    CHECK_FAILS(texture_latent_writer_write_rows(w, l0, 11, err), NBRDF_ERR_ARGUMENT, err,
                "11 rows after 0 of 10");
  texture_latent_writer_abort(w);
  CHECK(count_entries(dir) == 0);
  free(l0);
}

static void test_bad_values_name_the_texel(void) {
  nbrdf_error e, *err = &e;
  char dir[512], path[600];
  fresh_dir(dir, sizeof dir, "values");
  snprintf(path, sizeof path, "%s/t.exr", dir);
  float *l0 = fixture_texels(30, 10, &mono2, 2);
  texture_latent_writer *w = NULL;
  l0[(3 * 30 + 7) * 2 + 1] = NAN;
  CHECK_OK(texture_latent_writer_create(&w, path, 30, 10, &mono2, NULL, NULL, NULL, 0, err), err);
  if (w)
    CHECK_FAILS(texture_latent_writer_write_rows(w, l0, 10, err), NBRDF_ERR_ARGUMENT, err,
                "texel (7, 3) latent.L01.Y is NaN");
  CHECK(count_entries(dir) == 0); /* gone at the error, before abort */
  if (w)
    CHECK_FAILS(texture_latent_writer_write_rows(w, l0, 1, err), NBRDF_ERR_ARGUMENT, err,
                "already failed");
  texture_latent_writer_abort(w);

  l0[(3 * 30 + 7) * 2 + 1] = 1e5f; /* beyond half's 65504 */
  CHECK_OK(texture_latent_writer_create(&w, path, 30, 10, &mono2, NULL, NULL, NULL, 0, err), err);
  if (w)
    CHECK_FAILS(texture_latent_writer_write_rows(w, l0, 10, err), NBRDF_ERR_ARGUMENT, err,
                "exceeds the half range");
  if (w) CHECK_FAILS(texture_latent_writer_finish(w, err), NBRDF_ERR_ARGUMENT, err, "failed");
  CHECK(count_entries(dir) == 0);
  texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  opts.storage = NBRDF_LATENT_FLOAT;
  CHECK_OK(fixture_write(path, 30, 10, &mono2, NULL, &opts, l0, 10, err), err);
  CHECK(count_entries(dir) == 1);
  free(l0);
}

static void test_never_overwrites_an_input(void) {
  nbrdf_error e, *err = &e;
  char dir[512], in[600], link[600], other[700];
  fresh_dir(dir, sizeof dir, "inputs");
  snprintf(in, sizeof in, "%s/alpha.exr", dir);
  snprintf(link, sizeof link, "%s/link.exr", dir);
  snprintf(other, sizeof other, "%s/../inputs/./alpha.exr", dir);
  testing_write_text(in, "an input map");
  CHECK(symlink(in, link) == 0);
  const char *inputs[] = {"/nonexistent/r0.png", other};
  texture_latent_writer *w = NULL;
  CHECK_FAILS(texture_latent_writer_create(&w, in, 8, 8, &mono2, NULL, NULL, inputs, 2, err),
              NBRDF_ERR_ARGUMENT, err, "refusing to overwrite an input");
  CHECK_FAILS(texture_latent_writer_create(&w, link, 8, 8, &mono2, NULL, NULL, inputs, 2, err),
              NBRDF_ERR_ARGUMENT, err, "refusing to overwrite an input");
  CHECK(w == NULL && testing_file_is(in, "an input map") && count_entries(dir) == 2);
}

static void test_unwritable_destinations(void) {
  nbrdf_error e, *err = &e;
  char dir[512], path[700];
  fresh_dir(dir, sizeof dir, "unwritable");
  texture_latent_writer *w = NULL;
  snprintf(path, sizeof path, "%s/no/such/dir/t.exr", dir);
  CHECK_FAILS(texture_latent_writer_create(&w, path, 8, 8, &mono2, NULL, NULL, NULL, 0, err),
              NBRDF_ERR_IO, err, "cannot create a file in");
  CHECK(strstr(e.message, "No such file or directory") != NULL);
  snprintf(path, sizeof path, "%s/file", dir);
  testing_write_text(path, "x");
  snprintf(path, sizeof path, "%s/file/t.exr", dir);
  CHECK_FAILS(texture_latent_writer_create(&w, path, 8, 8, &mono2, NULL, NULL, NULL, 0, err),
              NBRDF_ERR_IO, err, "Not a directory");
  CHECK_FAILS(texture_latent_writer_create(&w, dir, 8, 8, &mono2, NULL, NULL, NULL, 0, err),
              NBRDF_ERR_ARGUMENT, err, "is a directory");
  /* /proc refuses new files even to root. */
  CHECK_FAILS(
      texture_latent_writer_create(&w, "/proc/t.exr", 8, 8, &mono2, NULL, NULL, NULL, 0, err),
      NBRDF_ERR_IO, err, "/proc/t.exr: cannot create a file in '/proc'");
  CHECK(w == NULL && count_entries(dir) == 1);
}

static void test_replaces_only_on_success(void) {
  nbrdf_error e, *err = &e;
  char dir[512], path[600];
  fresh_dir(dir, sizeof dir, "replace");
  snprintf(path, sizeof path, "%s/t.exr", dir);
  testing_write_text(path, "previous bake");
  float *l0 = fixture_texels(16, 16, &mono2, 3);
  texture_latent_writer *w = NULL;
  CHECK_OK(texture_latent_writer_create(&w, path, 16, 16, &mono2, NULL, NULL, NULL, 0, err), err);
  if (w) CHECK_OK(texture_latent_writer_write_rows(w, l0, 8, err), err);
  texture_latent_writer_abort(w);
  CHECK(testing_file_is(path, "previous bake") && count_entries(dir) == 1);
  CHECK_OK(fixture_write(path, 16, 16, &mono2, NULL, NULL, l0, 16, err), err);
  texture_latent_reader *r = NULL;
  CHECK_OK(texture_latent_reader_open(&r, path, err), err);
  texture_latent_reader_close(r);
  CHECK(count_entries(dir) == 1);
  free(l0);
}

static void test_writer_arguments(void) {
  nbrdf_error e, *err = &e;
  char path[512];
  snprintf(path, sizeof path, "%s/args.exr", testing_tmpdir());
  texture_latent_writer *w = NULL;
  texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  texture_latent_layout zero = {0, NBRDF_COLOUR_RGB, 0}, odd = {4, (texture_colour_mode)2, 0};
  CHECK_FAILS(texture_latent_writer_create(&w, path, 0, 8, &mono2, NULL, NULL, NULL, 0, err),
              NBRDF_ERR_ARGUMENT, err, "size 0x8");
  CHECK_FAILS(texture_latent_writer_create(&w, path, 8, 8, &zero, NULL, NULL, NULL, 0, err),
              NBRDF_ERR_ARGUMENT, err, "latent dimension 0");
  CHECK_FAILS(texture_latent_writer_create(&w, path, 8, 8, &odd, NULL, NULL, NULL, 0, err),
              NBRDF_ERR_ARGUMENT, err, "colour mode 2");
  opts.tile_size = 4;
  CHECK_FAILS(texture_latent_writer_create(&w, path, 8, 8, &mono2, NULL, &opts, NULL, 0, err),
              NBRDF_ERR_ARGUMENT, err, "tile size 4");
  CHECK(w == NULL && access(path, F_OK) != 0);
}

/* Changes an int attribute of an existing file in place, patching the bytes
 * "name\0int\0" + size (4) + value (4, little-endian): OpenEXRCore 3.1.5's
 * exr_start_inplace_header_update refuses these files. */
static int set_int_attr(const char *path, const char *name, int value) {
  static unsigned char buf[1 << 16];
  FILE *f = fopen(path, "r+b");
  if (!f) return 0;
  size_t n = fread(buf, 1, sizeof buf, f);
  char key[64];
  int klen = snprintf(key, sizeof key, "%s%cint", name, 0) + 1;
  int done = 0;
  for (size_t i = 0; !done && i + (size_t)klen + 8 <= n; i++)
    if (memcmp(buf + i, key, (size_t)klen) == 0) {
      unsigned char v[4] = {(unsigned char)value, (unsigned char)(value >> 8),
                            (unsigned char)(value >> 16), (unsigned char)(value >> 24)};
      done = fseek(f, (long)(i + (size_t)klen + 4), SEEK_SET) == 0 && fwrite(v, 1, 4, f) == 4;
    }
  return fclose(f) == 0 && done;
}

static void test_reader_refusals(void) {
  nbrdf_error e, *err = &e;
  char dir[512], path[600], text[600];
  fresh_dir(dir, sizeof dir, "reader");
  texture_latent_reader *r = NULL;
  snprintf(path, sizeof path, "%s/missing.exr", dir);
  CHECK_FAILS(texture_latent_reader_open(&r, path, err), NBRDF_ERR_IO, err, "cannot open");
  CHECK_FAILS(texture_latent_reader_open(&r, dir, err), NBRDF_ERR_IO, err,
              "is a directory, not a file");
  snprintf(text, sizeof text, "%s/text.exr", dir);
  testing_write_text(text, "not an image at all");
  CHECK_FAILS(texture_latent_reader_open(&r, text, err), NBRDF_ERR_FORMAT, err,
              "not a readable OpenEXR file");

  /* A tiled mip-mapped EXR without nbrdf's attributes. */
  snprintf(path, sizeof path, "%s/plain.exr", dir);
  exr_context_t c = NULL;
  int p = 0;
  static float tile[8 * 8];
  if (exr_start_write(&c, path, EXR_WRITE_FILE_DIRECTLY, NULL) == 0) {
    exr_add_part(c, "", EXR_STORAGE_TILED, &p);
    exr_initialize_required_attr_simple(c, p, 8, 8, EXR_COMPRESSION_NONE);
    exr_set_tile_descriptor(c, p, 8, 8, EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN);
    exr_add_channel(c, p, "Y", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    exr_write_header(c);
    exr_write_tile_chunk(c, p, 0, 0, 0, 0, tile, sizeof tile);
    exr_finish(&c);
  }
  CHECK_FAILS(texture_latent_reader_open(&r, path, err), NBRDF_ERR_FORMAT, err,
              "no nbrdf:formatVersion attribute");

  snprintf(path, sizeof path, "%s/t.exr", dir);
  float *l0 = fixture_texels(20, 20, &mono2, 4);
  texture_latent_meta meta = {"model-a", "1111", NULL, NULL, NULL, 0, NULL, NULL};
  CHECK_OK(fixture_write(path, 20, 20, &mono2, &meta, NULL, l0, 20, err), err);
  CHECK_OK(texture_latent_reader_open(&r, path, err), err);
  if (r) {
    const texture_latent_info *in = texture_latent_reader_info(r);
    CHECK_OK(texture_latent_check_model(in, path, "model-a", "1111", err), err);
    CHECK_FAILS(texture_latent_check_model(in, path, "model-a", "2222", err), NBRDF_ERR_MISMATCH,
                err, "baked with model 'model-a' (checksum 1111)");
    CHECK_FAILS(texture_latent_check_model(in, path, "model-b", NULL, err), NBRDF_ERR_MISMATCH, err,
                "not 'model-b'");
    CHECK(in->sources[0] == '\0' && in->file_size > 0);
  }
  texture_latent_reader_close(r);
  CHECK(set_int_attr(path, NBRDF_ATTR_FORMAT_VERSION, NBRDF_LATENT_FORMAT_VERSION + 1));
  CHECK_FAILS(texture_latent_reader_open(&r, path, err), NBRDF_ERR_FORMAT, err,
              "is newer than this nbrdf reads");
  /* Version 2 promises a decoder of its own: without the attribute (what an
   * image tool's copy leaves) the file is refused, saying why. */
  CHECK(set_int_attr(path, NBRDF_ATTR_FORMAT_VERSION, NBRDF_LATENT_FORMAT_OWN_DECODER));
  CHECK_FAILS(texture_latent_reader_open(&r, path, err), NBRDF_ERR_FORMAT, err,
              "the nbrdf:decoder attribute is missing: a tool that copies only the attributes "
              "it knows (oiiotool");
  CHECK(strstr(err->message, path) == err->message);
  CHECK(set_int_attr(path, NBRDF_ATTR_FORMAT_VERSION, NBRDF_LATENT_FORMAT_V1));
  CHECK(set_int_attr(path, NBRDF_ATTR_LATENT_DIM, 3));
  CHECK_FAILS(texture_latent_reader_open(&r, path, err), NBRDF_ERR_FORMAT, err,
              "missing channel latent.L02.Y");
  CHECK(set_int_attr(path, NBRDF_ATTR_LATENT_DIM, 0));
  CHECK_FAILS(texture_latent_reader_open(&r, path, err), NBRDF_ERR_FORMAT, err,
              "latent dimension 0");
  CHECK(r == NULL);
  texture_latent_reader_close(r);
  free(l0);
}

int main(void) {
  RUN(test_abort_and_incomplete_leave_nothing);
  RUN(test_bad_values_name_the_texel);
  RUN(test_never_overwrites_an_input);
  RUN(test_unwritable_destinations);
  RUN(test_replaces_only_on_success);
  RUN(test_writer_arguments);
  RUN(test_reader_refusals);
  return testing_finish();
}
