/* Every malformation the safetensors loader must refuse, one check each: the status, a
 * message that names the file and the problem, and no crash (this also runs under ASan). */
#include <string.h>

#include "nn/safetensors.h"
#include "st_fixture.h"
#include "testing.h"

/* json + data_size bytes must be refused with `status` and a message naming the file and
 * containing `needle`. */
#define REFUSED(json, data_size, status, needle)                                                   \
  do {                                                                                             \
    nbrdf_error err_ = {0};                                                                        \
    CHECK_FAILS(st_open_json((json), (data_size), &err_, NULL), (status), &err_, (needle));        \
    CHECK_MSG(strncmp(err_.message, "t.safetensors: ", 15) == 0, "no file name in \"%s\"",         \
              err_.message);                                                                       \
  } while (0)

#define T1 "{\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[0,8]}}"

static void test_header_length(void) {
  nbrdf_error err_storage = {0}, *err = &err_storage;
  nn_st_reader *r = NULL;
  size_t size = 0;
  unsigned char *b = st_build_raw(T1, 0, "\0\0\0\0\0\0\0\0", 8, &size);
  /* Beyond the file by one byte, and absurdly large. */
  for (int k = 0; k < 8; k++)
    b[k] = (unsigned char)((size - 8 + 1) >> (8 * k));
  CHECK_FAILS(nn_st_open_memory(b, size, "t.safetensors", &r, err), NBRDF_ERR_FORMAT, err,
              "runs past the end of the file");
  memset(b, 0xff, 8);
  CHECK_FAILS(nn_st_open_memory(b, size, "t.safetensors", &r, err), NBRDF_ERR_FORMAT, err,
              "header length 18446744073709551615 runs past");
  CHECK(r == NULL);
  free(b);
  /* A real buffer larger than the format's header limit: refused before anything is read
   * beyond the length (calloc'ed pages stay untouched). */
  size_t big = 100000000 + 16;
  unsigned char *huge = calloc(big, 1);
  if (huge) {
    uint64_t n = 100000001;
    for (int k = 0; k < 8; k++)
      huge[k] = (unsigned char)(n >> (8 * k));
    CHECK_FAILS(nn_st_open_memory(huge, big, "t.safetensors", &r, err), NBRDF_ERR_FORMAT, err,
                "exceeds the format's limit");
    free(huge);
  }
  CHECK_FAILS(nn_st_open_memory("\x10\0\0", 3, "t.safetensors", &r, err), NBRDF_ERR_FORMAT, err,
              "too short for the 8-byte header length");
  CHECK_FAILS(nn_st_open_memory(NULL, 0, "t.safetensors", &r, err), NBRDF_ERR_FORMAT, err,
              "too short");
}

static void test_not_json(void) {
  REFUSED("", 0, NBRDF_ERR_FORMAT, "does not start with '{'");
  REFUSED("[1, 2]", 0, NBRDF_ERR_FORMAT, "does not start with '{'");
  REFUSED(" {}", 0, NBRDF_ERR_FORMAT, "does not start with '{'");
  REFUSED("{\"a\":", 0, NBRDF_ERR_FORMAT, "JSON ends early");
  REFUSED("{\"a\" {}}", 0, NBRDF_ERR_FORMAT, "expected ':' after a tensor name, found '{'");
  REFUSED("{\"a\"\x01}", 0, NBRDF_ERR_FORMAT, "expected ':' after a tensor name, found byte 0x01");
  REFUSED("{\"a\":", 0, NBRDF_ERR_FORMAT, "JSON ends early: tensor 'a' is missing");
  REFUSED("{\"a\":{}", 0, NBRDF_ERR_FORMAT, "has no \"dtype\"");
  REFUSED("{a:1}", 0, NBRDF_ERR_FORMAT, "a tensor name is not a string");
  REFUSED("{\"a", 0, NBRDF_ERR_FORMAT, "unterminated string");
  REFUSED("{} x", 0, NBRDF_ERR_FORMAT, "unexpected bytes after the JSON object");
  REFUSED("{}{}", 0, NBRDF_ERR_FORMAT, "unexpected bytes after the JSON object");
  REFUSED("{\"x\":1,}", 0, NBRDF_ERR_FORMAT, "tensor 'x' is not an object");
  REFUSED("{\"\xff\":1}", 0, NBRDF_ERR_FORMAT, "not valid UTF-8 (at header byte 2)");
  REFUSED("{\"\xc0\xaf\":1}", 0, NBRDF_ERR_FORMAT, "not valid UTF-8");     /* overlong '/' */
  REFUSED("{\"\xed\xa0\x80\":1}", 0, NBRDF_ERR_FORMAT, "not valid UTF-8"); /* a surrogate */
  REFUSED("{\"a\tb\":1}", 0, NBRDF_ERR_FORMAT, "control character 0x09");
  REFUSED("{\"a\\qb\":1}", 0, NBRDF_ERR_FORMAT, "invalid escape");
  REFUSED("{\"a\\u12\":1}", 0, NBRDF_ERR_FORMAT, "invalid escape");
  REFUSED("{\"a\\ud800\":1}", 0, NBRDF_ERR_FORMAT, "unpaired UTF-16 surrogate");
  REFUSED("{\"a\\udc00x\":1}", 0, NBRDF_ERR_FORMAT, "unpaired UTF-16 surrogate");
  REFUSED("{\"a\\u0000b\":1}", 0, NBRDF_ERR_FORMAT, "NUL in a tensor name");
}

static void test_fields(void) {
  REFUSED("{\"a\":{\"shape\":[],\"data_offsets\":[0,4]}}", 4, NBRDF_ERR_FORMAT,
          "tensor 'a' has no \"dtype\" field");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"data_offsets\":[0,4]}}", 4, NBRDF_ERR_FORMAT,
          "tensor 'a' has no \"shape\" field");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[]}}", 4, NBRDF_ERR_FORMAT,
          "tensor 'a' has no \"data_offsets\" field");
  REFUSED("{\"a\":{\"dtype\":32,\"shape\":[],\"data_offsets\":[0,4]}}", 4, NBRDF_ERR_FORMAT,
          "dtype of tensor 'a' is not a string");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":\"2\",\"data_offsets\":[0,4]}}", 4, NBRDF_ERR_FORMAT,
          "shape of tensor 'a' is not an array of integers");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[\"2\"],\"data_offsets\":[0,4]}}", 4,
          NBRDF_ERR_FORMAT, "shape of tensor 'a' is not made of non-negative integers only");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[],\"data_offsets\":[4]}}", 4, NBRDF_ERR_FORMAT,
          "data_offsets of tensor 'a' must hold 2 integers");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[],\"data_offsets\":[0,4,8]}}", 4, NBRDF_ERR_FORMAT,
          "data_offsets of tensor 'a' has more than 2 entries");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[],\"data_offsets\":{}}}", 4, NBRDF_ERR_FORMAT,
          "data_offsets of tensor 'a' is not an array");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"dtype\":\"F32\",\"shape\":[],\"data_offsets\":[0,4]}}", 4,
          NBRDF_ERR_FORMAT, "two \"dtype\" fields");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[],\"data_offsets\":[0,4],\"x\":1}}", 4,
          NBRDF_ERR_FORMAT, "tensor 'a' has an unknown field \"x\"");
  REFUSED("{\"a\":[1]}", 4, NBRDF_ERR_FORMAT, "tensor 'a' is not an object");
}

static void test_dtypes(void) {
  REFUSED("{\"a\":{\"dtype\":\"F33\",\"shape\":[],\"data_offsets\":[0,4]}}", 4, NBRDF_ERR_FORMAT,
          "tensor 'a' has unknown dtype \"F33\"");
  REFUSED("{\"a\":{\"dtype\":\"f32\",\"shape\":[],\"data_offsets\":[0,4]}}", 4, NBRDF_ERR_FORMAT,
          "unknown dtype");
  REFUSED("{\"a\":{\"dtype\":\"I64\",\"shape\":[],\"data_offsets\":[0,8]}}", 8,
          NBRDF_ERR_UNSUPPORTED, "tensor 'a' has dtype I64; nbrdf reads only F32, F16, BF16");
  REFUSED("{\"a\":{\"dtype\":\"BOOL\",\"shape\":[1],\"data_offsets\":[0,1]}}", 1,
          NBRDF_ERR_UNSUPPORTED, "dtype BOOL");
}

static void test_shapes(void) {
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[-2],\"data_offsets\":[0,8]}}", 8, NBRDF_ERR_FORMAT,
          "shape of tensor 'a' holds a negative number");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2.5],\"data_offsets\":[0,8]}}", 8, NBRDF_ERR_FORMAT,
          "holds a number that is not an integer");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2.0],\"data_offsets\":[0,8]}}", 8, NBRDF_ERR_FORMAT,
          "not an integer");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2e0],\"data_offsets\":[0,8]}}", 8, NBRDF_ERR_FORMAT,
          "not an integer");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[02],\"data_offsets\":[0,8]}}", 8, NBRDF_ERR_FORMAT,
          "leading zero");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[18446744073709551616],\"data_offsets\":[0,8]}}", 8,
          NBRDF_ERR_FORMAT, "above 2^64 - 1");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[4294967296,4294967296],"
          "\"data_offsets\":[0,8]}}",
          8, NBRDF_ERR_FORMAT, "whose size overflows");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[4611686018427387904],\"data_offsets\":[0,8]}}", 8,
          NBRDF_ERR_FORMAT, "whose size overflows"); /* 2^62 elements x 4 bytes */
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[0,9223372036854775808],"
          "\"data_offsets\":[0,0]}}",
          0, NBRDF_ERR_FORMAT, "dimension 1 of 9223372036854775808");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[1,1,1,1,1,1,1,1,1],\"data_offsets\":[0,4]}}", 4,
          NBRDF_ERR_UNSUPPORTED, "shape of tensor 'a' has more than 8 entries");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[3],\"data_offsets\":[0,8]}}", 8, NBRDF_ERR_FORMAT,
          "tensor 'a' (F32, shape [3]) needs 12 bytes but its data_offsets "
          "[0, 8] span 8");
  REFUSED("{\"a\":{\"dtype\":\"F16\",\"shape\":[2,2],\"data_offsets\":[0,16]}}", 16,
          NBRDF_ERR_FORMAT, "needs 8 bytes");
}

static void test_offsets(void) {
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[8,0]}}", 8, NBRDF_ERR_FORMAT,
          "data_offsets [8, 0] that end before they begin");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[-1,7]}}", 8, NBRDF_ERR_FORMAT,
          "negative");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[4,12]}}", 8, NBRDF_ERR_FORMAT,
          "tensor 'a' has data_offsets [4, 12] past the end of the data "
          "buffer (8 bytes");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[18446744073709551612,"
          "18446744073709551620]}}",
          8, NBRDF_ERR_FORMAT, "above 2^64 - 1");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[0,8]},"
          "\"b\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[4,12]}}",
          12, NBRDF_ERR_FORMAT, "tensors 'a' and 'b' overlap in the data buffer");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[0,8]},"
          "\"b\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[0,8]}}",
          8, NBRDF_ERR_FORMAT, "overlap");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[0,8]},"
          "\"b\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[12,20]}}",
          20, NBRDF_ERR_FORMAT, "bytes [8, 12) of the data buffer belong to no tensor");
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[4,12]}}", 12, NBRDF_ERR_FORMAT,
          "bytes [0, 4) of the data buffer belong to no tensor");
  REFUSED(T1, 9, NBRDF_ERR_FORMAT, "1 trailing bytes after the last tensor's data");
  REFUSED("{}", 3, NBRDF_ERR_FORMAT, "3 trailing bytes after the header");
  REFUSED(T1, 7, NBRDF_ERR_FORMAT, "past the end of the data buffer (7 bytes; truncated");
}

static void test_names_and_metadata(void) {
  REFUSED("{\"a\":{\"dtype\":\"F32\",\"shape\":[1],\"data_offsets\":[0,4]},"
          "\"a\":{\"dtype\":\"F32\",\"shape\":[1],\"data_offsets\":[4,8]}}",
          8, NBRDF_ERR_FORMAT, "tensor name 'a' appears twice");
  REFUSED("{\"__metadata__\":{\"k\":\"v\",\"k\":\"w\"}}", 0, NBRDF_ERR_FORMAT,
          "metadata key 'k' appears twice");
  REFUSED("{\"__metadata__\":{},\"__metadata__\":{}}", 0, NBRDF_ERR_FORMAT,
          "two __metadata__ entries");
  REFUSED("{\"__metadata__\":{\"width\":256}}", 0, NBRDF_ERR_FORMAT,
          "metadata value for key 'width' is not a string");
  REFUSED("{\"__metadata__\":{\"x\":{\"y\":\"z\"}}}", 0, NBRDF_ERR_FORMAT,
          "metadata value for key 'x' is not a string");
  REFUSED("{\"__metadata__\":[\"x\"]}", 0, NBRDF_ERR_FORMAT, "__metadata__ is not an object");
  REFUSED("{\"__metadata__\":\"x\"}", 0, NBRDF_ERR_FORMAT, "__metadata__ is not an object");
  REFUSED("{\"__metadata__\":{\"k\":\"v\\u0000\"}}", 0, NBRDF_ERR_FORMAT,
          "NUL in a metadata value");
}

/* A valid two-tensor file with metadata; every proper prefix of it must be refused, and
 * every single-bit flip must load or be refused cleanly. */
static void test_every_truncation_and_bit_flip(void) {
  size_t size = 0;
  unsigned char *b = st_build("{\"__metadata__\":{\"arch\":\"mlp\"},"
                              "\"a\":{\"dtype\":\"F32\",\"shape\":[2],\"data_offsets\":[0,8]},"
                              "\"b\":{\"dtype\":\"F16\",\"shape\":[1,3],\"data_offsets\":[8,14]}}",
                              14, &size);
  nbrdf_error err_storage = {0}, *err = &err_storage;
  nn_st_reader *r = NULL;
  CHECK_OK(nn_st_open_memory(b, size, "t.safetensors", &r, err), err);
  CHECK(r && nn_st_tensor_count(r) == 2);
  nn_st_close(r);
  int refused = 0;
  for (size_t n = 0; n < size; n++) {
    unsigned char *prefix = malloc(n ? n : 1); /* exact size: ASan catches over-reads */
    memcpy(prefix, b, n);
    err->message[0] = '\0';
    nbrdf_status st = nn_st_open_memory(prefix, n, "t.safetensors", &r, err);
    refused += st == NBRDF_ERR_FORMAT && r == NULL &&
               strncmp(err->message, "t.safetensors: ", 15) == 0 && strlen(err->message) > 20;
    free(prefix);
  }
  CHECK_MSG(refused == (int)size, "%d of %zu prefixes refused cleanly", refused, size);
  int loaded = 0, clean = 0;
  for (size_t i = 0; i < size; i++)
    for (int bit = 0; bit < 8; bit++) {
      unsigned char *m = malloc(size);
      memcpy(m, b, size);
      m[i] ^= (unsigned char)(1u << bit);
      err->message[0] = '\0';
      nbrdf_status st = nn_st_open_memory(m, size, "t.safetensors", &r, err);
      if (st == NBRDF_OK)
        loaded++, clean++;
      else
        clean += r == NULL && strncmp(err->message, "t.safetensors: ", 15) == 0;
      nn_st_close(r);
      free(m);
    }
  CHECK(clean == (int)size * 8);
  CHECK(loaded > 0 && loaded < (int)size * 8); /* data-byte flips load, header flips don't */
  free(b);
}

int main(void) {
  RUN(test_header_length);
  RUN(test_not_json);
  RUN(test_fields);
  RUN(test_dtypes);
  RUN(test_shapes);
  RUN(test_offsets);
  RUN(test_names_and_metadata);
  RUN(test_every_truncation_and_bit_flip);
  return testing_finish();
}
