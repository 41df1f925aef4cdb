/* The bake settings a latent texture records ("key=value; key=value; ..." in
 * nbrdf:settings, docs/LATENT-TEXTURE.md), read by key. */
#ifndef NBRDF_TEXTURE_LATENT_SETTINGS_H
#define NBRDF_TEXTURE_LATENT_SETTINGS_H

#include <stddef.h>

/* The value of `key` in `settings` copied into value[size] (truncated, NUL-terminated):
 * 1 when the key is present, 0 when not (value ""). Keys match whole, so "range" never
 * matches "mip_range". */
int texture_latent_setting(const char *settings, const char *key, char *value, size_t size);

#endif
