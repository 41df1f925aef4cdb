#!/usr/bin/env python3
"""Picks a small regression corpus for tests/nn/safetensors_corpus/ from a (libFuzzer-merged)
corpus: a greedy set cover over gcov line and branch outcomes of the safetensors sources,
run through fuzz_safetensors.c itself. libFuzzer's -set_cover_merge keeps ~100 files (its
features count hit buckets too); this adds files while each brings at least 2 new
line/branch outcomes, then whatever files cover the remaining lines: about 45 files.

usage: /usr/bin/python3 fuzz/minimise_corpus.py CORPUS_DIR OUT_DIR   (from the repo root)"""
import glob
import gzip
import json
import os
import shutil
import subprocess
import sys
import tempfile

DRIVER = r"""
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int main(int argc, char **argv) {
  FILE *f = fopen(argv[1], "rb");
  if (!f) return 2;
  static uint8_t buf[1 << 20];
  size_t n = fread(buf, 1, sizeof buf, f);
  fclose(f);
  uint8_t *copy = malloc(n ? n : 1);
  for (size_t k = 0; k < n; k++) copy[k] = buf[k];
  LLVMFuzzerTestOneInput(copy, n);
  free(copy);
  return 0;
}
"""


def coverage_of(work, path):
    for g in glob.glob(os.path.join(work, "*.gcda")):
        os.remove(g)
    subprocess.run([os.path.join(work, "drv"), path], check=True)
    gcda = glob.glob(os.path.join(work, "*.gcda"))
    subprocess.run(["gcov", "--json-format", "-b"] + gcda, cwd=work, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    features = set()
    for j in glob.glob(os.path.join(work, "*.gcov.json.gz")):
        for f in json.load(gzip.open(j))["files"]:
            if "safetensors" not in f["file"]:
                continue
            for line in f["lines"]:
                if line["count"] > 0:
                    features.add((f["file"], line["line_number"]))
                for k, b in enumerate(line.get("branches", [])):
                    if b["count"] > 0:
                        features.add((f["file"], line["line_number"], k))
        os.remove(j)
    return features


def main(corpus, out):
    root = os.getcwd()
    work = tempfile.mkdtemp(prefix="nbrdf-minimise-")
    with open(os.path.join(work, "driver.c"), "w") as f:
        f.write(DRIVER)
    sources = [os.path.join(root, "fuzz/fuzz_safetensors.c"), os.path.join(root, "src/core/error.c")]
    sources += sorted(glob.glob(os.path.join(root, "src/nn/safetensors_*.c")))
    subprocess.run(["gcc", "-std=c11", "-D_DEFAULT_SOURCE", "-O0", "--coverage",
                    "-I" + os.path.join(root, "src"), "-I" + os.path.join(root, "include"),
                    "driver.c"] + sources + ["-lm", "-o", "drv"], cwd=work, check=True)
    files = sorted(glob.glob(os.path.join(corpus, "*")))
    cover = {f: coverage_of(work, os.path.abspath(f)) for f in files}
    every = set().union(*cover.values())
    chosen, got = [], set()
    while True:  # greedy set cover, stopping when a file adds fewer than 2 features
        best = max(files, key=lambda f: (len(cover[f] - got), -os.path.getsize(f)))
        if len(cover[best] - got) < 2:
            break
        chosen.append(best)
        got |= cover[best]
    for f in files:  # then every line that is covered at all
        if {x for x in cover[f] if len(x) == 2} - got:
            chosen.append(f)
            got |= cover[f]
    os.makedirs(out, exist_ok=True)
    for f in chosen:
        shutil.copy(f, out)
    lines = {x for x in every if len(x) == 2}
    print("%d files: %d of %d line/branch features, %d of %d lines" %
          (len(chosen), len(got), len(every), len({x for x in got if len(x) == 2}), len(lines)))
    shutil.rmtree(work)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
