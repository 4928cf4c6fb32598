#!/usr/bin/env bash
# Copies a folder of flight datasets (what `generate --suite` writes) with every navdata value
# removed: frames.csv keeps its frame, time and ground-truth columns and leaves roll, pitch, yaw,
# velocity and altitude empty (unknown, docs/dataset.md); navdata.csv and raw/ are not copied.
# The video and labels are hard links (same file system) or copies. What `eval` then measures is
# the classifier on footage without navdata, as real clips are.
# Usage: scripts/strip-navdata.sh SUITE_DIR OUT_DIR
set -euo pipefail
[[ $# -eq 2 ]] || { echo "usage: $0 SUITE_DIR OUT_DIR" >&2; exit 2; }
src=$1 out=$2
[[ -d $src ]] || { echo "$src: not a directory" >&2; exit 1; }
[[ ! -e $out ]] || { echo "$out: exists (refusing to write into it)" >&2; exit 1; }
mkdir -p "$out"
n=0
for flight in "$src"/*/; do
  [[ -f $flight/flight.json && -f $flight/frames.csv ]] || continue
  name=$(basename "$flight")
  mkdir "$out/$name"
  for f in "$flight"*; do
    case $(basename "$f") in
      frames.csv | navdata.csv | raw) ;;
      *) ln "$f" "$out/$name/" 2> /dev/null || cp -r "$f" "$out/$name/" ;;
    esac
  done
  awk -F, -v OFS=, '
    NR == 1 { for (i = 1; i <= NF; i++)
                if ($i ~ /^(roll_deg|pitch_deg|yaw_deg|vx_mps|vy_mps|vz_mps|altitude_m)$/) drop[i] = 1
              print; next }
    { for (i in drop) $i = ""; print }' "$flight/frames.csv" > "$out/$name/frames.csv"
  n=$((n + 1))
done
echo "$n flights without navdata in $out"
