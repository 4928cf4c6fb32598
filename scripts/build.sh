#!/usr/bin/env bash
# Configures (once) and builds one build tree. Incremental on later runs.
# Usage: [GS_TARGETS="a b"] scripts/build.sh BUILD_DIR [extra cmake -D options...]
set -euo pipefail
dir=$1; shift
gen=()
if command -v ninja >/dev/null; then gen=(-G Ninja); fi
if [[ ! -f $dir/CMakeCache.txt ]]; then
  cmake -S . -B "$dir" "${gen[@]}" "$@"
else
  cmake -S . -B "$dir" "$@" >/dev/null
fi
targets=()
for t in ${GS_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build "$dir" -j "$(nproc)" "${targets[@]}"
