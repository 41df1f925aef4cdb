# Sourced by the bench scripts that take [BUILD_DIR] [WORK_DIR] (pass them "$@"): sets root
# (the source tree), build (absolute; default root/build), work (created; default a new
# temporary folder) and nbrdf (the CLI of that build).
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
work="${2:-$(mktemp -d)}"
mkdir -p "$work"
nbrdf="$build/nbrdf"
