#!/usr/bin/env bash
# Reproduces the README's classifier evaluation: renders the 82-flight suite (thesis table 5.1)
# with the virtual drone, replays it through both classifiers split by split, and prints the
# summary rows of each report.
# Usage: scripts/evaluate-suite.sh [WORKDIR=/tmp/gs-suite] [SEED=2026]
# Needs a built ardrone-gs (./run.sh or ./test.sh). Takes about 6 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/bin/ardrone-gs
work=${1:-/tmp/gs-suite}
seed=${2:-2026}
suite=$work/suite_$seed
if [[ ! -f $suite/open_path3_10/flight.json ]]; then
  rm -rf "$suite"
  "$bin" generate --suite --seed "$seed" --out "$suite" -j 2 -q
fi
for c in thesis flow; do
  for s in tune test all; do
    out=$work/eval_${seed}_${c}_$s
    rm -rf "$out"
    split=()
    [[ $s != all ]] && split=(--split "$s")
    "$bin" eval "$suite" --out "$out" --classifier "$c" "${split[@]}" -j 2 -q
    echo "== seed $seed, classifier $c, split $s ($out/report.md)"
    grep -E '^\| (group|cluttered|open|uncluttered|\*\*all\*\*) \|' "$out/report.md"
  done
done
