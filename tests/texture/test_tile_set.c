/* UDIM tile patterns and tile sets (src/texture/tile_pattern.c, tile_set.c): the tokens and
 * their numbering, bad patterns, tiles found on disk, substitution, and the messages of a set
 * whose maps disagree. */
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "testing.h"
#include "texture/tile_pattern.h"
#include "texture/tile_set.h"

/* The path `pattern` gives for `tile`, in a static buffer ("" on failure). */
static const char *path_of(const char *pattern, int tile) {
  static char buf[512];
  buf[0] = '\0';
  texture_tile_pattern *p = NULL;
  nbrdf_error err = {0};
  if (texture_tile_pattern_parse(pattern, &p, &err) != NBRDF_OK) {
    CHECK_MSG(0, "%s: %s", pattern, err.message);
    return buf;
  }
  char *s = NULL;
  if (texture_tile_pattern_path(p, tile, &s, &err) == NBRDF_OK)
    snprintf(buf, sizeof buf, "%s", s);
  else
    CHECK_MSG(0, "%s, tile %d: %s", pattern, tile, err.message);
  free(s);
  texture_tile_pattern_free(p);
  return buf;
}

/* The pattern is refused with NBRDF_ERR_ARGUMENT and a message holding `text`. */
static void check_bad(const char *pattern, const char *text) {
  texture_tile_pattern *p = NULL;
  nbrdf_error err = {0};
  nbrdf_status st = texture_tile_pattern_parse(pattern, &p, &err);
  CHECK_MSG(st == NBRDF_ERR_ARGUMENT && !p, "'%s' not refused (status %d)", pattern, (int)st);
  CHECK_MSG(strstr(err.message, text) && strstr(err.message, pattern),
            "'%s': message '%s' lacks '%s' or the pattern", pattern, err.message, text);
  texture_tile_pattern_free(p);
}

static void test_tile_numbers(void) {
  int u, v;
  texture_tile_uv(1001, &u, &v);
  CHECK(u == 0 && v == 0);
  texture_tile_uv(1010, &u, &v);
  CHECK(u == 9 && v == 0);
  texture_tile_uv(1011, &u, &v);
  CHECK(u == 0 && v == 1);
  texture_tile_uv(1100, &u, &v);
  CHECK(u == 9 && v == 9);
  CHECK(texture_tile_at(2, 3) == 1033);
  CHECK(texture_tile_at(10, 0) == 0 && texture_tile_at(0, 10) == 0 && texture_tile_at(-1, 0) == 0);
  nbrdf_error err = {0};
  CHECK(texture_tile_check(1001, &err) == NBRDF_OK && texture_tile_check(1100, &err) == NBRDF_OK);
  CHECK(texture_tile_check(1000, &err) == NBRDF_ERR_ARGUMENT && strstr(err.message, "1000"));
  CHECK(texture_tile_check(1101, &err) == NBRDF_ERR_ARGUMENT && strstr(err.message, "1001..1100"));
  int t = 0;
  CHECK(texture_tile_parse("1003", &t, &err) == NBRDF_OK && t == 1003);
  CHECK(texture_tile_parse("1200", &t, &err) == NBRDF_ERR_ARGUMENT);
  CHECK(texture_tile_parse("01003", &t, &err) == NBRDF_ERR_ARGUMENT);
  CHECK(texture_tile_parse("1003x", &t, &err) == NBRDF_ERR_ARGUMENT &&
        strstr(err.message, "'1003x'"));
  CHECK(texture_tile_parse("", &t, &err) == NBRDF_ERR_ARGUMENT);
}

/* Each token's numbering, as OIIO (and Mudbox/Blender for <UVTILE>) write it. */
static void test_substitution(void) {
  CHECK(!strcmp(path_of("maps/rough.<UDIM>.exr", 1001), "maps/rough.1001.exr"));
  CHECK(!strcmp(path_of("maps/rough.<UDIM>.exr", 1034), "maps/rough.1034.exr"));
  CHECK(!strcmp(path_of("rough.%(UDIM)d.exr", 1012), "rough.1012.exr"));
  /* 1034: u 3, v 3; 1012: u 1, v 1; 1003: u 2, v 0 */
  CHECK(!strcmp(path_of("rough_u<u>_v<v>.exr", 1003), "rough_u2_v0.exr"));
  CHECK(!strcmp(path_of("rough_u<U>_v<V>.exr", 1003), "rough_u3_v1.exr"));
  CHECK(!strcmp(path_of("rough_v<v>_u<u>.exr", 1012), "rough_v1_u1.exr"));
  CHECK(!strcmp(path_of("rough.<UVTILE>.exr", 1003), "rough.u3_v1.exr"));
  CHECK(!strcmp(path_of("rough.<uvtile>.exr", 1100), "rough.u10_v10.exr"));
  CHECK(!strcmp(path_of("<UDIM>", 1002), "1002"));
  /* A plain path is every tile's file. */
  CHECK(!strcmp(path_of("maps/rough.exr", 1005), "maps/rough.exr"));
  CHECK(!strcmp(path_of("0.3", 1005), "0.3"));

  texture_tile_pattern *p = NULL;
  nbrdf_error err = {0};
  CHECK(texture_tile_pattern_parse("a.<UDIM>.exr", &p, &err) == NBRDF_OK);
  CHECK(p && texture_tile_pattern_is_tiled(p));
  CHECK(p && !strcmp(texture_tile_pattern_text(p), "a.<UDIM>.exr"));
  char *s = NULL;
  CHECK(p && texture_tile_pattern_path(p, 1101, &s, &err) == NBRDF_ERR_ARGUMENT && !s);
  CHECK(strstr(err.message, "1101"));
  texture_tile_pattern_free(p);
  CHECK(texture_tile_pattern_parse("a.exr", &p, &err) == NBRDF_OK && p &&
        !texture_tile_pattern_is_tiled(p));
  texture_tile_pattern_free(p);
}

static void test_bad_patterns(void) {
  check_bad("rough.<UDIM>.<UDIM>.exr", "two tile tokens");
  check_bad("rough.<UDIM>_<u>_<v>.exr", "three tile tokens");
  check_bad("rough.<UDIM>.<UVTILE>.exr", "two tile tokens");
  check_bad("rough_u<u>_u<U>.exr", "two tile tokens");
  check_bad("rough.<udim>.exr", "unknown tile token '<udim>'");
  check_bad("rough.<tile>.exr", "unknown tile token '<tile>'");
  check_bad("rough.%(U)d.exr", "unknown tile token '%(U)d'");
  check_bad("rough_u<u>.exr", "<u> needs its partner <v>");
  check_bad("rough_v<V>.exr", "<V> needs its partner <U>");
  check_bad("rough_u<u>_v<V>.exr", "mix 0-based");
  check_bad("tiles<UDIM>/rough.exr", "in a folder");
  check_bad("rough.<UDIM>0.exr", "followed by a digit");
  check_bad("rough_<u><v>.exr", "followed by another token");
  /* '<' alone, or around something that is no word, is part of a file name */
  texture_tile_pattern *p = NULL;
  nbrdf_error err = {0};
  CHECK(texture_tile_pattern_parse("a<b.<UDIM>.exr", &p, &err) == NBRDF_OK);
  texture_tile_pattern_free(p);
  CHECK(texture_tile_pattern_parse("a<b c>.exr", &p, &err) == NBRDF_OK);
  texture_tile_pattern_free(p);
}

static void touch(const char *name) { testing_write_text(testing_path(name), "x"); }

/* The tiles listed for `pattern` (in the scratch folder) are `want` (0-terminated). */
static void check_list(const char *pattern, const int *want) {
  char full[512];
  snprintf(full, sizeof full, "%s/%s", testing_tmpdir(), pattern);
  texture_tile_pattern *p = NULL;
  nbrdf_error err = {0};
  int tiles[TEXTURE_TILE_COUNT], n = -1;
  CHECK_MSG(texture_tile_pattern_parse(full, &p, &err) == NBRDF_OK, "%s", err.message);
  if (!p) return;
  CHECK_MSG(texture_tile_pattern_list(p, tiles, &n, &err) == NBRDF_OK, "%s: %s", pattern,
            err.message);
  int k = 0;
  while (want[k])
    k++;
  CHECK_MSG(n == k, "%s: %d tiles, expected %d", pattern, n, k);
  for (int i = 0; i < n && i < k; i++)
    CHECK_MSG(tiles[i] == want[i], "%s: tile %d is %d, expected %d", pattern, i, tiles[i], want[i]);
  texture_tile_pattern_free(p);
}

static void test_list(void) {
  /* Created out of order: the list is ascending. */
  touch("r.1012.exr");
  touch("r.1002.exr");
  touch("r.1001.exr");
  touch("r.1001.exr.bak"); /* no match: something follows */
  touch("r.1003.png");     /* another extension */
  touch("rr.1004.exr");
  mkdir(testing_path("r.1005.exr"), 0755); /* a folder is no tile */
  check_list("r.<UDIM>.exr", (const int[]){1001, 1002, 1012, 0});
  check_list("r.%(UDIM)d.exr", (const int[]){1001, 1002, 1012, 0});
  check_list("r.<UDIM>.png", (const int[]){1003, 0});
  check_list("q.<UDIM>.exr", (const int[]){0});

  touch("g_u0_v0.exr");
  touch("g_u9_v1.exr");
  touch("g_u1_v0.exr");
  check_list("g_u<u>_v<v>.exr", (const int[]){1001, 1002, 1020, 0});
  touch("h_u1_v1.exr");
  touch("h_u10_v2.exr");
  check_list("h_u<U>_v<V>.exr", (const int[]){1001, 1020, 0});
  touch("m.u1_v1.exr");
  touch("m.u10_v2.exr");
  check_list("m.<UVTILE>.exr", (const int[]){1001, 1020, 0});

  /* Names that match but name no tile are refused, naming the file. */
  struct {
    const char *file, *pattern, *text;
  } bad[] = {
      {"b1.1200.exr", "b1.<UDIM>.exr", "tile 1200, outside 1001..1100"},
      {"b2.0999.exr", "b2.<UDIM>.exr", "leading zero"},
      {"b3.1000.exr", "b3.<UDIM>.exr", "tile 1000"},
      {"b4_u10_v0.exr", "b4_u<u>_v<v>.exr", "outside u 0..9"},
      {"b5_u01_v0.exr", "b5_u<u>_v<v>.exr", "leading zero"},
      {"b6.u0_v1.exr", "b6.<UVTILE>.exr", "counting from 1"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    touch(bad[i].file);
    char full[512];
    snprintf(full, sizeof full, "%s/%s", testing_tmpdir(), bad[i].pattern);
    texture_tile_pattern *p = NULL;
    nbrdf_error err = {0};
    int tiles[TEXTURE_TILE_COUNT], n;
    CHECK(texture_tile_pattern_parse(full, &p, &err) == NBRDF_OK);
    if (!p) continue;
    CHECK_MSG(texture_tile_pattern_list(p, tiles, &n, &err) == NBRDF_ERR_ARGUMENT, "%s listed",
              bad[i].file);
    CHECK_MSG(strstr(err.message, bad[i].file) && strstr(err.message, bad[i].text),
              "%s: message '%s' lacks the file or '%s'", bad[i].file, err.message, bad[i].text);
    texture_tile_pattern_free(p);
  }
  texture_tile_pattern *p = NULL;
  nbrdf_error err = {0};
  int tiles[TEXTURE_TILE_COUNT], n;
  CHECK(texture_tile_pattern_parse("/nonexistent-nbrdf/r.<UDIM>.exr", &p, &err) == NBRDF_OK);
  CHECK(p && texture_tile_pattern_list(p, tiles, &n, &err) == NBRDF_ERR_IO &&
        strstr(err.message, "/nonexistent-nbrdf/"));
  texture_tile_pattern_free(p);
  CHECK(texture_tile_pattern_parse("r.exr", &p, &err) == NBRDF_OK);
  CHECK(p && texture_tile_pattern_list(p, tiles, &n, &err) == NBRDF_ERR_ARGUMENT);
  texture_tile_pattern_free(p);
}

/* A set's maps: `args` joined with the scratch folder where they hold a '.exr'. */
static nbrdf_status resolve(const char *const *args, int n, texture_tile_set *set,
                            nbrdf_error *err) {
  static const char *names[] = {"--alpha1", "--alpha2", "--r0", "--albedo"};
  char paths[4][512];
  texture_tile_map maps[4];
  for (int i = 0; i < n; i++) {
    if (strstr(args[i], ".exr"))
      snprintf(paths[i], sizeof paths[i], "%s/%s", testing_tmpdir(), args[i]);
    else
      snprintf(paths[i], sizeof paths[i], "%s", args[i]);
    maps[i] = (texture_tile_map){names[i], paths[i]};
  }
  return texture_tile_set_resolve(maps, n, set, err);
}

static void test_set(void) {
  const char *sets[] = {"s1", "s2", "s3"};
  for (int t = 1001; t <= 1004; t++) {
    char name[64];
    for (int s = 0; s < 3; s++) {
      if (s == 1 && t == 1003) continue; /* s2 lacks 1003 */
      snprintf(name, sizeof name, "%s.%d.exr", sets[s], t);
      touch(name);
    }
  }
  touch("s3.1005.exr");
  touch("s3.1006.exr");
  touch("plain.exr");

  texture_tile_set set;
  nbrdf_error err = {0};
  /* Tiled maps that agree, with a constant and a plain file for every tile. */
  CHECK(resolve((const char *[]){"s1.<UDIM>.exr", "0.3", "plain.exr", "s1.<UDIM>.exr"}, 4, &set,
                &err) == NBRDF_OK);
  CHECK(set.count == 4 && set.tiles[0] == 1001 && set.tiles[3] == 1004);
  CHECK(texture_tile_set_has(&set, 1003) && !texture_tile_set_has(&set, 1005));
  /* Nothing tiled: no set. */
  CHECK(resolve((const char *[]){"0.3", "plain.exr"}, 2, &set, &err) == NBRDF_OK && set.count == 0);

  /* The second map lacks a tile the first has. */
  CHECK(resolve((const char *[]){"s1.<UDIM>.exr", "s2.<UDIM>.exr"}, 2, &set, &err) ==
        NBRDF_ERR_MISMATCH);
  CHECK_MSG(strstr(err.message, "--alpha2 '") && strstr(err.message, "s2.<UDIM>.exr' has no "
                                                                     "tile 1003 (found in "
                                                                     "--alpha1)"),
            "message: %s", err.message);
  /* The first map lacks tiles the second has (after a constant). */
  CHECK(resolve((const char *[]){"s1.<UDIM>.exr", "0.5", "s3.<UDIM>.exr"}, 3, &set, &err) ==
        NBRDF_ERR_MISMATCH);
  CHECK_MSG(strstr(err.message, "--alpha1 '") &&
                strstr(err.message, "has no tiles 1005, 1006 (found in --r0)"),
            "message: %s", err.message);
  /* A pattern matching nothing. */
  CHECK(resolve((const char *[]){"none.<UDIM>.exr"}, 1, &set, &err) == NBRDF_ERR_IO);
  CHECK_MSG(strstr(err.message, "--alpha1 '") && strstr(err.message, "matches no file"),
            "message: %s", err.message);
  /* A bad pattern, named by its map. */
  CHECK(resolve((const char *[]){"0.2", "s1.<udim>.exr"}, 2, &set, &err) == NBRDF_ERR_ARGUMENT);
  CHECK_MSG(!strncmp(err.message, "--alpha2: ", 10) && strstr(err.message, "<udim>"), "message: %s",
            err.message);

  /* Outputs: tiled for a set, plain otherwise. */
  CHECK(resolve((const char *[]){"s1.<UDIM>.exr"}, 1, &set, &err) == NBRDF_OK && set.count == 4);
  CHECK(texture_tile_set_check_output(&set, "-o", "latent.<UDIM>.exr", &err) == NBRDF_OK);
  CHECK(texture_tile_set_check_output(&set, "-o", "latent.exr", &err) == NBRDF_ERR_ARGUMENT);
  CHECK_MSG(strstr(err.message, "-o 'latent.exr' names one file") &&
                strstr(err.message, "4 tiles (1001..1004)"),
            "message: %s", err.message);
  texture_tile_set none = {0};
  CHECK(texture_tile_set_check_output(&none, "-o", "latent.exr", &err) == NBRDF_OK);
  CHECK(texture_tile_set_check_output(&none, "-o", "latent.<UDIM>.exr", &err) ==
        NBRDF_ERR_ARGUMENT);
  CHECK(texture_tile_set_check_output(&set, "-o", "latent.<UDIM>.<u>.exr", &err) ==
            NBRDF_ERR_ARGUMENT &&
        !strncmp(err.message, "-o: ", 4));
}

/* --tiles lists: single tiles must be in the set, ranges keep the set's tiles within them. */
static void test_select(void) {
  texture_tile_set all = {4, {1001, 1002, 1003, 1012}}, s;
  nbrdf_error err = {0};
  s = all;
  CHECK_OK(texture_tile_set_select(&s, "1012,1001-1002", &err), &err);
  CHECK(s.count == 3 && s.tiles[0] == 1001 && s.tiles[1] == 1002 && s.tiles[2] == 1012);
  s = all;
  CHECK_OK(texture_tile_set_select(&s, "1001-1100,1003", &err), &err);
  CHECK(s.count == 4); /* a tile listed twice is kept once */
  s = all;
  CHECK(texture_tile_set_select(&s, "1004", &err) == NBRDF_ERR_ARGUMENT &&
        strstr(err.message, "no tile 1004") && strstr(err.message, "1001..1012"));
  s = all;
  CHECK(texture_tile_set_select(&s, "1004-1011", &err) == NBRDF_ERR_ARGUMENT &&
        strstr(err.message, "no tiles in 1004-1011"));
  static const char *const bad[] = {"", "1003,", "1003-", "1005-1003", "abc", "1003,,1004", "999"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    s = all;
    CHECK_MSG(texture_tile_set_select(&s, bad[i], &err) == NBRDF_ERR_ARGUMENT &&
                  strstr(err.message, "tile list"),
              "'%s' not refused as a tile list: %s", bad[i], err.message);
    CHECK(s.count == 4); /* left as it was */
  }
}

int main(void) {
  RUN(test_tile_numbers);
  RUN(test_substitution);
  RUN(test_bad_patterns);
  RUN(test_list);
  RUN(test_set);
  RUN(test_select);
  return testing_finish();
}
