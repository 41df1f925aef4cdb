#!/usr/bin/env bash
# nbrdf bundle init / info: an untrained bundle is written, described, and
# damaged bundles are refused with the file named. Each bundle command loads
# 4 MB of weights, slow under sanitizers: outputs are captured once and grepped.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"

# expect_err TEXT: the stderr of the last expect_exit contains TEXT.
expect_err() { check "stderr has '$1' (got: $(head -c 300 "$TMP/err"))" grep -Fq -- "$1" "$TMP/err"; }

B="$TMP/models/untrained"
expect_exit 0 "$NBRDF" bundle --help
check "usage names init" grep -q "bundle init DIR" "$TMP/out"
expect_exit 0 "$NBRDF" bundle init "$B" --seed 7
for f in decoder layering sampler base_tables; do
  check "$f.safetensors written" test -s "$B/$f.safetensors"
done
check "model.json marks it untrained" grep -q '"trained":[[:space:]]*false' "$B/model.json"
check "the card says UNTRAINED" grep -q "UNTRAINED" "$B/MODEL_CARD.md"
expect_exit 0 "$NBRDF" bundle info "$B"
cp "$TMP/out" "$TMP/info"
for re in "^name: +untrained$" "^trained: +NO" "^checksum: +[0-9a-f]{16}$" \
          "5344 MACs per query" "^table conductor: 12 x 8 grid"; do
  check "bundle info shows /$re/" grep -Eq -- "$re" "$TMP/info"
done
sum_b=$(sed -n 's/^checksum: *//p' "$TMP/info")

# Same seed, same checksum (printed by init too); the paper decoder's cost is the paper's.
expect_exit 0 "$NBRDF" bundle init "$TMP/again" --seed 7 --name other
check "same seed gives the same checksum" grep -q "checksum $sum_b" "$TMP/out"
expect_exit 0 "$NBRDF" bundle init "$TMP/paper" --decoder paper --seed 7
check "another decoder, another checksum" test -z "$(grep "checksum $sum_b" "$TMP/out")"
expect_exit 0 "$NBRDF" bundle info "$TMP/paper"
check "paper decoder: 1058560 MACs" grep -q "1058560 MACs per query" "$TMP/out"

# Audit slopes: none after init; measured and recorded by audit-slopes, shown by info.
check "bundle info says it has no audit slopes" grep -q "^audit: .*no slopes" "$TMP/info"
expect_exit 0 "$NBRDF" bundle audit-slopes "$B" --bases 16 --clearcoat-bases 4 --progress=json
check "audit-slopes names model.json" grep -q "model.json: audit slopes of 'untrained'" "$TMP/out"
check "audit-slopes reports progress" grep -q '"stage":"audit slopes"' "$TMP/out"
check "model.json has the slopes" grep -q '"audit_slopes"' "$B/model.json"
check "model.json records the command" grep -q 'audit-slopes --bases 16 --clearcoat-bases 4 --seed 11' "$B/model.json"
expect_exit 0 "$NBRDF" bundle info "$B"
check "bundle info says the slopes were measured" grep -q "^audit: .*slopes measured.*per direction$" "$TMP/out"
expect_exit 2 "$NBRDF" bundle audit-slopes "$B" --bases 0 --clearcoat-bases 0
expect_exit 2 "$NBRDF" bundle audit-slopes "$B" --bases -5
expect_exit 2 "$NBRDF" bundle audit-slopes
expect_exit 1 "$NBRDF" bundle audit-slopes "$TMP/no-such-bundle"
expect_err "no-such-bundle/model.json"

# An existing bundle is not overwritten without --force.
expect_exit 1 "$NBRDF" bundle init "$B"
expect_err "already holds a bundle"
expect_exit 0 "$NBRDF" bundle init "$B" --seed 7 --force

# Bad usage.
expect_exit 2 "$NBRDF" bundle
expect_exit 2 "$NBRDF" bundle frob "$B"
expect_exit 2 "$NBRDF" bundle init "$TMP/x" --decoder huge
expect_exit 2 "$NBRDF" bundle init "$TMP/x" --seed -3
expect_exit 2 "$NBRDF" bundle info
check "nothing written on bad usage" test ! -e "$TMP/x"

# Damaged bundles: the message names the file.
rm "$B/sampler.safetensors"
expect_exit 1 "$NBRDF" bundle info "$B"
expect_err "sampler.safetensors"
cp "$TMP/paper/decoder.safetensors" "$TMP/again/decoder.safetensors"
expect_exit 1 "$NBRDF" bundle info "$TMP/again"
expect_err "model.json: checksum"
expect_exit 1 "$NBRDF" bundle info "$TMP/no-such-dir"
expect_err "no-such-dir/model.json"
finish
