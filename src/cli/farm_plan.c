#define _GNU_SOURCE /* open_memstream */
#include "cli/farm_plan.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/output_file.h"

/* The cost of a tile bake, measured (docs/FARM.md, "Resources"): an all-distinct RGB bake
 * spends ~7.5e-5 CPU-s per texel in its networks (docs/BAKE.md, 2048^2) and the energy
 * audit and reading add up to as much again on sharp coats (256^2 example maps: 1.7e-4
 * CPU-s per texel with start-up); memory grows with the width, not the area (540 MiB peak at
 * 8192 wide, 280-350 MiB at 256-1024 with the bundle loaded). The limits are generous: a
 * job killed at its limit costs a resubmission, a loose one only a scheduling slot. */
#define TILE_CPU_S_PER_TEXEL 2.0e-4
#define TILE_CPU_S_START 10.0
#define TILE_MIB_BASE 384
#define TILE_MIB_PER_WIDTH 0.05
#define TIME_SAFETY 3.0
#define TIME_MIN_S 600

static int round_up(double v, int step) { return (int)(ceil(v / step) * step); }

static farm_resources with_time(int cpus, int memory_mib, double cpu_s) {
  farm_resources r = {cpus, memory_mib, 0};
  double wall = TIME_SAFETY * cpu_s / (cpus > 0 ? cpus : 1);
  r.time_limit_s = wall < TIME_MIN_S ? TIME_MIN_S : round_up(wall, 60);
  return r;
}

farm_resources farm_tile_resources(int width, int height, int cpus) {
  double texels = (double)(width > 0 ? width : 1) * (double)(height > 0 ? height : 1);
  int mib = round_up(TILE_MIB_BASE + TILE_MIB_PER_WIDTH * width, 64);
  return with_time(cpus, mib, TILE_CPU_S_START + TILE_CPU_S_PER_TEXEL * texels);
}

/* The budget is the ground truth's and fit's cost-model seconds "about the wall time on one
 * free core" (nbrdf bake --help); the fit then bakes nothing. */
farm_resources farm_fit_resources(double budget_s, int cpus) {
  farm_resources r = with_time(cpus, 1024, budget_s * 2.0 + 60.0);
  r.time_limit_s = round_up(r.time_limit_s * (cpus > 0 ? cpus : 1), 60);
  return r;
}

/* verify: ~10 s of random walks per texture with its defaults (docs/VERIFY.md). */
farm_resources farm_verify_resources(int n_tiles, int cpus) {
  return with_time(cpus, 1024, 30.0 * (n_tiles > 0 ? n_tiles : 1));
}

const char *farm_shell_quote(const char *text, char *buf, size_t cap) {
  size_t k = 0;
  int plain = *text != '\0';
  for (const char *c = text; *c; c++)
    if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=/.,:@%", *c))
      plain = 0;
  if (plain) {
    snprintf(buf, cap, "%s", text);
    return buf;
  }
  if (cap < 3) return "''";
  buf[k++] = '\'';
  for (const char *c = text; *c && k + 5 < cap; c++) {
    if (*c == '\'') {
      memcpy(buf + k, "'\\''", 4);
      k += 4;
    } else {
      buf[k++] = *c;
    }
  }
  buf[k++] = '\'';
  buf[k] = '\0';
  return buf;
}

static void put_quoted(FILE *f, const char *text) {
  size_t cap = 4 * strlen(text) + 3;
  char *buf = malloc(cap);
  if (!buf) return;
  fputs(farm_shell_quote(text, buf, cap), f);
  free(buf);
}

static void put_args(FILE *f, const farm_argv *a) {
  for (int i = 0; i < a->n; i++) {
    fputs(" ", f);
    put_quoted(f, a->arg[i]);
  }
}

static void json_string(FILE *f, const char *s) {
  fputc('"', f);
  for (const unsigned char *c = (const unsigned char *)s; *c; c++) {
    if (*c == '"' || *c == '\\')
      fprintf(f, "\\%c", *c);
    else if (*c < 0x20)
      fprintf(f, "\\u%04x", *c);
    else
      fputc(*c, f);
  }
  fputc('"', f);
}

static void json_command(FILE *f, const farm_plan *p, const char *sub, const farm_argv *a,
                         const char *const *extra, int n_extra) {
  fputs("[", f);
  json_string(f, p->nbrdf);
  fputs(", ", f);
  json_string(f, sub);
  for (int i = 0; i < a->n; i++) fputs(", ", f), json_string(f, a->arg[i]);
  for (int i = 0; i < n_extra; i++) fputs(", ", f), json_string(f, extra[i]);
  fputs("]", f);
}

static void json_resources(FILE *f, farm_resources r) {
  fprintf(f, "{\"cpus\": %d, \"memory_mib\": %d, \"time_limit_s\": %d}", r.cpus, r.memory_mib,
          r.time_limit_s);
}

static void tile_path(const farm_plan *p, int tile, char *out, size_t cap) {
  texture_tile_pattern *pat = NULL;
  char *path = NULL;
  nbrdf_error err = {0};
  if (texture_tile_pattern_parse(p->output, &pat, &err) == NBRDF_OK &&
      texture_tile_pattern_path(pat, tile, &path, &err) == NBRDF_OK)
    snprintf(out, cap, "%s", path);
  else
    snprintf(out, cap, "%s", p->output);
  free(path);
  texture_tile_pattern_free(pat);
}

static void write_json(FILE *f, const farm_plan *p, double budget_s) {
  fputs("{\n  \"format\": \"nbrdf-farm-plan\",\n  \"version\": 1,\n  \"cwd\": ", f);
  json_string(f, p->cwd);
  fputs(",\n  \"output\": ", f);
  json_string(f, p->output);
  fputs(",\n  \"tiles\": [", f);
  for (int i = 0; i < p->n_tiles; i++) fprintf(f, "%s%d", i ? ", " : "", p->tiles[i].tile);
  fputs("],\n  \"jobs\": [\n", f);
  if (p->fit) {
    const char *extra[] = {"-o", p->fit};
    fputs("    {\"name\": \"fit\", \"after\": [], \"command\": ", f);
    json_command(f, p, "fit", &p->fit_args, extra, 2);
    fputs(", \"skip_if_exists\": ", f);
    json_string(f, p->fit);
    fputs(", \"resources\": ", f);
    json_resources(f, farm_fit_resources(budget_s, p->cpus));
    fputs("},\n", f);
  }
  for (int i = 0; i < p->n_tiles; i++) {
    char tile[16], out[4096];
    snprintf(tile, sizeof tile, "%d", p->tiles[i].tile);
    tile_path(p, p->tiles[i].tile, out, sizeof out);
    const char *extra[] = {p->tile_option, tile, "-o", p->output, "--fit", p->fit};
    fprintf(f, "    {\"name\": \"tile-%d\", \"after\": [%s], \"command\": ", p->tiles[i].tile,
            p->fit ? "\"fit\"" : "");
    json_command(f, p, "bake", &p->bake_args, extra, p->fit ? 6 : 4);
    fputs(", \"output\": ", f);
    json_string(f, out);
    fputs(", \"resources\": ", f);
    json_resources(f, farm_tile_resources(p->tiles[i].width, p->tiles[i].height, p->cpus));
    fputs("},\n", f);
  }
  char report[4096];
  snprintf(report, sizeof report, "%s/verify.json", p->dir);
  const char *extra[] = {"--json", report};
  fputs("    {\"name\": \"verify\", \"after\": [", f);
  for (int i = 0; i < p->n_tiles; i++) fprintf(f, "%s\"tile-%d\"", i ? ", " : "", p->tiles[i].tile);
  fputs("], \"command\": ", f);
  farm_argv va = p->verify_args;
  /* verify takes the texture first */
  fputs("[", f);
  json_string(f, p->nbrdf);
  fputs(", \"verify\", ", f);
  json_string(f, p->output);
  for (int i = 0; i < va.n; i++) fputs(", ", f), json_string(f, va.arg[i]);
  for (int i = 0; i < 2; i++) fputs(", ", f), json_string(f, extra[i]);
  fputs("], \"resources\": ", f);
  json_resources(f, farm_verify_resources(p->n_tiles, p->cpus));
  fputs("}\n  ]\n}\n", f);
}

static void sbatch_head(FILE *f, const farm_plan *p, const char *name, farm_resources r) {
  fprintf(f, "#!/usr/bin/env bash\n# Written by 'nbrdf farm slurm'; submit.sh submits it (docs/FARM.md).\n");
  fprintf(f, "#SBATCH --job-name=nbrdf-%s\n", name);
  fprintf(f, "#SBATCH --chdir=%s\n", p->cwd);
  fprintf(f, "#SBATCH --output=%s/logs/%s-%%A_%%a.log\n", p->dir, name);
  fprintf(f, "#SBATCH --cpus-per-task=%d\n#SBATCH --mem=%dM\n#SBATCH --time=%d\n", r.cpus,
          r.memory_mib, (r.time_limit_s + 59) / 60);
  if (p->partition) fprintf(f, "#SBATCH --partition=%s\n", p->partition);
  if (p->account) fprintf(f, "#SBATCH --account=%s\n", p->account);
}

static void sbatch_env(FILE *f, const farm_plan *p) {
  /* One BLAS thread per CPU the job holds (a bake's throughput per CPU-second). */
  fprintf(f, "export OPENBLAS_NUM_THREADS=%d\nset -u\n", p->cpus);
}

static void write_fit(FILE *f, const farm_plan *p, double budget_s) {
  sbatch_head(f, p, "fit", farm_fit_resources(budget_s, p->cpus));
  sbatch_env(f, p);
  fputs("# A fit already made is kept: delete it to fit again (a bake refuses a fit whose\n"
        "# inputs differ from the maps, naming the map).\nif [ -s ",
        f);
  put_quoted(f, p->fit);
  fputs(" ]; then\n  echo \"nbrdf farm: the fit exists, kept: \"", f);
  put_quoted(f, p->fit);
  fputs("\n  exit 0\nfi\nexec ", f);
  put_quoted(f, p->nbrdf);
  fputs(" fit", f);
  put_args(f, &p->fit_args);
  fputs(" -o ", f);
  put_quoted(f, p->fit);
  fputs(" --progress=json\n", f);
}

static void write_tiles(FILE *f, const farm_plan *p) {
  int w = 0, h = 0;
  for (int i = 0; i < p->n_tiles; i++) {
    if (p->tiles[i].width > w) w = p->tiles[i].width;
    if (p->tiles[i].height > h) h = p->tiles[i].height;
  }
  sbatch_head(f, p, "tiles", farm_tile_resources(w, h, p->cpus));
  fprintf(f, "#SBATCH --array=0-%d", p->n_tiles - 1);
  if (p->max_parallel > 0) fprintf(f, "%%%d", p->max_parallel);
  fputs("\n", f);
  sbatch_env(f, p);
  fputs("tiles=(", f);
  for (int i = 0; i < p->n_tiles; i++) fprintf(f, "%s%d", i ? " " : "", p->tiles[i].tile);
  fputs(")\ntile=${tiles[$SLURM_ARRAY_TASK_ID]}\n", f);
  fputs("# A tile whose texture already records the same inputs and fit is skipped by the bake;\n"
        "# scancel (SIGTERM) leaves no partial file.\nexec ",
        f);
  put_quoted(f, p->nbrdf);
  fputs(" bake", f);
  put_args(f, &p->bake_args);
  fprintf(f, " %s \"$tile\" -o ", p->tile_option);
  put_quoted(f, p->output);
  if (p->fit) {
    fputs(" --fit ", f);
    put_quoted(f, p->fit);
  }
  fputs(" --progress=json\n", f);
}

static void write_verify(FILE *f, const farm_plan *p) {
  sbatch_head(f, p, "verify", farm_verify_resources(p->n_tiles, p->cpus));
  sbatch_env(f, p);
  fputs("exec ", f);
  put_quoted(f, p->nbrdf);
  fputs(" verify ", f);
  put_quoted(f, p->output);
  put_args(f, &p->verify_args);
  fprintf(f, " --json ");
  char report[4096];
  snprintf(report, sizeof report, "%s/verify.json", p->dir);
  put_quoted(f, report);
  fputs("\n", f);
}

static void write_submit(FILE *f, const farm_plan *p) {
  fputs("#!/usr/bin/env bash\n"
        "# Written by 'nbrdf farm slurm': submits the plan in this folder (fit, then the tiles\n"
        "# as a job array after it, then verify after every tile). Run it again after a\n"
        "# failure: the jobs of the last submission still waiting are cancelled, the fit is\n"
        "# kept and the tiles already baked are skipped. Prints one 'JOB ID' line per job.\n"
        "set -euo pipefail\n"
        "cd \"$(dirname \"$0\")\"\n"
        "if [ -s jobs.txt ]; then\n"
        "  ids=$(cut -d' ' -f2 jobs.txt | paste -sd, -)\n"
        "  scancel --state=PENDING \"$ids\" 2>/dev/null || true\n"
        "fi\n"
        "submit() { sbatch --parsable \"$@\" | cut -d';' -f1; }\n",
        f);
  if (p->fit) {
    fputs("fit=$(submit fit.sbatch)\n"
          "tiles=$(submit --dependency=afterok:\"$fit\" tiles.sbatch)\n",
          f);
  } else {
    fputs("tiles=$(submit tiles.sbatch)\n", f);
  }
  fputs("verify=$(submit --dependency=afterok:\"$tiles\" verify.sbatch)\n"
        "{\n",
        f);
  if (p->fit) fputs("  echo \"fit $fit\"\n", f);
  fputs("  echo \"tiles $tiles\"\n  echo \"verify $verify\"\n} >jobs.txt.tmp\n"
        "mv jobs.txt.tmp jobs.txt\ncat jobs.txt\n",
        f);
}

static int executable(const char *name) {
  size_t n = strlen(name);
  return (n > 3 && !strcmp(name + n - 3, ".sh")) || (n > 7 && !strcmp(name + n - 7, ".sbatch"));
}

typedef struct planned_file {
  const char *name;
  char *text;
  size_t size;
} planned_file;

static nbrdf_status make_dir(const char *path, nbrdf_error *err) {
  if (mkdir(path, 0777) == 0 || errno == EEXIST) {
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) return NBRDF_OK;
    return core_fail(err, NBRDF_ERR_IO, "%s: exists and is not a folder", path);
  }
  return core_fail(err, NBRDF_ERR_IO, "%s: cannot create the folder (%s)", path, strerror(errno));
}

nbrdf_status farm_plan_write(const farm_plan *p, double budget_s, nbrdf_error *err) {
  planned_file files[5] = {{"plan.json", NULL, 0}, {"fit.sbatch", NULL, 0},
                           {"tiles.sbatch", NULL, 0}, {"verify.sbatch", NULL, 0},
                           {"submit.sh", NULL, 0}};
  nbrdf_status st = NBRDF_OK;
  for (int i = 0; i < 5 && st == NBRDF_OK; i++) {
    if (i == 1 && !p->fit) continue;
    FILE *f = open_memstream(&files[i].text, &files[i].size);
    if (!f) {
      st = core_fail(err, NBRDF_ERR_MEMORY, "farm plan: out of memory");
      break;
    }
    switch (i) {
    case 0: write_json(f, p, budget_s); break;
    case 1: write_fit(f, p, budget_s); break;
    case 2: write_tiles(f, p); break;
    case 3: write_verify(f, p); break;
    default: write_submit(f, p); break;
    }
    if (fclose(f) != 0) st = core_fail(err, NBRDF_ERR_MEMORY, "farm plan: out of memory");
  }
  char logs[4096];
  snprintf(logs, sizeof logs, "%s/logs", p->dir);
  if (st == NBRDF_OK) st = make_dir(p->dir, err);
  if (st == NBRDF_OK) st = make_dir(logs, err);
  core_output_file out[5];
  int n = 0;
  for (int i = 0; i < 5 && st == NBRDF_OK; i++) {
    if (!files[i].text) continue;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", p->dir, files[i].name);
    st = core_output_file_open(&out[n], path, NULL, 0, err);
    if (st != NBRDF_OK) break;
    n++;
    st = core_output_file_pwrite(&out[n - 1], files[i].text, files[i].size, 0, err);
    if (st == NBRDF_OK && executable(files[i].name) && fchmod(out[n - 1].fd, 0755) != 0)
      st = core_fail(err, NBRDF_ERR_IO, "%s: cannot make it executable (%s)", path,
                     strerror(errno));
  }
  if (st == NBRDF_OK)
    st = core_output_file_commit_all(out, n, err);
  else
    for (int i = 0; i < n; i++) core_output_file_abort(&out[i]);
  for (int i = 0; i < 5; i++) free(files[i].text);
  return st;
}
