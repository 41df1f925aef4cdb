#!/usr/bin/env bash
# One option parser for every command (src/cli/cli_options.c): '--name value' and
# '--name=value' mean the same everywhere, a bad value is a usage error naming the command,
# the option, what was expected and what was given, each command's --help lists every option
# of its table, and the completion script generated from the same tables loads and completes.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
cd "$TMP" || exit 1

# --- both spellings, the same result (bytes where the command writes a file) -----------
expect_exit 0 "$NBRDF" bundle init b1 --seed 3
expect_exit 0 "$NBRDF" bundle init b2 --seed=3 --name=b1
check "bundle init: --seed=3 and --seed 3 write the same networks" \
  cmp -s b1/decoder.safetensors b2/decoder.safetensors

consts=(--alpha1 0.2 --eta 1.5 --alpha2 0.3 --r0 0.9 --albedo 0.7 --sigma-t 1)
expect_exit 0 "$NBRDF" bake --bundle b1 "${consts[@]}" --tile 16 --size 4x4 -o apart.exr
expect_exit 0 "$NBRDF" bake --bundle=b1 --alpha1=0.2 --eta=1.5 --alpha2=0.3 --r0=0.9 \
  --albedo=0.7 --sigma-t=1 --tile=16 --size=4x4 --output=joined.exr
check "bake: both spellings bake the same bytes" cmp -s apart.exr joined.exr

expect_exit 0 "$NBRDF" render apart.exr --bundle b1 --width 4 --height 4 --spp 1 -o r1.exr
expect_exit 0 "$NBRDF" render apart.exr --bundle=b1 --width=4 --height=4 --spp=1 --output=r2.exr
# A render's EXR header differs from run to run: compare the pixels.
check "render: both spellings render the same pixels" oiiotool r1.exr r2.exr --diff

q='alpha,r0,theta_i,phi_i,theta_o,phi_o\n0.5,0.9,30,0,30,180\n'
printf "$q" >q.csv
"$NBRDF" eval --model conductor --in q.csv >e1.csv 2>/dev/null
"$NBRDF" eval --model=conductor --in=q.csv >e2.csv 2>/dev/null
check "eval: both spellings" cmp -s e1.csv e2.csv
check "eval: a value was written" grep -q '^0.5,0.9,30' e1.csv

expect_exit 0 "$NBRDF" verify apart.exr --bundle=b1 "${consts[@]}" --texels=1 --spp=2 \
  --threads=1
expect_exit 0 "$NBRDF" info --header-only apart.exr
expect_exit 0 "$NBRDF" help --

# --- bad values: usage errors (exit 2) that name the option and the value ---------------
bad() { # bad TEXT CMD...: exit 2, the text on stderr, nothing on stdout
  local text=$1; shift
  expect_exit 2 "$@"
  check "'$*' says: $text (stderr: $(head -c 200 "$TMP/err"))" grep -Fq -- "$text" "$TMP/err"
}
bad "nbrdf bake: --tile expects an integer in [8, 1024], got 'abc'" \
  "$NBRDF" bake --bundle b1 "${consts[@]}" --tile abc -o x.exr
bad "nbrdf bake: --tile expects an integer in [8, 1024], got '4'" \
  "$NBRDF" bake --bundle b1 "${consts[@]}" --tile=4 -o x.exr
bad "nbrdf bake: --compression expects zip, piz, rle or none, got 'lzw'" \
  "$NBRDF" bake --bundle b1 "${consts[@]}" --compression=lzw -o x.exr
bad "nbrdf bake: --roughness expects alpha or perceptual, got 'r'" \
  "$NBRDF" bake --bundle b1 "${consts[@]}" --roughness r -o x.exr
bad "nbrdf bake: --half takes no value, got 'yes'" \
  "$NBRDF" bake --bundle b1 "${consts[@]}" --half=yes -o x.exr
bad "nbrdf bake: --tile expects an integer in [8, 1024], got nothing" \
  "$NBRDF" bake --bundle b1 "${consts[@]}" -o x.exr --tile
bad "nbrdf bake: --tile expects an integer in [8, 1024], got ''" \
  "$NBRDF" bake --bundle b1 "${consts[@]}" -o x.exr --tile=
bad "nbrdf bake: unknown option '--frobnicate'" "$NBRDF" bake --frobnicate
check "no texture after bad options" test ! -e x.exr
bad "nbrdf verify: --spp expects an integer in [1, 100000000], got 'abc'" \
  "$NBRDF" verify apart.exr --spp=abc
bad "nbrdf verify: --gate expects worst, p90 or median, got 'p50'" \
  "$NBRDF" verify apart.exr --gate p50
bad "nbrdf render: --spp expects an integer in [1, 1048576], got '0'" \
  "$NBRDF" render apart.exr -o r.exr --spp 0
bad "nbrdf render: --mode expects neural or reference, got 'x'" \
  "$NBRDF" render apart.exr -o r.exr --mode=x
bad "nbrdf eval: --spp expects an integer in [1, 1000000000], got 'many'" \
  "$NBRDF" eval --model layered --spp many
bad "nbrdf dataset: --incident expects an integer in [1, 4096], got '0'" \
  "$NBRDF" dataset --incident=0
bad "nbrdf dataset: --count expects a 64-bit integer >= 1, got '0'" "$NBRDF" dataset --count 0
bad "nbrdf evaluate: --count expects an integer in [1, 100000], got 'x'" \
  "$NBRDF" evaluate --count x
bad "nbrdf info: takes one texture, got 'a.exr' and 'b.exr'" "$NBRDF" info a.exr b.exr
bad "nbrdf bundle: --seed expects an unsigned 64-bit integer, got '-1'" \
  "$NBRDF" bundle init b3 --seed -1
bad "nbrdf train: --steps expects an integer in [1, 1000000], got 'x'" \
  "$NBRDF" train tables --steps=x
bad "nbrdf train: --steps expects a number in [1, 1e12], got '0'" \
  "$NBRDF" train decoder --steps 0
bad "nbrdf train: --minutes expects a number of minutes in [0, 1e9], got '-1'" \
  "$NBRDF" train sampler --minutes -1
bad "nbrdf completion: SHELL expects bash or zsh, got 'fish'" "$NBRDF" completion fish

# --- --help is generated from the tables: every option a command parses is listed -----
"$NBRDF" completion bash >nbrdf.bash
check "the completion script is valid bash" bash -n nbrdf.bash
source ./nbrdf.bash
for key in help "bundle init" "bundle info" eval bake info verify render dataset \
  "train decoder" "train tables" "train layering" "train sampler" "train bundle" evaluate \
  completion; do
  cmd=${key%% *}
  "$NBRDF" "$cmd" --help >help.txt 2>&1
  opts=$(_nbrdf_options "$key")
  check "$key has options in the completion script" test -n "$opts"
  for o in $opts; do
    [ "$o" = --help ] && continue
    check "'nbrdf $cmd --help' lists $o" grep -Eq -- "(^|[ ,[])$o([] ,=|]|$)" help.txt
  done
done

# --- the completion completes ------------------------------------------------------------
complete_words() { # complete_words WORD...: what <TAB> after the words offers
  COMP_WORDS=("$@")
  COMP_CWORD=$(($# - 1))
  COMPREPLY=()
  _nbrdf
  echo "${COMPREPLY[*]}"
}
check "complete -F _nbrdf nbrdf is registered" \
  bash -c "source ./nbrdf.bash; complete -p nbrdf | grep -q -- '-F _nbrdf nbrdf'"
check "nbrdf bake --al<TAB>" test "$(complete_words nbrdf bake --al)" = \
  "--alpha1 --alpha2 --albedo --albedo-colourspace"
check "nbrdf bake --roughness <TAB>" test "$(complete_words nbrdf bake --roughness '')" = \
  "alpha perceptual"
check "nbrdf bake --compression=r<TAB>" \
  test "$(complete_words nbrdf bake --compression = r)" = "rle"
check "nbrdf tr<TAB>" test "$(complete_words nbrdf tr)" = "train"
check "nbrdf train la<TAB>" test "$(complete_words nbrdf train la)" = "layering"
check "nbrdf train layering --lo<TAB>" \
  test "$(complete_words nbrdf train layering --lo)" = "--loss --log"
check "nbrdf verify --gate <TAB>" test "$(complete_words nbrdf verify --gate '')" = \
  "worst p90 median"
check "nbrdf bake --tile <TAB> offers nothing (a number)" \
  test -z "$(complete_words nbrdf bake --tile '')"
"$NBRDF" completion zsh >nbrdf.zsh
check "zsh: the bash script through bashcompinit" grep -q '^autoload -U +X bashcompinit' nbrdf.zsh
finish
