/* Byte layout of a data set file (docs/DATASET.md), shared by the writer and
 * the reader. Every number is little-endian whatever the host. */
#ifndef NBRDF_TRAIN_DATASET_FORMAT_H
#define NBRDF_TRAIN_DATASET_FORMAT_H

#include <stddef.h>
#include <stdint.h>

#include "train/dataset_settings.h"
#include "train/params.h"

#define TRAIN_DS_MAGIC "NBRDFDS\0"
#define TRAIN_DS_FOOTER_MAGIC "NBRDFEND"
enum { TRAIN_DS_HEADER_BYTES = 64, TRAIN_DS_RECORD_HEAD_BYTES = 104, TRAIN_DS_FOOTER_BYTES = 24 };

/* Bytes of one record: head, samples, checksum. */
size_t train_ds_record_bytes(const train_dataset_settings *s);
void train_ds_encode_header(const train_dataset_settings *s,
                            unsigned char out[TRAIN_DS_HEADER_BYTES]);
/* Returns 0 and a reason in *why when the header is not a valid one. */
int train_ds_decode_header(const unsigned char in[TRAIN_DS_HEADER_BYTES], train_dataset_settings *s,
                           const char **why);
/* Encodes record `index` into out[train_ds_record_bytes(s)], checksum included. */
void train_ds_encode_record(const train_dataset_settings *s, uint64_t index, const train_params *p,
                            const float *samples, unsigned char *out);
void train_ds_encode_footer(uint64_t count, uint64_t checksum,
                            unsigned char out[TRAIN_DS_FOOTER_BYTES]);

void train_ds_put_u32(unsigned char *p, uint32_t v);
void train_ds_put_u64(unsigned char *p, uint64_t v);
uint32_t train_ds_get_u32(const unsigned char *p);
uint64_t train_ds_get_u64(const unsigned char *p);
double train_ds_get_f64(const unsigned char *p);
float train_ds_get_f32(const unsigned char *p);

#endif
