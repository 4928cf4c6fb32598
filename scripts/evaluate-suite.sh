#!/usr/bin/env bash
# Reproduces the README's classifier evaluation: renders the 82-flight suite (thesis table 5.1)
# with the virtual drone, replays it through both classifiers split by split, and prints the
# summary rows of each report.
# Usage: scripts/evaluate-suite.sh [WORKDIR=/tmp/gs-suite] [SEED=2026] [REALISM=clean|real]
#   REALISM=real films the same flights as a real AR.Drone 2 camera, link and estimator would
#   (`generate --realism --bitrate 1000`: drone/sim/realism.hpp) into suite_real_SEED.
# Every core is used (generate and eval default to all; JOBS=N to change). Needs a built
# ardrone-gs (./run.sh or ./test.sh). The clean suite takes about 6 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/bin/ardrone-gs
work=${1:-/tmp/gs-suite}
seed=${2:-2026}
realism=${3:-clean}
jobs=()
[[ -n ${JOBS:-} ]] && jobs=(-j "$JOBS")
case $realism in
  clean) gen=(); tag=$seed ;;
  real) gen=(--realism --bitrate 1000); tag=real_$seed ;;
  *) echo "REALISM must be clean or real, not '$realism'" >&2; exit 2 ;;
esac
suite=$work/suite_$tag
if [[ ! -f $suite/open_path3_10/flight.json ]]; then
  rm -rf "$suite"
  "$bin" generate --suite --seed "$seed" "${gen[@]}" --out "$suite" "${jobs[@]}" -q
fi
for c in thesis flow; do
  for s in tune test all; do
    out=$work/eval_${tag}_${c}_$s
    rm -rf "$out"
    split=()
    [[ $s != all ]] && split=(--split "$s")
    "$bin" eval "$suite" --out "$out" --classifier "$c" "${split[@]}" "${jobs[@]}" -q || true
    echo "== seed $seed ($realism), classifier $c, split $s ($out/report.md)"
    grep -E '^\| (group|cluttered|open|uncluttered|\*\*all\*\*) \|' "$out/report.md"
  done
done
