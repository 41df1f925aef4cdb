#!/usr/bin/env bash
# A bundle that reads an earlier bundle's textures (model.json "reads_textures_of"): a
# retrained layering network must not orphan the textures users baked. `train bundle
# --reads-textures-of` records it only when the decoders are the same bytes; a texture of
# the old bundle then decodes with the new one exactly as with its own; without the list it
# is refused naming both checksums; another decoder, and a damaged list, are refused.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP"
D="$NBRDF_SOURCE_DIR/models/default"
P=(--alpha1 0.3 --eta 1.5 --alpha2 0.2 --r0 0.9,0.6,0.3 --albedo 0.5 --sigma-t 1)
expect_exit 0 "$NBRDF" bake --bundle "$D" "${P[@]}" --energy-audit 0 -o old.exr
# Another layering network (random weights, the same architecture) over default's decoder.
"$NBRDF" bundle init rnd --decoder medium --seed 3 >/dev/null || { echo "bundle init failed" >&2; exit 1; }
parts=(--decoder "$D/decoder.safetensors" --tables "$D/base_tables.safetensors"
  --layering rnd/layering.safetensors --sampler "$D/sampler.safetensors")
printf 'id,u,v,theta_i,phi_i,theta_o,phi_o\nq,0.5,0.5,30,0,30,180\nr,0.2,0.7,70,40,80,200\n' >q.csv
expect_exit 0 "$NBRDF" eval --texture old.exr --bundle "$D" --in q.csv
cp "$TMP/out" own.csv

expect_exit 0 "$NBRDF" train bundle -o plain --name next "${parts[@]}"
expect_exit 1 "$NBRDF" eval --texture old.exr --bundle plain --in q.csv
sum=$(grep -o '"checksum":[^,]*' "$D/model.json" | grep -o '[0-9a-f]\{16\}')
check "the refusal names the texture's bundle and checksum" \
  grep -Fq "baked with model 'default' (checksum $sum)" "$TMP/err"

expect_exit 0 "$NBRDF" train bundle -o next --name next "${parts[@]}" --reads-textures-of "$D"
check "model.json lists the old bundle" grep -Fq "\"checksum\":	\"$sum\"" next/model.json
expect_exit 0 "$NBRDF" bundle info next
check "bundle info says which textures it reads" \
  grep -Fq "reads textures of: default (checksum $sum; the same decoder)" "$TMP/out"
expect_exit 0 "$NBRDF" eval --texture old.exr --bundle next --in q.csv
check "the old texture decodes with the new bundle exactly as with its own" cmp -s own.csv "$TMP/out"
expect_exit 0 "$NBRDF" verify old.exr --bundle next "${P[@]}" --texels 1 --spp 16
# Transitive: a bundle reading `next` also reads what `next` reads.
expect_exit 0 "$NBRDF" train bundle -o third --name third "${parts[@]}" --reads-textures-of next
expect_exit 0 "$NBRDF" eval --texture old.exr --bundle third --in q.csv
check "reads are transitive" cmp -s own.csv "$TMP/out"
# A texture baked with the new bundle is still refused by the old one.
expect_exit 0 "$NBRDF" bake --bundle next "${P[@]}" --energy-audit 0 -o new.exr
expect_exit 1 "$NBRDF" eval --texture new.exr --bundle "$D" --in q.csv

# Another decoder: refused, and nothing written.
expect_exit 1 "$NBRDF" train bundle -o other --name other --decoder rnd/decoder.safetensors \
  --tables "$D/base_tables.safetensors" --layering rnd/layering.safetensors --reads-textures-of "$D"
check "another decoder is refused naming the files" grep -Fq "is not byte for byte" "$TMP/err"
check "nothing is written" test ! -e other

# The old bundle is an input: writing the new one over it is refused, and it stays intact.
cp -r "$D" old
expect_exit 1 "$NBRDF" train bundle -o old --name next --decoder "$D/decoder.safetensors" \
  --tables "$D/base_tables.safetensors" --layering rnd/layering.safetensors --reads-textures-of old
check "writing over the old bundle is refused" grep -Fq "old/" "$TMP/err"
check "the old bundle is intact" cmp -s old/layering.safetensors "$D/layering.safetensors"

# A damaged list: refused at load, naming the key.
cp -r next broken
sed -i 's/"checksum":	"'"$sum"'"/"checksum":	"xyz"/' broken/model.json
expect_exit 1 "$NBRDF" bundle info broken
check "a damaged list is refused naming the key" grep -Fq '"reads_textures_of" entry 1' "$TMP/err"
finish
