#!/usr/bin/env bash
# The one prepared device check (docs/SHADERS.md, "Running on a GPU"): pack the GPU tests and
# benches here, run them on a bare GPU machine, get one Markdown report back.
#
#   bash bench/gpu_check.sh pack BUILD_DIR PACK_DIR [STEPS_FILE...]
#       On the build machine. Copies the binaries named in bench/gpu_check.steps (and any
#       further STEPS_FILEs, or $NBRDF_GPU_CHECK_STEPS) into PACK_DIR/bin, every *.spv of
#       BUILD_DIR into PACK_DIR/spv, and the shared libraries they need (ldd; glibc, the
#       dynamic loader and libvulkan excepted: those come with the machine / Debian's
#       libvulkan1 .deb) into PACK_DIR/lib.tar.xz. A step whose binary this build lacks is
#       recorded and skipped at run time.
#   bash bench/gpu_check.sh run PACK_DIR OUT_DIR
#       On the GPU machine, from the repository root (models/ is read from there), after
#       the caller has installed the Vulkan loader (for f in .gl/*.deb; do dpkg -x $f /;
#       done; ldconfig). Unpacks the libraries to a temporary folder, points the loader at
#       NVIDIA's ICD when /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json exists, sets
#       NBRDF_VK_DEVICE=NVIDIA unless set, prints nvidia-smi's name, driver and clocks, runs
#       every step with its own timeout inside a total budget (NBRDF_GPU_CHECK_BUDGET
#       seconds, default 450), keeps going after a failed step, and writes
#       OUT_DIR/gpu_check.md (status, time and output of every step) and OUT_DIR/<step>.log.
#       NBRDF_GPU_CHECK_QUICK=1 adds --quick to the bench steps (a CPU dry run:
#       NBRDF_VK_DEVICE=llvmpipe).
#
# Steps file: one step a line, "TIMEOUT_S BINARY [ARGS...]"; '#' starts a comment; @REPO@ in
# ARGS is replaced by the repository root at run time. BINARY is a file name looked up
# under BUILD_DIR (bench/, tests/, anywhere), e.g. "120 bench_gpu_nn --quick".
set -uo pipefail

here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/.." && pwd)

usage() {
  sed -n '2,30p' "$0" >&2
  exit 2
}

# Libraries that must come from the GPU machine itself.
system_lib() {
  case "$(basename "$1")" in
    libc.so* | libm.so* | libpthread.so* | libdl.so* | librt.so* | libresolv.so* | ld-linux* | \
      libvulkan.so* | linux-vdso*) return 0 ;;
  esac
  return 1
}

pack() {
  local build=$1 out=$2
  shift 2
  [ -d "$build" ] || { echo "gpu_check: no build folder $build" >&2; exit 1; }
  rm -rf "$out"
  mkdir -p "$out/bin" "$out/spv"
  local steps="$out/steps"
  : > "$steps"
  : > "$out/skipped"
  local f
  for f in "$here/gpu_check.steps" "$@" ${NBRDF_GPU_CHECK_STEPS:-}; do
    [ -f "$f" ] || { echo "gpu_check: no steps file $f" >&2; exit 1; }
    grep -v '^[[:space:]]*\(#\|$\)' "$f" >> "$steps"
  done
  local libs
  libs=$(mktemp -d)
  local timeout name args path lib
  while read -r timeout name args; do
    [ -e "$out/bin/$name" ] && continue
    path=$(find "$build" -path "$build/CMakeFiles" -prune -o -type f -name "$name" -perm -u+x \
             -print 2>/dev/null | head -n 1)
    if [ -z "$path" ]; then
      echo "gpu_check: $name is not in $build (step kept, skipped at run time)"
      echo "$name not in the build" >> "$out/skipped"
      continue
    fi
    # A binary linked to OpenImageIO pulls ~260 libraries (~95 MB xz'ed, minutes to pack):
    # more than NBRDF_GPU_CHECK_MAX_LIBS (default 40) and it stays behind.
    local deps n
    deps=$(ldd "$path" | awk '/=> \// {print $3}')
    n=$(echo "$deps" | grep -c .)
    if [ "$n" -gt "${NBRDF_GPU_CHECK_MAX_LIBS:-40}" ]; then
      echo "gpu_check: $name needs $n shared libraries: not packed (skipped at run time)"
      echo "$name not packed: needs $n shared libraries" >> "$out/skipped"
      continue
    fi
    cp "$path" "$out/bin/$name"
    strip --strip-debug "$out/bin/$name" 2>/dev/null || true
    for lib in $deps; do
      system_lib "$lib" || cp -Ln "$lib" "$libs/" 2>/dev/null || true
    done
  done < "$steps"
  find "$build" -path "$build/CMakeFiles" -prune -o -type f -name '*.spv' -print |
    while read -r spv; do cp "$spv" "$out/spv/"; done
  strip --strip-debug "$libs"/* 2>/dev/null || true
  tar -C "$libs" -cf - . | xz -T2 -6 > "$out/lib.tar.xz"
  rm -rf "$libs"
  cp "$0" "$out/gpu_check.sh"
  echo "gpu_check: packed $(ls "$out/bin" | wc -l) binaries, $(ls "$out/spv" | wc -l) SPIR-V" \
       "kernels, $(tar -tJf "$out/lib.tar.xz" | grep -c '\.so') libraries into $out" \
       "($(du -sh "$out" | cut -f1))"
}

run() {
  local pack=$1 out=$2
  pack=$(cd "$pack" && pwd)
  mkdir -p "$out"
  out=$(cd "$out" && pwd)
  local budget=${NBRDF_GPU_CHECK_BUDGET:-450} start=$SECONDS
  local libs
  libs=$(mktemp -d)
  tar -C "$libs" -xJf "$pack/lib.tar.xz"
  export LD_LIBRARY_PATH="$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  local icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
  [ -f "$icd" ] && export VK_DRIVER_FILES=$icd
  export NBRDF_VK_DEVICE=${NBRDF_VK_DEVICE:-NVIDIA}
  export NBRDF_SPIRV_DIR=$pack/spv NBRDF_SOURCE_DIR=$repo
  local md=$out/gpu_check.md
  {
    echo "# nbrdf GPU check"
    echo
    echo "$(date -u '+%Y-%m-%d %H:%M UTC'), $(uname -n), commit $(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo '?')"
    echo "NBRDF_VK_DEVICE=$NBRDF_VK_DEVICE, VK_DRIVER_FILES=${VK_DRIVER_FILES:-unset}, budget ${budget} s"
    echo
    echo '```'
    if command -v nvidia-smi >/dev/null; then
      nvidia-smi --query-gpu=name,driver_version,clocks.max.sm,clocks.sm,memory.total \
        --format=csv 2>&1
    else
      echo "nvidia-smi: not found"
    fi
    echo '```'
    echo
    echo "| step | status | seconds |"
    echo "|---|---|---|"
  } > "$md"
  local details=$out/details.md
  : > "$details"
  local timeout name args i=0 status rc t0 secs left log
  while read -r timeout name args; do
    i=$((i + 1))
    args=${args//@REPO@/$repo}
    if [ "${NBRDF_GPU_CHECK_QUICK:-0}" = 1 ] && [[ $name == bench_* ]]; then args="$args --quick"; fi
    log=$out/$(printf '%02d' $i)-$name.log
    left=$((budget - (SECONDS - start)))
    if [ ! -x "$pack/bin/$name" ]; then
      status="skipped: $(grep -m1 "^$name " "$pack/skipped" 2>/dev/null | cut -d' ' -f2- || true)"
      [ "$status" = "skipped: " ] && status="skipped: not in the pack"
      secs=0
      : > "$log"
    elif [ "$left" -lt 15 ]; then
      status="skipped: budget spent"
      secs=0
      : > "$log"
    else
      [ "$timeout" -gt "$left" ] && timeout=$left
      echo "gpu_check: [$i] $name $args (timeout ${timeout}s)" >&2
      t0=$SECONDS
      (cd "$repo" && timeout -k 10 "$timeout" "$pack/bin/$name" $args) > "$log" 2>&1 < /dev/null
      rc=$?
      secs=$((SECONDS - t0))
      case $rc in
        0) status=ok ;;
        124 | 137) status="TIMEOUT after ${timeout} s" ;;
        *) status="FAILED (exit $rc)" ;;
      esac
    fi
    echo "| $name $args | $status | $secs |" >> "$md"
    {
      echo "## $name $args: $status"
      echo
      if grep -q '^|' "$log"; then
        grep '^|' "$log"
        echo
      fi
      echo '```'
      if [ "$(wc -l < "$log")" -gt 150 ]; then
        head -n 20 "$log"
        echo "... ($(wc -l < "$log") lines; the whole log is $(basename "$log"))"
        tail -n 100 "$log"
      else
        cat "$log"
      fi
      echo '```'
      echo
    } >> "$details"
    echo "gpu_check: [$i] $name: $status (${secs} s)" >&2
  done < "$pack/steps"
  { echo; cat "$details"; } >> "$md"
  rm -f "$details"
  rm -rf "$libs"
  echo "gpu_check: report $md ($((SECONDS - start)) s)" >&2
}

[ $# -ge 3 ] || usage
mode=$1
shift
case $mode in
  pack) pack "$@" ;;
  run) run "$@" ;;
  *) usage ;;
esac
