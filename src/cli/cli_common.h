/* What every subcommand shares: exit statuses, messages, strict number parsing,
 * the bundle and texture look-ups (cli_common.c, cli_model.c). The option
 * tables (cli_options.c) build on these; cli.h adds the command list. */
#ifndef NBRDF_CLI_COMMON_H
#define NBRDF_CLI_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "nbrdf/model.h"
#include "nbrdf/status.h"

enum { CLI_EXIT_OK = 0, CLI_EXIT_FAILURE = 1, CLI_EXIT_USAGE = 2 };

/* Prints "nbrdf <cmd>: <message>" and a hint to stderr; returns CLI_EXIT_USAGE. */
int cli_usage_error(const char *cmd, const char *fmt, ...);
/* Prints "nbrdf <cmd>: <message>" to stderr; returns CLI_EXIT_FAILURE. */
int cli_fail(const char *cmd, const char *fmt, ...);
/* Prints an nbrdf_error; returns CLI_EXIT_FAILURE. */
int cli_fail_error(const char *cmd, const nbrdf_error *err);
/* "bundle: DIR" (the default bundle), or why none is found, for --version. */
void cli_bundle_describe(FILE *out);
/* Loads the bundle of --bundle DIR (`bundle`), or when it is NULL the default bundle
 * (nbrdf_default_bundle_path: $NBRDF_BUNDLE, the install, the source tree, ./models/default).
 * `used` (may be NULL) receives the folder. Returns CLI_EXIT_OK or reports the failure. */
int cli_model_load(const char *cmd, const char *bundle, nbrdf_model **out, char *used, size_t size);

/* Strict number parsing (core/number.h): the whole string must be a decimal
 * number, white space around it allowed; no hex, inf or nan; overflow and
 * underflow refused. An int has no fraction or exponent. */
int cli_parse_double(const char *text, double *out);
/* The same for a value the library keeps as a float: beyond FLT_MAX, or a
 * non-zero value below FLT_MIN, is refused here (a usage error) rather than
 * turned into inf or 0 for the library to refuse later (exit 1). */
int cli_parse_float(const char *text, float *out);
int cli_parse_int(const char *text, long lo, long hi, long *out);
/* Decimal digits only, the whole of 0..2^64-1 (seeds, counts). */
int cli_parse_u64(const char *text, uint64_t *out);
/* An index (a mip level, a texel's column): decimal digits only; a value beyond
 * 2^64-1 reads as UINT64_MAX, so that it is refused as out of range, like any
 * other too large index, rather than as "not a number". */
int cli_parse_index(const char *text, uint64_t *out);
/* The mip level count of latent texture `path`, and level `level`'s size in
 * *width, *height (when level < the count). 0 when the file cannot be read as
 * a latent texture: the command's own reading then says why. */
int cli_texture_levels(const char *path, int level, int *width, int *height);
/* The usage error of a mip level the texture lacks: "nbrdf CMD: OPTION: TEXTURE
 * has N mip levels (0..N-1); there is no level LEVEL". Returns CLI_EXIT_USAGE. */
int cli_level_error(const char *cmd, const char *option, const char *texture, int levels,
                    const char *level);
/* --compact's value "K[,WIDTH]": K latent channels 1..8, WIDTH 4..256 (0 when not given).
 * 0 when `text` is not one; CLI_COMPACT_EXPECTED says what is. */
int cli_parse_compact(const char *text, int *k, int *width);
#define CLI_COMPACT_EXPECTED "K[,WIDTH]: K latent channels 1..8, WIDTH 4..256 (e.g. 8 or 8,32)"
/* True for "-h" and "--help". */
int cli_is_help(const char *arg);

#endif
