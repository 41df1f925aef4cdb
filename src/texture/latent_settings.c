#include "texture/latent_settings.h"

#include <string.h>

int texture_latent_setting(const char *settings, const char *key, char *value, size_t size) {
  if (size) value[0] = '\0';
  size_t klen = strlen(key);
  for (const char *p = settings; p && *p;) {
    while (*p == ' ' || *p == ';')
      p++;
    const char *end = strchr(p, ';');
    size_t len = end ? (size_t)(end - p) : strlen(p);
    if (len > klen && !strncmp(p, key, klen) && p[klen] == '=') {
      size_t n = len - klen - 1;
      if (size) {
        if (n >= size) n = size - 1;
        memcpy(value, p + klen + 1, n);
        value[n] = '\0';
      }
      return 1;
    }
    p += len;
  }
  return 0;
}
