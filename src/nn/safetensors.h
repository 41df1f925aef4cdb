/* Weights on disk: a reader and a writer for the safetensors format
 * (https://github.com/huggingface/safetensors), so that nbrdf's own models and models
 * trained elsewhere (PyTorch) load through the same code.
 *
 * The format: an 8-byte little-endian unsigned header length N; N bytes of UTF-8 JSON,
 * an object mapping each tensor name to
 *   {"dtype": "F32", "shape": [d0, d1, ...], "data_offsets": [begin, end]}
 * (byte offsets relative to the first byte after the header) plus an optional
 * "__metadata__" object of string -> string; then the data buffer, little-endian,
 * row-major, which the tensors must cover exactly (no overlap, no hole, nothing after).
 *
 * This is a generic named-tensor container: it knows nothing about networks. The model
 * layer puts its architecture into the metadata and checks shapes with nn_st_expect.
 *
 * Reading: the whole file is validated before anything is returned (every name, dtype,
 * shape, offset and the file size; see DESIGN.md "Formats"); a malformed or truncated file
 * is refused with NBRDF_ERR_FORMAT and a message "<label>: <what is wrong>", never a
 * crash or an allocation larger than a small multiple of the input's real size. Tensor data
 * is converted to float at open: F32 is nbrdf's own dtype; F16, BF16 (exactly) and F64
 * (rounded to nearest, out-of-range values become +-inf) are accepted because PyTorch
 * exports often use them. Any other dtype of the format (BOOL, integers, FP8...) is refused
 * with NBRDF_ERR_UNSUPPORTED naming the tensor; an unknown dtype string is NBRDF_ERR_FORMAT.
 * The reader does not keep a reference to the file or buffer it was opened from.
 *
 * Strictness and limits (documented refusals, NBRDF_ERR_FORMAT unless said): the header
 * must start with '{', be at most 100,000,000 bytes (the reference implementation's limit)
 * and end with nothing but JSON whitespace; shapes and offsets are plain non-negative JSON
 * integers below 2^64 (1.0, 1e3, -0 are refused, as serde does), dimensions at most 2^63-1;
 * a tensor entry has exactly the fields dtype, shape, data_offsets (unknown fields are
 * refused); "__metadata__": null is read as no metadata; at most NBRDF_ST_MAX_DIMS
 * dimensions (NBRDF_ERR_UNSUPPORTED); names, keys and values may not contain NUL.
 * The JSON is parsed by a small strict parser of this one schema, not cJSON: see why in
 * safetensors_header.c.
 *
 * A reader is immutable after open: several threads may read one reader at once.
 * A writer must be used by one thread at a time. */
#ifndef NBRDF_NN_SAFETENSORS_H
#define NBRDF_NN_SAFETENSORS_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/status.h"

#define NBRDF_ST_MAX_DIMS 8
/* The largest file nn_st_open reads (the networks and tables nbrdf writes
 * are a few MB); checked against stat before anything is allocated. */
#define NBRDF_ST_FILE_MAX ((uint64_t)1 << 30)

typedef enum nn_st_dtype {
  NBRDF_ST_F32 = 0,
  NBRDF_ST_F16,
  NBRDF_ST_BF16,
  NBRDF_ST_F64
} nn_st_dtype;

/* "F32", "F16", "BF16", "F64". */
const char *nn_st_dtype_name(nn_st_dtype dtype);

/* One tensor of a reader; owned by the reader, valid until nn_st_close. */
typedef struct nn_st_tensor {
  const char *name;
  nn_st_dtype dtype;                /* as stored in the file */
  int ndim;                         /* 0 for a scalar */
  int64_t shape[NBRDF_ST_MAX_DIMS]; /* row-major; entries past ndim are 0 */
  size_t count;                     /* product of the shape (1 for a scalar) */
  const float *data;                /* count floats, converted from dtype; NULL iff count == 0 */
} nn_st_tensor;

/* ---------------------------------------------------------------- reading */

typedef struct nn_st_reader nn_st_reader;

/* Opens and validates a file; messages start with `path`. */
nbrdf_status nn_st_open(const char *path, nn_st_reader **out, nbrdf_error *err);

/* The same from memory (the bytes of a file); `label` (e.g. a file name) starts every
 * message and is returned by nn_st_label. The buffer is not used after the call. */
nbrdf_status nn_st_open_memory(const void *bytes, size_t size, const char *label,
                               nn_st_reader **out, nbrdf_error *err);

void nn_st_close(nn_st_reader *reader); /* NULL is allowed */

const char *nn_st_label(const nn_st_reader *reader);

/* Tensors in increasing strcmp order of their names (not file order). */
size_t nn_st_tensor_count(const nn_st_reader *reader);
const nn_st_tensor *nn_st_tensor_at(const nn_st_reader *reader, size_t index);
/* NULL when there is no tensor of that name. */
const nn_st_tensor *nn_st_find(const nn_st_reader *reader, const char *name);

/* The tensor `name` with exactly the given shape (ndim entries) and only finite values,
 * for loading nbrdf's own weights. Fails with NBRDF_ERR_MISMATCH and a message such as
 * "decoder.safetensors: tensor 'block3.fc1.weight' has shape [128, 256], expected
 * [256, 128]" (or "has no tensor 'x'"), or NBRDF_ERR_FORMAT if a value is NaN or
 * infinite. On success *data points to the reader's floats (valid until close). */
nbrdf_status nn_st_expect(const nn_st_reader *reader, const char *name, int ndim,
                          const int64_t *shape, const float **data, nbrdf_error *err);
/* nn_st_expect, then copies the values into dst (room for the product of shape). */
nbrdf_status nn_st_expect_copy(const nn_st_reader *reader, const char *name, int ndim,
                               const int64_t *shape, float *dst, nbrdf_error *err);

/* Metadata, in increasing strcmp order of keys. nn_st_metadata_get returns NULL when
 * the key is absent; nn_st_metadata_require fails with NBRDF_ERR_MISMATCH instead. */
size_t nn_st_metadata_count(const nn_st_reader *reader);
const char *nn_st_metadata_key(const nn_st_reader *reader, size_t index);
const char *nn_st_metadata_value(const nn_st_reader *reader, size_t index);
const char *nn_st_metadata_get(const nn_st_reader *reader, const char *key);
nbrdf_status nn_st_metadata_require(const nn_st_reader *reader, const char *key, const char **value,
                                    nbrdf_error *err);

/* ---------------------------------------------------------------- checksum */

/* The checksum of a weights file is FNV-1a 64-bit over every byte of the file, as read
 * (header included, so metadata changes change it). It identifies a model, e.g. in a
 * latent texture's header so that a texture baked with another model is refused; it
 * detects accidents, not forgery. The writer's output is deterministic, so the same
 * weights and metadata always give the same checksum. Format it with "%016" PRIx64. */
#define NBRDF_ST_FNV1A64_INIT UINT64_C(0xcbf29ce484222325)
/* Continues a running checksum (start from NBRDF_ST_FNV1A64_INIT) over more bytes. */
uint64_t nn_st_fnv1a64(uint64_t hash, const void *bytes, size_t size);
/* The checksum of the file or buffer the reader was opened from. */
uint64_t nn_st_checksum(const nn_st_reader *reader);

/* ---------------------------------------------------------------- writing */

typedef struct nn_st_writer nn_st_writer;

nbrdf_status nn_st_writer_create(nn_st_writer **out, nbrdf_error *err);
void nn_st_writer_destroy(nn_st_writer *writer); /* NULL is allowed */

/* Adds an F32 tensor of the given shape (ndim <= NBRDF_ST_MAX_DIMS, each dim >= 0; data
 * may be NULL only if a dim is 0). The data is COPIED: the caller may reuse its buffer at
 * once. Fails with NBRDF_ERR_ARGUMENT for an empty name (the reader accepts one from other
 * writers), "__metadata__", a name that is not UTF-8, or a name already added. Values are
 * written as given, NaN and infinities too (nn_st_expect refuses them when read). */
nbrdf_status nn_st_writer_add(nn_st_writer *writer, const char *name, int ndim,
                              const int64_t *shape, const float *data, nbrdf_error *err);
/* The same without the copy: `data` is BORROWED and must stay valid and unchanged until
 * the last nn_st_writer_save / _serialize call or nn_st_writer_destroy. */
nbrdf_status nn_st_writer_add_borrowed(nn_st_writer *writer, const char *name, int ndim,
                                       const int64_t *shape, const float *data, nbrdf_error *err);

/* Sets (or replaces) a metadata entry; both strings are copied and must be UTF-8. */
nbrdf_status nn_st_writer_set_metadata(nn_st_writer *writer, const char *key, const char *value,
                                       nbrdf_error *err);

/* Writes the file atomically: into a temporary file in the same directory, flushed and
 * synced, then renamed over `path`. On any failure nothing is left behind and an existing
 * file at `path` is untouched. Tensors are written sorted by name, metadata sorted by key,
 * the header padded with spaces to a multiple of 8 bytes so that the data is 8-aligned in
 * the file. `checksum` (may be NULL) receives the checksum of the written bytes. */
nbrdf_status nn_st_writer_save(const nn_st_writer *writer, const char *path, uint64_t *checksum,
                               nbrdf_error *err);

/* The same bytes into a malloc'ed buffer (caller frees with free()). */
nbrdf_status nn_st_writer_serialize(const nn_st_writer *writer, void **bytes, size_t *size,
                                    nbrdf_error *err);

#endif
