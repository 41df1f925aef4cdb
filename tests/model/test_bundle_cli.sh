#!/usr/bin/env bash
# nbrdf bundle init / info: an untrained bundle is written, described, and
# damaged bundles are refused with the file named.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"

B="$TMP/models/untrained"
expect_exit 0 "$NBRDF" bundle --help
expect_output "bundle init DIR" "$NBRDF" bundle --help
expect_exit 0 "$NBRDF" bundle init "$B" --seed 7
for f in decoder layering sampler base_tables; do
  check "$f.safetensors written" test -s "$B/$f.safetensors"
done
check "model.json marks it untrained" grep -q '"trained":[[:space:]]*false' "$B/model.json"
check "the card says UNTRAINED" grep -q "UNTRAINED" "$B/MODEL_CARD.md"
"$NBRDF" bundle info "$B" >"$TMP/info" 2>&1
for re in "^name: +untrained$" "^trained: +NO" "^checksum: +[0-9a-f]{16}$" \
          "5344 MACs per query" "^table conductor: 12 x 8 grid"; do
  check "bundle info shows /$re/" grep -Eq -- "$re" "$TMP/info"
done

# Same seed, same checksum; the paper decoder's cost is the paper's.
sum() { "$NBRDF" bundle info "$1" | sed -n 's/^checksum: *//p'; }
expect_exit 0 "$NBRDF" bundle init "$TMP/again" --seed 7 --name other
check "same seed gives the same checksum" test "$(sum "$B")" = "$(sum "$TMP/again")"
expect_exit 0 "$NBRDF" bundle init "$TMP/paper" --decoder paper --seed 7
expect_output "1058560 MACs per query" "$NBRDF" bundle info "$TMP/paper"
check "another decoder, another checksum" test "$(sum "$B")" != "$(sum "$TMP/paper")"

# An existing bundle is not overwritten without --force.
expect_exit 1 "$NBRDF" bundle init "$B"
expect_stderr "already holds a bundle" "$NBRDF" bundle init "$B"
expect_exit 0 "$NBRDF" bundle init "$B" --seed 7 --force

# Bad usage.
expect_exit 2 "$NBRDF" bundle
expect_exit 2 "$NBRDF" bundle frob "$B"
expect_exit 2 "$NBRDF" bundle init "$TMP/x" --decoder huge
expect_exit 2 "$NBRDF" bundle init "$TMP/x" --seed -3
expect_exit 2 "$NBRDF" bundle info

# Damaged bundles: the message names the file.
rm "$B/sampler.safetensors"
expect_exit 1 "$NBRDF" bundle info "$B"
expect_stderr "sampler.safetensors" "$NBRDF" bundle info "$B"
cp "$TMP/paper/decoder.safetensors" "$TMP/again/decoder.safetensors"
expect_stderr "model.json: checksum" "$NBRDF" bundle info "$TMP/again"
expect_stderr "no-such-dir/model.json" "$NBRDF" bundle info "$TMP/no-such-dir"
finish
