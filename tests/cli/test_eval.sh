#!/usr/bin/env bash
# The point-query contract of 'nbrdf eval' (issue 2): columns, passthrough,
# exit codes, messages naming line and column, determinism across thread
# counts, and closed-form values of the analytic BRDFs computed here in awk.
set -u
source "$NBRDF_SOURCE_DIR/tests/cli/lib.sh"
DATA="$NBRDF_SOURCE_DIR/tests/cli/data"

# run_eval INPUT_FILE ARGS...: runs 'nbrdf eval ARGS' on the file; sets $rc,
# leaves stdout in $TMP/out and stderr in $TMP/err.
run_eval() {
  local in=$1; shift
  "$NBRDF" eval "$@" <"$in" >"$TMP/out" 2>"$TMP/err"
  rc=$?
}
# eval_exit CODE INPUT_FILE ARGS...
eval_exit() {
  local want=$1; shift
  run_eval "$@"
  check "'eval ${*:2}' on $(basename "$1") exits $want (got $rc; stderr: $(head -c 300 "$TMP/err"))" \
    test "$rc" = "$want"
}
# eval_error TEXT INPUT_FILE ARGS...: exits 1, nothing on stdout, stderr has TEXT.
eval_error() {
  local text=$1; shift
  eval_exit 1 "$@"
  check "stderr '$(cat "$TMP/err")' contains \"$text\"" grep -Fq -- "$text" "$TMP/err"
  check "no output on failure" test ! -s "$TMP/out"
}
# near A B REL: |A - B| <= REL * |B| (awk, doubles).
NUM='^-?[0-9]+([.][0-9]*)?([eE][-+]?[0-9]+)?$'
near() { awk -v a="$1" -v b="$2" -v r="$3" -v num="$NUM" 'BEGIN { d = a - b; if (d < 0) d = -d;
  m = b < 0 ? -b : b; exit !(a ~ num && d <= r * m) }'; }
# column NAME FILE: prints the column NAME of every data row of a CSV file.
column() { awk -F, -v n="$1" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == n) c = i; next }
  { print $c }' "$2"; }

LAYERED_HEADER="alpha1,eta,alpha2,r0,albedo,sigma_t,theta_i,phi_i,theta_o,phi_o"
SINGLE_ANGLES="theta_i,phi_i,theta_o,phi_o"

# --- help documents the contract -------------------------------------------
# (Each run of a sanitized build costs ~1 s of start-up: run the CLI as few times as possible.)
"$NBRDF" eval --help >"$TMP/help" 2>&1
check "eval --help exits 0" test $? = 0
for text in "degrees" "WITHOUT the cosine" "f_stderr" "%.17g" "alpha1,eta,alpha2,r0,albedo,sigma_t" \
  "[0, 90)" "[0.001, 1]" "exit status" "--threads" "stdin:7: column 'eta' expects"; do
  check "eval --help mentions '$text'" grep -Fq -- "$text" "$TMP/help"
done

# --- closed forms of the GGX conductor (alpha, Schlick R0) -----------------
# f = D(h) G2(wi, wo) F(wi.h) / (4 cos_i cos_o), with
#   D(h)  = alpha^2 / (pi cos^4(th) (alpha^2 + tan^2(th))^2)      (GGX)
#   G2    = 1 / (1 + Lambda(wi) + Lambda(wo)),                      (height-correlated Smith)
#   Lambda(w) = (sqrt(1 + alpha^2 tan^2(theta)) - 1) / 2
#   F     = R0 + (1 - R0) (1 - wi.h)^5                              (Schlick)
# Point 1: alpha = 0.5, R0 = 1, theta_i = theta_o = 0: h = n, D = 1/(pi alpha^2) = 4/pi,
#   Lambda = 0 so G2 = 1, F = 1, cosines 1: f = (4/pi) / 4 = 1/pi = 0.318309886183790...
printf 'alpha,r0,%s\n0.5,1,0,0,0,0\n' "$SINGLE_ANGLES" >"$TMP/c1.csv"
eval_exit 0 "$TMP/c1.csv" --model conductor
check "conductor output header" test "$(head -1 "$TMP/out")" = "alpha,r0,$SINGLE_ANGLES,f"
f=$(column f "$TMP/out")
check "conductor(0.5, R0=1) at normal incidence = 1/pi (got $f)" near "$f" 0.31830988618379067 1e-12

# Point 2: alpha = 0.5, R0 = 0.5, theta_i = theta_o = 30 deg, mirror (phi_o = 180): h = n,
#   D = 4/pi; tan^2 30 = 1/3, Lambda = (sqrt(1 + 1/12) - 1)/2 = 0.020416...; G2 = 1/(1 + 2 Lambda);
#   wi.h = cos 30, F = 0.5 + 0.5 (1 - cos 30)^5; f = D G2 F / (4 cos^2 30) = 0.20389...
want=$(awk 'BEGIN { pi = atan2(0, -1); c = cos(pi / 6); L = (sqrt(1 + 0.25 / 3) - 1) / 2;
  printf "%.17g", (4 / pi) / (1 + 2 * L) * (0.5 + 0.5 * (1 - c)^5) / (4 * c * c) }')
# Point 3, off-specular: alpha = 0.3, R0 = 0.2, theta_i = 40, theta_o = 70, phi_o = 120.
# The same formulas with the half vector h = (wi + wo) / |wi + wo|, computed in awk below.
awk_conductor() { awk -v a="$1" -v r0="$2" -v ti="$3" -v pi_="$4" -v to="$5" -v po="$6" 'BEGIN {
  pi = atan2(0, -1); d = pi / 180
  ix = sin(ti*d)*cos(pi_*d); iy = sin(ti*d)*sin(pi_*d); iz = cos(ti*d)
  ox = sin(to*d)*cos(po*d); oy = sin(to*d)*sin(po*d); oz = cos(to*d)
  hx = ix + ox; hy = iy + oy; hz = iz + oz; l = sqrt(hx*hx + hy*hy + hz*hz); hx /= l; hy /= l; hz /= l
  c2 = hz * hz; t2 = (1 - c2) / c2; D = a*a / (pi * c2 * c2 * (a*a + t2)^2)
  Li = (sqrt(1 + a*a * (1 - iz*iz) / (iz*iz)) - 1) / 2; Lo = (sqrt(1 + a*a * (1 - oz*oz) / (oz*oz)) - 1) / 2
  F = r0 + (1 - r0) * (1 - (ix*hx + iy*hy + iz*hz))^5
  printf "%.17g", D * F / (1 + Li + Lo) / (4 * iz * oz) }'; }
want3=$(awk_conductor 0.3 0.2 40 0 70 120)
printf 'alpha,r0,%s\n0.5,0.5,30,0,30,180\n0.3,0.2,40,0,70,120\n' "$SINGLE_ANGLES" >"$TMP/c2.csv"
eval_exit 0 "$TMP/c2.csv" --model conductor
f2=$(column f "$TMP/out" | sed -n 1p)
f3=$(column f "$TMP/out" | sed -n 2p)
check "conductor mirror point: $f2 vs hand-computed $want" near "$f2" "$want" 1e-12
check "conductor off-specular point: $f3 vs awk $want3" near "$f3" "$want3" 1e-12

# Dielectric reflection at normal incidence: F = ((eta - 1)/(eta + 1))^2 = 0.04 for eta = 1.5,
# D = 1/(pi alpha^2), G2 = 1: f = 0.04 / (4 pi alpha^2) = 0.04/pi for alpha = 0.5.
printf 'alpha,eta,%s\n0.5,1.5,0,0,0,0\n' "$SINGLE_ANGLES" >"$TMP/d1.csv"
eval_exit 0 "$TMP/d1.csv" --model dielectric
check "dielectric output header" test "$(head -1 "$TMP/out")" = "alpha,eta,$SINGLE_ANGLES,f"
fd=$(column f "$TMP/out")
check "dielectric(0.5, 1.5) at normal incidence = 0.04/pi (got $fd)" near "$fd" 0.012732395447351627 1e-9

# --- column order and passthrough --------------------------------------------
# Extra columns (one quoted with a comma and a doubled quote, one with spaces) come back
# byte for byte, in input order, and the values do not depend on where the columns are.
printf 'id,theta_o,alpha,"note, with ""comma""",r0,theta_i,phi_o,phi_i, tag \n' >"$TMP/p.csv"
printf 'A,30,0.5,"x, ""y""",0.5,30,180,0, keep me \n' >>"$TMP/p.csv"
printf 'B,70,0.3,,0.2,40,120,0,\n' >>"$TMP/p.csv"
eval_exit 0 "$TMP/p.csv" --model conductor
check "passthrough header" test "$(sed -n 1p "$TMP/out")" = "$(sed -n 1p "$TMP/p.csv"),f"
check "passthrough row 1" test "$(sed -n 2p "$TMP/out" | sed 's/,[^,]*$//')" = "$(sed -n 2p "$TMP/p.csv")"
check "passthrough row 2" test "$(sed -n 3p "$TMP/out" | sed 's/,[^,]*$//')" = "$(sed -n 3p "$TMP/p.csv")"
check "reordered columns give the same value (row 1)" near "$(sed -n 2p "$TMP/out" | awk -F, '{print $NF}')" "$want" 1e-12
check "reordered columns give the same value (row 2)" near "$(sed -n 3p "$TMP/out" | awk -F, '{print $NF}')" "$want3" 1e-12

# --- line endings, blank lines, header only ------------------------------------
sed 's/$/\r/' "$TMP/c2.csv" >"$TMP/crlf.csv"
printf '\n\n  \n' >>"$TMP/crlf.csv"
eval_exit 0 "$TMP/crlf.csv" --model conductor
check "CRLF input and trailing blank lines give the same values" \
  test "$(column f "$TMP/out" | tr '\n' ' ')" = "$f2 $f3 "
check "CRLF output has LF line endings" bash -c "! grep -q $'\r' '$TMP/out'"
printf '%s\n' "$LAYERED_HEADER" >"$TMP/h.csv"
eval_exit 0 "$TMP/h.csv" --model layered
check "header-only input gives header-only output" \
  test "$(cat "$TMP/out")" = "$LAYERED_HEADER,f,f_stderr"
: >"$TMP/empty.csv"
eval_error "no header row" "$TMP/empty.csv" --model conductor

# --- layered: f and a positive f_stderr; determinism across threads ---------------
cp "$DATA/eval_layered.csv" "$TMP/l.csv"
eval_exit 0 "$TMP/l.csv" --model layered --spp 64 --seed 7 --threads 1
cp "$TMP/out" "$TMP/l1.out"
check "layered output header" test "$(head -1 "$TMP/l1.out")" = "$(head -1 "$TMP/l.csv"),f,f_stderr"
check "layered output has one row per input row" \
  test "$(grep -c . "$TMP/l1.out")" = "$(grep -c . "$TMP/l.csv")"
check "layered f is finite and >= 0 and f_stderr > 0 on every row" awk -F, -v num="$NUM" '
  NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  { f = $c["f"]; s = $c["f_stderr"]; if (!(f ~ num && s ~ num && f >= 0 && s > 0)) bad = 1 }
  END { exit bad }' "$TMP/l1.out"
eval_exit 0 "$TMP/l.csv" --model layered --spp 64 --seed 7 --threads 2
check "--threads 1 and --threads 2 give identical output" cmp -s "$TMP/l1.out" "$TMP/out"
eval_exit 0 "$TMP/l.csv" --model layered --spp 64 --seed 8 --threads 2
check "another seed gives other values" bash -c "! cmp -s '$TMP/l1.out' '$TMP/out'"

# --- grazing and extreme parameters never print NaN ----------------------------
cp "$DATA/eval_extremes.csv" "$TMP/x.csv"
eval_exit 0 "$TMP/x.csv" --model layered --spp 16
check "extreme rows give finite numbers, f >= 0" awk -F, -v num="$NUM" '
  NR > 1 { if (!($(NF-1) ~ num && $NF ~ num && $(NF-1) >= 0)) bad = 1 } END { exit bad || NR < 2 }' \
  "$TMP/out"

# --- errors name the line and column; exit 1 -----------------------------------
{ echo "$LAYERED_HEADER"; for i in 1 2 3 4 5; do echo "0.1,1.5,0.3,0.9,0.8,1,30,0,30,180"; done
  echo "0.1,abc,0.3,0.9,0.8,1,30,0,30,180"; } >"$TMP/bad.csv"
eval_error "stdin:7: column 'eta' expects a number in [1, 4], got 'abc'" "$TMP/bad.csv" --model layered --spp 4
sed 's/^0.1,abc/2,1.5/' "$TMP/bad.csv" >"$TMP/bad2.csv"
eval_error "stdin:7: column 'alpha1' expects a number in [0.001, 1], got '2'" "$TMP/bad2.csv" --model layered --spp 4
printf 'alpha,r0,%s\n0.5,1,0,0,95,0\n' "$SINGLE_ANGLES" >"$TMP/bad3.csv"
eval_error "stdin:2: column 'theta_o' expects a number in [0, 90), got '95'" "$TMP/bad3.csv" --model conductor
printf 'alpha,r0,%s\n0.5,1,0,0,inf,0\n' "$SINGLE_ANGLES" >"$TMP/bad4.csv"
eval_error "stdin:2: column 'theta_o' expects a number in [0, 90), got 'inf'" "$TMP/bad4.csv" --model conductor
printf 'alpha,r0,%s\n0.5,-0.1,0,0,5,0\n' "$SINGLE_ANGLES" >"$TMP/bad5.csv"
eval_error "stdin:2: column 'r0' expects a number in [0, 1], got '-0.1'" "$TMP/bad5.csv" --model conductor
printf 'alpha,r0,%s\n\n0.5,,0,0,5,0\n' "$SINGLE_ANGLES" >"$TMP/bad6.csv"
eval_error "stdin:3: column 'r0' expects a number in [0, 1], got nothing" "$TMP/bad6.csv" --model conductor
printf 'alpha,r0,%s\n0.5,1,0,0,5,0\n0.5,1,0\n' "$SINGLE_ANGLES" >"$TMP/bad7.csv"
eval_error "stdin:3: 3 fields, but the header has 6 columns" "$TMP/bad7.csv" --model conductor
printf 'alpha,%s\n0.5,0,0,5,0\n' "$SINGLE_ANGLES" >"$TMP/bad8.csv"
eval_error "missing column 'r0'" "$TMP/bad8.csv" --model conductor
eval_error "missing column 'eta'" "$TMP/bad8.csv" --model dielectric
eval_error "missing column 'alpha1'" "$TMP/c1.csv" --model layered
printf 'alpha,r0,%s,f\n0.5,1,0,0,5,0,1\n' "$SINGLE_ANGLES" >"$TMP/bad9.csv"
eval_error "already has a column 'f'" "$TMP/bad9.csv" --model conductor
printf 'alpha,r0,%s\n0.5,"1,0,0,5,0\n' "$SINGLE_ANGLES" >"$TMP/bad10.csv"
eval_error "line 2: a quoted field is never closed" "$TMP/bad10.csv" --model conductor

# --- bad usage: exit 2 ------------------------------------------------------------
eval_exit 2 "$TMP/c1.csv"
eval_exit 2 "$TMP/c1.csv" --model neural-ish
check "unknown model is named" grep -Fq -- "--model expects layered, conductor, dielectric, neural, neural-conductor or neural-dielectric, got 'neural-ish'" "$TMP/err"
eval_exit 2 "$TMP/c1.csv" --model conductor --frobnicate
eval_exit 2 "$TMP/c1.csv" --model layered --spp 0
eval_exit 2 "$TMP/c1.csv" --model layered --seed -3
eval_exit 2 "$TMP/c1.csv" --model layered --threads x
eval_exit 2 "$TMP/c1.csv" --model conductor extra-argument
eval_exit 0 "$TMP/c1.csv" --model=conductor --spp=8 --seed=1 --threads=1

finish
