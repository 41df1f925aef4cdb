/* A strict streaming parser for the one JSON shape a safetensors header has:
 *   {"__metadata__": {"key": "value", ...} | null,
 *    "name": {"dtype": "F32", "shape": [2, 3], "data_offsets": [0, 24]}, ...}
 * followed only by whitespace (the writer pads with spaces).
 *
 * Why not cJSON (which nbrdf links): cJSON records every parse failure in a process-wide
 * variable (a data race when two threads load models), reads integers as doubles (offsets
 * above 2^53 lose bits silently) and builds a tree of ~64-byte nodes per value, so a forged
 * header of "[0,0,0,..." costs ~30x its size. Here nothing is global, integers are exact
 * u64 with overflow detected, nesting is bounded by the schema and memory is linear in the
 * number of tensors. Like the reference (serde), a "shape" or offset must be a plain
 * non-negative integer: 1.0, 1e3 and -0 are refused. Unknown fields are refused too. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "nn/safetensors_internal.h"

typedef struct parser {
  const unsigned char *s;
  size_t size, pos;
  nbrdf_error *err;
} parser;

static nbrdf_status fail_at(parser *p, nbrdf_status status, const char *fmt, ...)
    NBRDF_PRINTF(3, 4);

static nbrdf_status fail_at(parser *p, nbrdf_status status, const char *fmt, ...) {
  char what[NBRDF_ERROR_MESSAGE_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  return core_fail(p->err, status, "header: %s (at header byte %zu)", what, p->pos);
}

static void skip_ws(parser *p) {
  while (p->pos < p->size) {
    unsigned char c = p->s[p->pos];
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r') break;
    p->pos++;
  }
}

/* The next non-blank byte, or -1 at the end of the header. */
static int peek(parser *p) {
  skip_ws(p);
  return p->pos < p->size ? p->s[p->pos] : -1;
}

static nbrdf_status expect(parser *p, char c, const char *context) {
  int got = peek(p);
  if (got == c) {
    p->pos++;
    return NBRDF_OK;
  }
  if (got < 0) return fail_at(p, NBRDF_ERR_FORMAT, "JSON ends early: expected '%c' %s", c, context);
  if (got < 0x20 || got > 0x7e)
    return fail_at(p, NBRDF_ERR_FORMAT, "expected '%c' %s, found byte 0x%02x", c, context, got);
  return fail_at(p, NBRDF_ERR_FORMAT, "expected '%c' %s, found '%c'", c, context, got);
}

/* "<what> is <kind>", or that the JSON ended where a value was expected. */
static nbrdf_status not_a(parser *p, const char *what, const char *kind) {
  if (peek(p) < 0) return fail_at(p, NBRDF_ERR_FORMAT, "JSON ends early: %s is missing", what);
  return fail_at(p, NBRDF_ERR_FORMAT, "%s is %s", what, kind);
}

static int hex_value(unsigned char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

static int read_hex4(parser *p, size_t at, uint32_t *out) {
  if (p->size - at < 4) return 0;
  uint32_t v = 0;
  for (int k = 0; k < 4; k++) {
    int h = hex_value(p->s[at + (size_t)k]);
    if (h < 0) return 0;
    v = v << 4 | (uint32_t)h;
  }
  *out = v;
  return 1;
}

static size_t put_utf8(unsigned char *o, uint32_t cp) {
  if (cp < 0x80) return o[0] = (unsigned char)cp, 1;
  if (cp < 0x800) {
    o[0] = (unsigned char)(0xc0 | cp >> 6), o[1] = (unsigned char)(0x80 | (cp & 0x3f));
    return 2;
  }
  if (cp < 0x10000) {
    o[0] = (unsigned char)(0xe0 | cp >> 12), o[1] = (unsigned char)(0x80 | (cp >> 6 & 0x3f));
    o[2] = (unsigned char)(0x80 | (cp & 0x3f));
    return 3;
  }
  o[0] = (unsigned char)(0xf0 | cp >> 18), o[1] = (unsigned char)(0x80 | (cp >> 12 & 0x3f));
  o[2] = (unsigned char)(0x80 | (cp >> 6 & 0x3f)), o[3] = (unsigned char)(0x80 | (cp & 0x3f));
  return 4;
}

/* A JSON string into a malloc'ed C string. Escapes never make the text longer, so the raw
 * length bounds the output. NUL (\u0000) is refused: names and metadata are C strings. */
static nbrdf_status parse_string(parser *p, const char *what, char **out) {
  if (peek(p) != '"') return not_a(p, what, "not a string");
  size_t start = ++p->pos, end = start;
  while (end < p->size && p->s[end] != '"')
    end += p->s[end] == '\\' ? 2 : 1;
  if (end >= p->size) return fail_at(p, NBRDF_ERR_FORMAT, "unterminated string in %s", what);
  unsigned char *o = malloc(end - start + 1);
  if (!o) return core_fail(p->err, NBRDF_ERR_MEMORY, "out of memory reading the header");
  size_t n = 0;
  while (p->pos < end) {
    unsigned char ch = p->s[p->pos];
    if (ch < 0x20) {
      free(o);
      return fail_at(p, NBRDF_ERR_FORMAT, "control character 0x%02x in %s", ch, what);
    }
    if (ch != '\\') {
      o[n++] = ch, p->pos++;
      continue;
    }
    unsigned char e = p->s[p->pos + 1]; /* end > pos + 1: the scan above skipped it */
    const char *simple = strchr("\"\\/bfnrt", e);
    if (e && simple) {
      static const char decoded[] = "\"\\/\b\f\n\r\t";
      o[n++] = (unsigned char)decoded[simple - "\"\\/bfnrt"], p->pos += 2;
      continue;
    }
    uint32_t cp = 0, low = 0;
    if (e != 'u' || !read_hex4(p, p->pos + 2, &cp) || p->pos + 6 > end) {
      free(o);
      return fail_at(p, NBRDF_ERR_FORMAT, "invalid escape in %s", what);
    }
    p->pos += 6;
    if (cp >= 0xd800 && cp <= 0xdbff) { /* a surrogate pair */
      if (p->pos + 6 > end || p->s[p->pos] != '\\' || p->s[p->pos + 1] != 'u' ||
          !read_hex4(p, p->pos + 2, &low) || low < 0xdc00 || low > 0xdfff) {
        free(o);
        return fail_at(p, NBRDF_ERR_FORMAT, "unpaired UTF-16 surrogate in %s", what);
      }
      p->pos += 6;
      cp = 0x10000 + ((cp - 0xd800) << 10) + (low - 0xdc00);
    } else if ((cp >= 0xdc00 && cp <= 0xdfff) || cp == 0) {
      free(o);
      return fail_at(p, NBRDF_ERR_FORMAT, "%s in %s", cp ? "unpaired UTF-16 surrogate" : "NUL",
                     what);
    }
    n += put_utf8(o + n, cp);
  }
  p->pos = end + 1;
  o[n] = '\0';
  *out = (char *)o;
  return NBRDF_OK;
}

/* A plain non-negative JSON integer, exact up to 2^64 - 1. */
static nbrdf_status parse_u64(parser *p, const char *what, uint64_t *out) {
  int c = peek(p);
  if (c == '-') return fail_at(p, NBRDF_ERR_FORMAT, "%s holds a negative number", what);
  if (c < '0' || c > '9') return not_a(p, what, "not made of non-negative integers only");
  uint64_t v = 0;
  size_t first = p->pos;
  while (p->pos < p->size && p->s[p->pos] >= '0' && p->s[p->pos] <= '9') {
    unsigned d = p->s[p->pos] - '0';
    if (v > (UINT64_MAX - d) / 10)
      return fail_at(p, NBRDF_ERR_FORMAT, "%s holds an integer above 2^64 - 1", what);
    v = v * 10 + d, p->pos++;
  }
  if (p->s[first] == '0' && p->pos - first > 1)
    return fail_at(p, NBRDF_ERR_FORMAT, "%s holds a number with a leading zero", what);
  if (p->pos < p->size && strchr(".eE", p->s[p->pos]) && p->s[p->pos])
    return fail_at(p, NBRDF_ERR_FORMAT, "%s holds a number that is not an integer", what);
  *out = v;
  return NBRDF_OK;
}

/* [u64, ...] with at most `max` entries; *count gets how many. More entries than `max` is
 * NBRDF_ERR_UNSUPPORTED (too many dimensions) or FORMAT, as `too_many` says. */
static nbrdf_status parse_u64_array(parser *p, const char *what, int max, nbrdf_status too_many,
                                    uint64_t *values, int *count) {
  int c = peek(p);
  if (c != '[') return not_a(p, what, "not an array of integers");
  p->pos++;
  *count = 0;
  if (peek(p) == ']') return p->pos++, NBRDF_OK;
  for (;;) {
    if (*count == max) return fail_at(p, too_many, "%s has more than %d entries", what, max);
    nbrdf_status st = parse_u64(p, what, &values[(*count)++]);
    if (st) return st;
    c = peek(p);
    if (c == ']') return p->pos++, NBRDF_OK;
    if (c != ',') return expect(p, ',', "between array entries");
    p->pos++;
  }
}

static nbrdf_status parse_tensor(parser *p, nn_st_entry *t) {
  char what[320];
  snprintf(what, sizeof what, "tensor '%.200s'", t->name);
  if (peek(p) != '{') return not_a(p, what, "not an object");
  p->pos++;
  int have_shape = 0, have_offsets = 0;
  for (int first = 1;; first = 0) {
    int c = peek(p);
    if (c == '}' && first) break;
    char *key = NULL;
    nbrdf_status st = parse_string(p, "a field name", &key);
    if (!st) st = expect(p, ':', "after a field name");
    if (st) return free(key), st;
    char field[360];
    snprintf(field, sizeof field, "%s of %s", key, what);
    if (strcmp(key, "dtype") == 0 && !t->dtype) {
      st = parse_string(p, field, &t->dtype);
    } else if (strcmp(key, "shape") == 0 && !have_shape) {
      st = parse_u64_array(p, field, NBRDF_ST_MAX_DIMS, NBRDF_ERR_UNSUPPORTED, t->shape, &t->ndim);
      have_shape = 1;
    } else if (strcmp(key, "data_offsets") == 0 && !have_offsets) {
      uint64_t offsets[2];
      int n = 0;
      st = parse_u64_array(p, field, 2, NBRDF_ERR_FORMAT, offsets, &n);
      if (!st && n != 2) st = fail_at(p, NBRDF_ERR_FORMAT, "%s must hold 2 integers", field);
      if (!st) t->begin = offsets[0], t->end = offsets[1];
      have_offsets = 1;
    } else if (!strcmp(key, "dtype") || !strcmp(key, "shape") || !strcmp(key, "data_offsets")) {
      st = fail_at(p, NBRDF_ERR_FORMAT, "%s has two \"%s\" fields", what, key);
    } else {
      st = fail_at(p, NBRDF_ERR_FORMAT, "%s has an unknown field \"%.100s\"", what, key);
    }
    free(key);
    if (st) return st;
    c = peek(p);
    if (c == '}') break;
    if (c != ',') return expect(p, ',', "between fields");
    p->pos++;
  }
  p->pos++;
  const char *missing = !t->dtype       ? "dtype"
                        : !have_shape   ? "shape"
                        : !have_offsets ? "data_offsets"
                                        : NULL;
  if (missing) return fail_at(p, NBRDF_ERR_FORMAT, "%s has no \"%s\" field", what, missing);
  return NBRDF_OK;
}

/* Room for one more element: the (possibly moved) array, or NULL if out of memory. */
static void *grow(void *array, size_t *cap, size_t count, size_t elem) {
  if (count < *cap) return array;
  size_t n = *cap ? 2 * *cap : 16;
  void *a = realloc(array, n * elem);
  if (a) *cap = n;
  return a;
}

static nbrdf_status parse_metadata(parser *p, nn_st_header *h) {
  int c = peek(p);
  if (c == 'n' && p->size - p->pos >= 4 && memcmp(p->s + p->pos, "null", 4) == 0)
    return p->pos += 4, NBRDF_OK; /* serde reads null as "no metadata" */
  if (c != '{') return not_a(p, "__metadata__", "not an object");
  p->pos++;
  for (int first = 1;; first = 0) {
    if (peek(p) == '}' && first) break;
    nn_st_meta *meta = grow(h->meta, &h->meta_cap, h->meta_count, sizeof *meta);
    if (!meta) return core_fail(p->err, NBRDF_ERR_MEMORY, "out of memory reading the header");
    h->meta = meta;
    char **key = &h->meta[h->meta_count].key, **value = &h->meta[h->meta_count].value;
    *key = *value = NULL;
    h->meta_count++;
    nbrdf_status st = parse_string(p, "a metadata key", key);
    if (!st) st = expect(p, ':', "after a metadata key");
    if (!st && peek(p) != '"')
      st = fail_at(p, NBRDF_ERR_FORMAT, "metadata value for key '%.200s' is not a string", *key);
    if (!st) st = parse_string(p, "a metadata value", value);
    if (st) return st;
    c = peek(p);
    if (c == '}') break;
    if (c != ',') return expect(p, ',', "between metadata entries");
    p->pos++;
  }
  p->pos++;
  return NBRDF_OK;
}

nbrdf_status nn_st_parse_header(const char *json, size_t size, nn_st_header *h, nbrdf_error *err) {
  parser p = {(const unsigned char *)json, size, 0, err};
  nbrdf_status st = expect(&p, '{', "at the start of the header");
  int have_metadata = 0;
  for (int first = 1; !st; first = 0) {
    if (peek(&p) == '}' && first) break;
    char *name = NULL;
    st = parse_string(&p, "a tensor name", &name);
    if (!st) st = expect(&p, ':', "after a tensor name");
    if (!st && strcmp(name, "__metadata__") == 0) {
      free(name);
      if (have_metadata) return fail_at(&p, NBRDF_ERR_FORMAT, "two __metadata__ entries");
      have_metadata = 1;
      st = parse_metadata(&p, h);
    } else if (!st) {
      nn_st_entry *entries = grow(h->entries, &h->cap, h->count, sizeof *entries);
      if (!entries) {
        free(name);
        return core_fail(err, NBRDF_ERR_MEMORY, "out of memory reading the header");
      }
      h->entries = entries;
      nn_st_entry *t = &h->entries[h->count++];
      memset(t, 0, sizeof *t);
      t->name = name;
      st = parse_tensor(&p, t);
    } else {
      free(name);
    }
    if (st) return st;
    int c = peek(&p);
    if (c == '}') break;
    st = expect(&p, ',', "between tensors");
  }
  if (st) return st;
  p.pos++;
  if (peek(&p) >= 0) return fail_at(&p, NBRDF_ERR_FORMAT, "unexpected bytes after the JSON object");
  return NBRDF_OK;
}

void nn_st_header_free(nn_st_header *h) {
  for (size_t i = 0; i < h->count; i++) {
    free(h->entries[i].name);
    free(h->entries[i].dtype);
  }
  for (size_t i = 0; i < h->meta_count; i++) {
    free(h->meta[i].key);
    free(h->meta[i].value);
  }
  free(h->entries);
  free(h->meta);
  memset(h, 0, sizeof *h);
}
