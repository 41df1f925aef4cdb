#include "texture/tile_pattern.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"

typedef enum field_kind {
  FIELD_UDIM,
  FIELD_UVTILE,
  FIELD_U0,
  FIELD_V0,
  FIELD_U1,
  FIELD_V1
} field_kind;

static const struct {
  const char *token;
  field_kind kind;
} tokens[] = {
    {"<UDIM>", FIELD_UDIM},     {"%(UDIM)d", FIELD_UDIM}, {"<UVTILE>", FIELD_UVTILE},
    {"<uvtile>", FIELD_UVTILE}, {"<u>", FIELD_U0},        {"<v>", FIELD_V0},
    {"<U>", FIELD_U1},          {"<V>", FIELD_V1},
};
#define N_TOKENS (sizeof tokens / sizeof tokens[0])

#define KNOWN_TOKENS "<UDIM>, %(UDIM)d, <UVTILE>, <u> and <v>, <U> and <V>"

/* text = literal[0] field[0] literal[1] field[1] literal[2], n_fields of 0..2;
 * literal[0] starts with the folder (dir_len bytes, its '/' included). */
struct texture_tile_pattern {
  char *text;
  size_t dir_len;
  int n_fields;
  field_kind fields[2];
  const char *field_tokens[2]; /* as written, for messages */
  char *literals[3];
};

void texture_tile_uv(int tile, int *u, int *v) {
  *u = (tile - TEXTURE_TILE_FIRST) % 10;
  *v = (tile - TEXTURE_TILE_FIRST) / 10;
}

int texture_tile_at(int u, int v) {
  if (u < 0 || u > 9 || v < 0 || v > 9) return 0;
  return TEXTURE_TILE_FIRST + u + 10 * v;
}

nbrdf_status texture_tile_check(int tile, nbrdf_error *err) {
  if (tile < TEXTURE_TILE_FIRST || tile > TEXTURE_TILE_LAST)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "tile %d is outside %d..%d (u 0..9, v 0..9: 1001 + u + 10 v)", tile,
                     TEXTURE_TILE_FIRST, TEXTURE_TILE_LAST);
  return NBRDF_OK;
}

/* A decimal number without sign or leading zero, of at most 9 digits, at
 * s[0 .. *len): its value, or -1 (and *len its digits) when it is none. */
static long digits_at(const char *s, size_t *len) {
  size_t n = 0;
  while (s[n] >= '0' && s[n] <= '9')
    n++;
  *len = n;
  if (n == 0 || n > 9 || (n > 1 && s[0] == '0')) return -1;
  long value = 0;
  for (size_t i = 0; i < n; i++)
    value = value * 10 + (s[i] - '0');
  return value;
}

nbrdf_status texture_tile_parse(const char *text, int *tile, nbrdf_error *err) {
  size_t len;
  long value = digits_at(text, &len);
  if (value < 0 || text[len] != '\0')
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "'%s' is not a tile number: expected %d..%d (1001 + u + 10 v)", text,
                     TEXTURE_TILE_FIRST, TEXTURE_TILE_LAST);
  nbrdf_status st = texture_tile_check((int)value, err);
  if (st != NBRDF_OK) return st;
  *tile = (int)value;
  return NBRDF_OK;
}

void texture_tile_pattern_free(texture_tile_pattern *p) {
  if (!p) return;
  free(p->text);
  for (int i = 0; i < 3; i++)
    free(p->literals[i]);
  free(p);
}

static int is_u(field_kind k) { return k == FIELD_U0 || k == FIELD_U1; }
static int is_v(field_kind k) { return k == FIELD_V0 || k == FIELD_V1; }

/* The fields found make one tile expression, or a message says why not. */
static nbrdf_status check_fields(const texture_tile_pattern *p, nbrdf_error *err) {
  const char *path = p->text;
  if (p->n_fields == 1) {
    if (is_u(p->fields[0]) || is_v(p->fields[0]))
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "'%s': %s needs its partner %s (a pattern names both u and v)", path,
                       p->field_tokens[0],
                       p->fields[0] == FIELD_U0   ? "<v>"
                       : p->fields[0] == FIELD_U1 ? "<V>"
                       : p->fields[0] == FIELD_V0 ? "<u>"
                                                  : "<U>");
    return NBRDF_OK;
  }
  field_kind a = p->fields[0], b = p->fields[1];
  int pair = (is_u(a) && is_v(b)) || (is_v(a) && is_u(b));
  int same_base = (a == FIELD_U0 || a == FIELD_V0) == (b == FIELD_U0 || b == FIELD_V0);
  if (!pair)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "'%s': two tile tokens (%s and %s); a pattern names its tile once: "
                     "<UDIM>, %%(UDIM)d, <UVTILE>, or <u> and <v>, or <U> and <V>",
                     path, p->field_tokens[0], p->field_tokens[1]);
  if (!same_base)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "'%s': %s and %s mix 0-based (<u>, <v>) and 1-based (<U>, <V>) tile "
                     "numbers; use one convention for both",
                     path, p->field_tokens[0], p->field_tokens[1]);
  return NBRDF_OK;
}

nbrdf_status texture_tile_pattern_parse(const char *path, texture_tile_pattern **out,
                                        nbrdf_error *err) {
  *out = NULL;
  texture_tile_pattern *p = calloc(1, sizeof *p);
  if (!p || !(p->text = strdup(path))) {
    free(p);
    return core_fail(err, NBRDF_ERR_MEMORY, "'%s': out of memory", path);
  }
  const char *slash = strrchr(path, '/');
  p->dir_len = slash ? (size_t)(slash - path) + 1 : 0;

  size_t literal_start = 0;
  const char *extra_token = NULL; /* a third token, for the message */
  for (size_t i = 0; path[i];) {
    size_t k = 0;
    while (k < N_TOKENS && strncmp(path + i, tokens[k].token, strlen(tokens[k].token)) != 0)
      k++;
    if (k == N_TOKENS) {
      /* <word> or %(word)d that is not ours: a tile token misspelt (<udim>) or
       * another tool's (<tile>, %(U)d), never a file name the user meant */
      size_t n = 0;
      const char *open = path[i] == '<' ? "<" : strncmp(path + i, "%(", 2) == 0 ? "%(" : NULL;
      const char *close = open && open[0] == '<' ? ">" : ")d";
      if (open) {
        size_t o = strlen(open);
        while (path[i + o + n] == '_' || isalnum((unsigned char)path[i + o + n]))
          n++;
        if (n > 0 && strncmp(path + i + o + n, close, strlen(close)) == 0) {
          int len = (int)(o + n + strlen(close));
          nbrdf_status st =
              core_fail(err, NBRDF_ERR_ARGUMENT, "'%s': unknown tile token '%.*s'; known: %s", path,
                        len, path + i, KNOWN_TOKENS);
          texture_tile_pattern_free(p);
          return st;
        }
      }
      i++;
      continue;
    }
    if (i < p->dir_len) {
      nbrdf_status st =
          core_fail(err, NBRDF_ERR_ARGUMENT,
                    "'%s': the tile token %s is in a folder; it must be in the file name", path,
                    tokens[k].token);
      texture_tile_pattern_free(p);
      return st;
    }
    if (p->n_fields == 2) {
      extra_token = tokens[k].token;
      break;
    }
    p->literals[p->n_fields] = strndup(path + literal_start, i - literal_start);
    p->fields[p->n_fields] = tokens[k].kind;
    p->field_tokens[p->n_fields] = tokens[k].token;
    p->n_fields++;
    i += strlen(tokens[k].token);
    literal_start = i;
  }
  if (extra_token) {
    nbrdf_status st =
        core_fail(err, NBRDF_ERR_ARGUMENT,
                  "'%s': three tile tokens (%s, %s, %s); a pattern names its tile "
                  "once: %s",
                  path, p->field_tokens[0], p->field_tokens[1], extra_token, KNOWN_TOKENS);
    texture_tile_pattern_free(p);
    return st;
  }
  p->literals[p->n_fields] = strdup(path + literal_start);
  for (int i = 0; i <= p->n_fields; i++)
    if (!p->literals[i]) {
      texture_tile_pattern_free(p);
      return core_fail(err, NBRDF_ERR_MEMORY, "'%s': out of memory", path);
    }
  nbrdf_status st = p->n_fields ? check_fields(p, err) : NBRDF_OK;
  /* A number is read up to the first non-digit, so what follows a token
   * (the next token included) must start with one. */
  for (int i = 1; st == NBRDF_OK && i <= p->n_fields; i++) {
    char c = p->literals[i][0];
    if ((i < p->n_fields && c == '\0') || (c >= '0' && c <= '9'))
      st = core_fail(err, NBRDF_ERR_ARGUMENT,
                     "'%s': %s is followed by %s; put a non-digit between a tile token and "
                     "what follows it, or the tile number has no end",
                     path, p->field_tokens[i - 1], c ? "a digit" : "another token");
  }
  if (st != NBRDF_OK) {
    texture_tile_pattern_free(p);
    return st;
  }
  *out = p;
  return NBRDF_OK;
}

int texture_tile_pattern_is_tiled(const texture_tile_pattern *p) { return p->n_fields > 0; }

const char *texture_tile_pattern_text(const texture_tile_pattern *p) { return p->text; }

static int format_field(char *buf, size_t size, field_kind kind, int tile) {
  int u, v;
  texture_tile_uv(tile, &u, &v);
  switch (kind) {
  case FIELD_UDIM:
    return snprintf(buf, size, "%d", tile);
  case FIELD_UVTILE:
    return snprintf(buf, size, "u%d_v%d", u + 1, v + 1);
  case FIELD_U0:
    return snprintf(buf, size, "%d", u);
  case FIELD_V0:
    return snprintf(buf, size, "%d", v);
  case FIELD_U1:
    return snprintf(buf, size, "%d", u + 1);
  case FIELD_V1:
    return snprintf(buf, size, "%d", v + 1);
  }
  return 0;
}

nbrdf_status texture_tile_pattern_path(const texture_tile_pattern *p, int tile, char **path,
                                       nbrdf_error *err) {
  *path = NULL;
  if (p->n_fields) {
    nbrdf_status st = texture_tile_check(tile, err);
    if (st != NBRDF_OK) return st;
  }
  size_t size = strlen(p->text) + 1 + 16 * (size_t)p->n_fields;
  char *s = malloc(size);
  if (!s) return core_fail(err, NBRDF_ERR_MEMORY, "'%s': out of memory", p->text);
  size_t at = 0;
  for (int i = 0; i <= p->n_fields; i++) {
    at += (size_t)snprintf(s + at, size - at, "%s", p->literals[i]);
    if (i < p->n_fields) at += (size_t)format_field(s + at, size - at, p->fields[i], tile);
  }
  *path = s;
  return NBRDF_OK;
}

/* Matches a file name against the pattern's name part. Returns 0 when it does
 * not match, 1 with *tile set when it names a valid tile, -1 when it matches
 * but names none (what[] then says why). */
static int match_name(const texture_tile_pattern *p, const char *name, int *tile, char *what,
                      size_t what_size) {
  long u = -1, v = -1, udim = -1;
  int bad = 0;
  const char *s = name;
  for (int i = 0; i <= p->n_fields; i++) {
    const char *lit = i == 0 ? p->literals[0] + p->dir_len : p->literals[i];
    size_t n = strlen(lit);
    if (strncmp(s, lit, n) != 0) return 0;
    s += n;
    if (i == p->n_fields) break;
    size_t len;
    long value;
    switch (p->fields[i]) {
    case FIELD_UVTILE:
      if (*s++ != 'u') return 0;
      value = digits_at(s, &len);
      if (len == 0) return 0;
      bad |= value < 1;
      u = value - 1;
      s += len;
      if (s[0] != '_' || s[1] != 'v') return 0;
      s += 2;
      value = digits_at(s, &len);
      if (len == 0) return 0;
      bad |= value < 1;
      v = value - 1;
      break;
    default:
      value = digits_at(s, &len);
      if (len == 0) return 0;
      bad |= value < 0;
      if (p->fields[i] == FIELD_UDIM) udim = value;
      if (p->fields[i] == FIELD_U0) u = value;
      if (p->fields[i] == FIELD_V0) v = value;
      if (p->fields[i] == FIELD_U1) u = value - 1, bad |= value < 1;
      if (p->fields[i] == FIELD_V1) v = value - 1, bad |= value < 1;
    }
    s += len;
  }
  if (*s != '\0') return 0;
  if (bad) {
    snprintf(what, what_size, "a tile number with a leading zero, or 0 where counting from 1");
    return -1;
  }
  int t = udim >= 0 ? (udim <= TEXTURE_TILE_LAST ? (int)udim : 0) : texture_tile_at((int)u, (int)v);
  if (t < TEXTURE_TILE_FIRST || t > TEXTURE_TILE_LAST) {
    if (udim >= 0)
      snprintf(what, what_size, "tile %ld, outside %d..%d", udim, TEXTURE_TILE_FIRST,
               TEXTURE_TILE_LAST);
    else
      snprintf(what, what_size, "tile u %ld, v %ld (0-based), outside u 0..9, v 0..9", u, v);
    return -1;
  }
  *tile = t;
  return 1;
}

nbrdf_status texture_tile_pattern_list(const texture_tile_pattern *p, int tiles[TEXTURE_TILE_COUNT],
                                       int *n, nbrdf_error *err) {
  *n = 0;
  if (!p->n_fields)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "'%s' is not a tile pattern: it has no tile token",
                     p->text);
  char *dir = p->dir_len ? strndup(p->text, p->dir_len) : strdup(".");
  if (!dir) return core_fail(err, NBRDF_ERR_MEMORY, "'%s': out of memory", p->text);
  DIR *d = opendir(dir);
  if (!d) {
    nbrdf_status st = core_fail(err, NBRDF_ERR_IO, "'%s': cannot read the folder %s: %s", p->text,
                                dir, strerror(errno));
    free(dir);
    return st;
  }
  unsigned char present[TEXTURE_TILE_COUNT] = {0};
  nbrdf_status st = NBRDF_OK;
  struct dirent *e;
  while (st == NBRDF_OK && (e = readdir(d)) != NULL) {
    int tile = 0;
    char what[128];
    int m = match_name(p, e->d_name, &tile, what, sizeof what);
    if (m == 0) continue;
    /* only files: a folder named like a tile is not one */
    char *full = malloc(p->dir_len + strlen(e->d_name) + 1);
    if (!full) {
      st = core_fail(err, NBRDF_ERR_MEMORY, "'%s': out of memory", p->text);
      break;
    }
    memcpy(full, p->text, p->dir_len);
    strcpy(full + p->dir_len, e->d_name);
    struct stat sb;
    int is_file = stat(full, &sb) == 0 && S_ISREG(sb.st_mode);
    if (is_file && m < 0)
      st = core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s matches the tile pattern '%s' but names %s; tiles are 1001..1100 "
                     "(u 0..9, v 0..9), their numbers without leading zeros",
                     full, p->text, what);
    else if (is_file)
      present[tile - TEXTURE_TILE_FIRST] = 1;
    free(full);
  }
  closedir(d);
  free(dir);
  if (st != NBRDF_OK) return st;
  for (int i = 0; i < TEXTURE_TILE_COUNT; i++)
    if (present[i]) tiles[(*n)++] = TEXTURE_TILE_FIRST + i;
  return NBRDF_OK;
}
