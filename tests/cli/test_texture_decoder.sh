#!/usr/bin/env bash
# Textures that carry their own decoder (format version 2, issue 17), from the
# command line: bake --decoder embeds it; info, verify, render and eval
# --texture use it; the committed version-1 texture is still read; a copy
# through oiiotool (which drops the decoder), a damaged decoder and bad
# --texture queries are refused with messages naming the file, line or column.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
differ() { ! cmp -s "$1" "$2"; }
V1="$NBRDF_SOURCE_DIR/tests/cli/data/v1_constant_rgb.exr"
BUNDLE="$NBRDF_SOURCE_DIR/models/default"
# A decoder of random weights with the default bundle's latent size.
"$NBRDF" bundle init rnd --decoder medium --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
P=(--bundle "$BUNDLE" --alpha1 0.3 --eta 1.5 --alpha2 0.2 --r0 0.9,0.6,0.3 --albedo 0.5 --sigma-t 1)

# The committed version-1 file: small, read, decoded with the bundle's decoder.
check "the v1 fixture is small" test "$(stat -c %s "$V1")" -lt 100000
expect_exit 0 "$NBRDF" info "$V1"
check "v1: format version 1" grep -Eq '^format: +version 1,' "$TMP/out"
check "v1: decoder bundle" grep -Eq '^decoder: +bundle$' "$TMP/out"

expect_exit 0 "$NBRDF" bake "${P[@]}" --decoder rnd/decoder.safetensors -o v2.exr
# The energy audit (on by default) adds the optional nbrdf:maxAlbedo attribute,
# which version-1 readers ignore; without it the bytes are exactly version 1's.
expect_exit 0 "$NBRDF" bake "${P[@]}" --energy-audit 0 -o v1.exr
# The fixture was baked with models/v1 (the default until 2026-11-26) on another machine.
# Its bytes cannot be promised here: the networks agree across CPUs and OpenBLAS kernels
# within float rounding only (docs/RELIABILITY.md, "Determinism"), and a value that close
# to a half's rounding boundary rounds to the neighbouring half. So the header (format
# version, channels, tiles, every attribute) must be the fixture's exactly and each value
# within two half ulps (2^-9 relative; idiff fails a value only past both the relative and
# the 1e-6 absolute bound, which covers values under 1e-3 whose half step is smaller).
# The writer's bytes for given values are checked in tests/texture/test_latent_decoder.c.
expect_exit 0 "$NBRDF" bake "${P[@]}" --bundle "$NBRDF_SOURCE_DIR/models/v1" --energy-audit 0 -o old.exr
header() { oiiotool --info -v "$1" | sed -e 1d -e '2s/^.* : //'; }
check "a models/v1 bake without --decoder or audit has the committed v1 file's header" \
  test "$(header old.exr)" = "$(header "$V1")" -a -n "$(header old.exr)"
check "... and its values within half rounding" \
  idiff -q -a -fail 1e-6 -failrelative 2e-3 -warn 1e-6 -warnrelative 2e-3 old.exr "$V1"
printf 'id,u,v,theta_i,phi_i,theta_o,phi_o\nq,0.5,0.5,30,0,30,180\n' >q0.csv
expect_exit 1 "$NBRDF" eval --texture "$V1" --bundle "$BUNDLE" --in q0.csv
check "today's default refuses the fixture, naming its bundle" \
  grep -Fq "baked with model 'default' (checksum 0ab22d273b6be904)" "$TMP/err"
expect_exit 0 "$NBRDF" bake "${P[@]}" -o v1audit.exr
expect_exit 0 "$NBRDF" info v1audit.exr
check "an audited bake without --decoder is still format version 1" \
  grep -Eq '^format: +version 1,' "$TMP/out"
check "an audited bake records its max albedo" grep -Eq '^max albedo: +[0-9.]+ ' "$TMP/out"
expect_exit 0 "$NBRDF" info v2.exr
check "v2: format version 2" grep -Eq '^format: +version 2,' "$TMP/out"
size=$(stat -c %s rnd/decoder.safetensors)
sum=$(python3 -c '
import sys
h = 0xcbf29ce484222325
for b in open(sys.argv[1], "rb").read():
    h = ((h ^ b) * 0x100000001b3) & 0xffffffffffffffff
print("%016x" % h)' rnd/decoder.safetensors)
check "v2: decoder own ($size bytes, $sum)" grep -Fq "decoder:       own ($size bytes, checksum $sum)" "$TMP/out"
check "v2: the full check parses the decoder" grep -Fq 'own decoder: medium, log1p output' "$TMP/out"

# verify, render and eval --texture decode with the embedded decoder.
fast=(--texels 1 --spp 16)
expect_exit 0 "$NBRDF" verify v2.exr "${P[@]}" "${fast[@]}"
check "verify says own" grep -Fq "decoder: own ($size bytes, checksum $sum)" "$TMP/out"
expect_exit 0 "$NBRDF" verify v1.exr "${P[@]}" "${fast[@]}" --json v1.json
check "verify of v1 says bundle" grep -Fq 'decoder: bundle' "$TMP/out"
check "verify JSON says bundle" grep -Eq '"decoder":\s*"bundle"' v1.json
for t in v1 v2; do
  expect_exit 0 "$NBRDF" render $t.exr --bundle "$BUNDLE" -o r_$t.exr --width 16 --height 16 --spp 2 \
    --lobe 0,0
done
check "renders differ (the texture's own decoder was used)" differ r_v1.exr r_v2.exr
check "lobe images differ" differ r_v1-lobe-0-0-0.png r_v2-lobe-0-0-0.png
printf 'id,u,v,theta_i,phi_i,theta_o,phi_o\nq,0.5,0.5,30,0,30,180\n' >q.csv
expect_exit 0 "$NBRDF" eval --texture v1.exr --bundle "$BUNDLE" --in q.csv
cp "$TMP/out" e1.csv
check "eval --texture header" grep -Fxq 'id,u,v,theta_i,phi_i,theta_o,phi_o,f_r,f_g,f_b' e1.csv
expect_exit 0 "$NBRDF" eval --texture v2.exr --bundle "$BUNDLE" --in q.csv
check "eval --texture decodes with the own decoder" differ e1.csv "$TMP/out"

# oiiotool keeps formatVersion 2 but drops the decoder: refused, saying why.
oiiotool v2.exr -o copied.exr
for cmd in "info copied.exr" "eval --texture copied.exr --in q.csv" \
  "render copied.exr -o r.exr --width 8 --height 8"; do
  expect_exit 1 "$NBRDF" $cmd
  check "$cmd: names the file and the cause" grep -Fq 'copied.exr: format version 2 says the texture carries its own decoder, but the nbrdf:decoder attribute is missing: a tool that copies only the attributes it knows (oiiotool' "$TMP/err"
done
check "no render output" test ! -e r.exr

# A byte flipped inside the embedded decoder: the checksum catches it.
python3 - <<'PY'
data = bytearray(open("v2.exr", "rb").read())
dec = open("rnd/decoder.safetensors", "rb").read()
at = data.find(dec[4096:4160])
assert at > 0
data[at + 7] ^= 0x20
open("damaged.exr", "wb").write(data)
PY
expect_exit 1 "$NBRDF" info --header-only damaged.exr
check "damaged: named" grep -Fq 'damaged.exr: the embedded decoder is damaged' "$TMP/err"
expect_exit 1 "$NBRDF" verify damaged.exr "${P[@]}" "${fast[@]}"
check "verify damaged: named" grep -Fq 'damaged.exr: the embedded decoder is damaged' "$TMP/err"

# --decoder with --accuracy compact (issue 30, 4.6): it is the decoder the scene's latents are
# fitted with and whose fine-tuned copy teaches the compact decoder; the texture carries the
# compact one, so the bake says what became of --decoder, and the result is not the bundle's.
expect_exit 0 "$NBRDF" bake "${P[@]}" --decoder rnd/decoder.safetensors --accuracy compact \
  --budget 3 -o cdec.exr
check "compact --decoder: the summary says what became of it: $(cat "$TMP/out")" grep -Fq \
  "decoder: rnd/decoder.safetensors, fine-tuned to the scene, taught the compact decoder" "$TMP/out"
expect_exit 0 "$NBRDF" bake "${P[@]}" --accuracy compact --budget 3 -o cbundle.exr
check "compact --decoder: a different texture than the bundle decoder's" differ cdec.exr cbundle.exr

# bake --decoder refusals name the file.
expect_exit 1 "$NBRDF" bake "${P[@]}" --decoder missing.safetensors -o x.exr
check "missing decoder named" grep -Fq 'missing.safetensors' "$TMP/err"
expect_exit 1 "$NBRDF" bake "${P[@]}" --decoder rnd/sampler.safetensors -o x.exr
check "a sampler as decoder named" grep -Fq 'rnd/sampler.safetensors' "$TMP/err"
check "no output" test ! -e x.exr

# eval --texture: bad CSV names the line and column; usage errors exit 2.
E=(eval --texture v2.exr --bundle "$BUNDLE")
printf 'u,v,theta_i,phi_i,theta_o,phi_o\n0.5,0.5,30,0,30,180\n0.5,x,30,0,30,180\n' >bad.csv
expect_exit 1 "$NBRDF" "${E[@]}" --in bad.csv
check "bad number: line 3, column v" grep -Fq "bad.csv:3: column 'v' expects a number in [0, 1], got 'x'" "$TMP/err"
check "nothing written on error" test ! -s "$TMP/out"
printf 'u,v,theta_i,phi_i,theta_o,phi_o\n1.5,0.5,30,0,30,180\n' >bad.csv
expect_exit 1 "$NBRDF" "${E[@]}" --in bad.csv
check "u out of range" grep -Fq "bad.csv:2: column 'u' expects a number in [0, 1], got '1.5'" "$TMP/err"
printf 'u,v,theta_i,phi_i,theta_o,phi_o\n0.5,0.5,90,0,30,180\n' >bad.csv
expect_exit 1 "$NBRDF" "${E[@]}" --in bad.csv
check "theta 90 refused" grep -Fq "bad.csv:2: column 'theta_i' expects a number in [0, 90), got '90'" "$TMP/err"
printf 'u,v,theta_i,phi_i,theta_o\n0.5,0.5,30,0,30\n' >bad.csv
expect_exit 1 "$NBRDF" "${E[@]}" --in bad.csv
check "missing column" grep -Fq "missing column 'phi_o'" "$TMP/err"
printf 'u,v,theta_i,phi_i,theta_o,phi_o,f_g\n0.5,0.5,30,0,30,180,1\n' >bad.csv
expect_exit 1 "$NBRDF" "${E[@]}" --in bad.csv
check "output column present" grep -Fq "the input already has a column 'f_g'" "$TMP/err"
printf 'u,v,theta_i,phi_i,theta_o,phi_o\n0.5,0.5,30,0\n' >bad.csv
expect_exit 1 "$NBRDF" "${E[@]}" --in bad.csv
check "short row" grep -Fq "bad.csv:2: 4 fields, but the header has 6 columns" "$TMP/err"
expect_exit 2 "$NBRDF" "${E[@]}" --level 1 --in q.csv
check "no such level" grep -Fq 'v2.exr has 1 mip level (0..0); there is no level 1' "$TMP/err"
expect_exit 1 "$NBRDF" "${E[@]}" --in nothere.csv
check "missing --in named" grep -Fq 'nothere.csv' "$TMP/err"
expect_exit 2 "$NBRDF" "${E[@]}" --model neural --in q.csv
expect_exit 2 "$NBRDF" "${E[@]}" --spp 4 --in q.csv
expect_exit 2 "$NBRDF" eval --model conductor --level 1 --in q.csv
expect_exit 2 "$NBRDF" "${E[@]}" --level -1 --in q.csv
# A mono texture writes f.
expect_exit 0 "$NBRDF" bake "${P[@]}" --r0 0.9 -o mono.exr
expect_exit 0 "$NBRDF" eval --texture mono.exr --bundle "$BUNDLE" --in q.csv
check "mono: f" grep -Fxq 'id,u,v,theta_i,phi_i,theta_o,phi_o,f' "$TMP/out"
finish
