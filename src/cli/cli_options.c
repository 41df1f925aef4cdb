#include "cli/cli_options.h"

#include <float.h>
#include <stdarg.h>
#include <string.h>

#include "cli/cli_common.h"

int cli_opt_bad(const char *cmd, const char *option, const char *what, const char *value) {
  return cli_usage_error(cmd, "%s expects %s, got '%s'", option, what, value);
}

const char *cli_opt_number(double v, char *buf, size_t cap) {
  char raw[32];
  snprintf(raw, sizeof raw, "%g", v);
  size_t n = 0;
  int exponent = 0; /* inside the exponent, before its first significant digit */
  for (const char *c = raw; *c && n + 1 < cap; c++) {
    if (*c == 'e') {
      exponent = 1;
    } else if (exponent && (*c == '+' || (*c == '0' && c[1]))) {
      continue;
    } else if (exponent && *c != '-') {
      exponent = 0;
    }
    buf[n++] = *c;
  }
  buf[n] = '\0';
  return buf;
}

/* "a|b|c" -> "a, b or c" in `buf`. */
static const char *choice_words(const char *choices, char *buf, size_t cap) {
  size_t n = 0, count = 1;
  for (const char *c = choices; *c; c++)
    count += *c == '|';
  buf[0] = '\0';
  size_t k = 0;
  for (const char *c = choices; *c && n + 8 < cap; k++) {
    size_t len = strcspn(c, "|");
    const char *sep = k == 0 ? "" : (k + 1 == count ? " or " : ", ");
    n += (size_t)snprintf(buf + n, cap - n, "%s%.*s", sep, (int)len, c);
    c += len + (c[len] == '|');
  }
  return buf;
}

/* What the option's value must be, for its error. */
static const char *expected(const cli_opt *o, char *buf, size_t cap) {
  switch (o->type) {
  case CLI_OPT_INT:
    snprintf(buf, cap, "an integer in [%.17g, %.17g]", o->lo, o->hi);
    break;
  case CLI_OPT_U64:
    if (o->hi > 0)
      snprintf(buf, cap, "an integer in [%.17g, %.17g]", o->lo, o->hi);
    else if (o->lo > 0)
      snprintf(buf, cap, "a 64-bit integer >= %.17g", o->lo);
    else
      snprintf(buf, cap, "an unsigned 64-bit integer");
    break;
  case CLI_OPT_DOUBLE:
  case CLI_OPT_FLOAT: {
    char lo[32], hi[32];
    cli_opt_number(o->lo, lo, sizeof lo), cli_opt_number(o->hi, hi, sizeof hi);
    if (o->type == CLI_OPT_FLOAT && o->hi >= FLT_MAX)
      snprintf(buf, cap, "a number in [%s, 3.4e38]", lo);
    else if (o->hi >= 1e300)
      snprintf(buf, cap, "a number >= %s", lo);
    else
      snprintf(buf, cap, "a number in [%s, %s]", lo, hi);
    break;
  }
  case CLI_OPT_ENUM:
    return choice_words(o->choices, buf, cap);
  default:
    snprintf(buf, cap, "%s", o->meta ? o->meta : "a value");
  }
  return buf;
}

static int read_value(const char *cmd, const cli_opt *o, const char *v) {
  char what[256];
  switch (o->type) {
  case CLI_OPT_INT: {
    long n;
    if (!cli_parse_int(v, (long)o->lo, (long)o->hi, &n))
      return cli_opt_bad(cmd, o->name, expected(o, what, sizeof what), v);
    *(int *)o->dest = (int)n;
    return 0;
  }
  case CLI_OPT_U64: {
    uint64_t n;
    if (!cli_parse_u64(v, &n) || (double)n < o->lo || (o->hi > 0 && (double)n > o->hi))
      return cli_opt_bad(cmd, o->name, expected(o, what, sizeof what), v);
    *(uint64_t *)o->dest = n;
    return 0;
  }
  case CLI_OPT_DOUBLE: {
    double d;
    if (!cli_parse_double(v, &d) || !(d >= o->lo && d <= o->hi))
      return cli_opt_bad(cmd, o->name, expected(o, what, sizeof what), v);
    *(double *)o->dest = d;
    return 0;
  }
  case CLI_OPT_FLOAT: {
    float f;
    if (!cli_parse_float(v, &f) || !(f >= o->lo && f <= o->hi))
      return cli_opt_bad(cmd, o->name, expected(o, what, sizeof what), v);
    *(float *)o->dest = f;
    return 0;
  }
  case CLI_OPT_STRING:
  case CLI_OPT_PATH:
    *(const char **)o->dest = v;
    return 0;
  case CLI_OPT_ENUM: {
    const char *c = o->choices;
    for (int k = 0; *c; k++) {
      size_t len = strcspn(c, "|");
      if (strlen(v) == len && !strncmp(c, v, len)) {
        *(int *)o->dest = o->values ? o->values[k] : k;
        return 0;
      }
      c += len + (c[len] == '|');
    }
    return cli_opt_bad(cmd, o->name, expected(o, what, sizeof what), v);
  }
  case CLI_OPT_CUSTOM:
    return o->parse(cmd, o, v);
  default:
    return 0;
  }
}

/* The option argv[i] names: 1 with *value set (NULL for "--name" alone), else 0. */
static int matches(const cli_opt *o, const char *arg, const char **value) {
  size_t n = strlen(o->name);
  *value = NULL;
  if (o->alias && !strcmp(arg, o->alias)) return 1;
  if (strncmp(arg, o->name, n)) return 0;
  if (arg[n] == '=') *value = arg + n + 1;
  return arg[n] == '\0' || arg[n] == '=';
}

int cli_options_parse(const char *cmd, const cli_opt *table, int argc, char **argv, int first,
                      cli_positionals *pos) {
  int options_end = 0;
  for (int i = first; i < argc; i++) {
    const char *a = argv[i];
    if (!options_end && !strcmp(a, "--")) {
      options_end = 1;
      continue;
    }
    if (options_end || a[0] != '-' || !a[1]) {
      if (!pos || pos->max == 0) return cli_usage_error(cmd, "unexpected argument '%s'", a);
      if (pos->count == pos->max && pos->max == 1)
        return cli_usage_error(cmd, "takes one %s, got '%s' and '%s'", pos->meta, pos->value[0], a);
      if (pos->count == pos->max)
        return cli_usage_error(cmd, "takes at most %d %s; '%s' is one too many", pos->max,
                               pos->meta, a);
      pos->value[pos->count++] = a;
      continue;
    }
    if (cli_is_help(a)) return CLI_OPTIONS_HELP;
    const cli_opt *o = table;
    const char *v = NULL;
    for (; o->type != CLI_OPT_END || o->help; o++)
      if (o->type != CLI_OPT_END && matches(o, a, &v)) break;
    if (o->type == CLI_OPT_END) return cli_usage_error(cmd, "unknown option '%s'", a);
    if (o->seen) ++*o->seen;
    if (o->type == CLI_OPT_FLAG) {
      if (v) return cli_usage_error(cmd, "%s takes no value, got '%s'", o->name, v);
      *(int *)o->dest = o->value;
      continue;
    }
    if (!v) {
      if (i + 1 >= argc) {
        char what[256];
        return cli_usage_error(cmd, "%s expects %s, got nothing", o->name,
                               expected(o, what, sizeof what));
      }
      v = argv[++i];
    }
    if (!v[0]) {
      char what[256];
      return cli_opt_bad(cmd, o->name, expected(o, what, sizeof what), v);
    }
    if (read_value(cmd, o, v)) return CLI_EXIT_USAGE;
  }
  return CLI_OPTIONS_OK;
}

void cli_options_help(FILE *out, const cli_opt *table) {
  for (const cli_opt *o = table; o->type != CLI_OPT_END || o->help; o++) {
    if (o->type == CLI_OPT_END) {
      fprintf(out, "%s\n", o->help);
      continue;
    }
    char left[160];
    const char *meta = o->meta ? o->meta : (o->choices ? o->choices : "VALUE");
    int n =
        snprintf(left, sizeof left, "  %s%s%s%s%s", o->alias ? o->alias : "", o->alias ? ", " : "",
                 o->name, o->type == CLI_OPT_FLAG ? "" : " ", o->type == CLI_OPT_FLAG ? "" : meta);
    const char *h = o->help ? o->help : "";
    if (n < 24) {
      fprintf(out, "%-24s", left);
    } else {
      fprintf(out, "%s\n%24s", left, "");
    }
    for (;;) {
      size_t len = strcspn(h, "\n");
      fprintf(out, "%.*s\n", (int)len, h);
      if (!h[len]) break;
      h += len + 1;
      fprintf(out, "%24s", "");
    }
  }
}

const char *cli_opt_completion(const cli_opt *o, char *buf, size_t cap) {
  if (o->type == CLI_OPT_FLAG) return "";
  if (o->type == CLI_OPT_PATH) return "f";
  if (!o->choices) return "v";
  size_t n = (size_t)snprintf(buf, cap, "w ");
  for (const char *c = o->choices; *c && n + 1 < cap; c++)
    buf[n++] = *c == '|' ? ' ' : *c;
  buf[n < cap ? n : cap - 1] = '\0';
  return buf;
}

void cli_options_parse_visit(void *user, const char *sub, const cli_opt *table) {
  cli_parse_call *c = user;
  if (sub && c->sub && strcmp(sub, c->sub)) return;
  c->rc = cli_options_parse(c->cmd, table, c->argc, c->argv, c->first, c->pos);
}

void cli_options_help_visit(void *user, const char *sub, const cli_opt *table) {
  (void)sub;
  cli_options_help(user, table);
}
