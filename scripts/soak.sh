#!/usr/bin/env bash
# A fault soak anyone can run (not part of ./test.sh): the virtual drone with every fault knob
# (`ardrone-gs sim`: navdata loss, reordering, duplicates, bad checksums; a video reset inside an
# IDR frame every 90 s; a navdata blackout every 120 s; a reboot half-way) recorded by
# `ardrone-gs record` for MINUTES, then every counter checked against the dataset:
#   frames recorded            = frames.csv rows = frames `replay` decodes, none unreadable
#   navdata accepted (link)    = navdata.csv rows = the recorder's accepted samples = the link's
#                                count from the first recorded sample to the last (0 lost)
#   video connections (link)   = raw/video_connections.csv rows
#   drops                      = the sum of their reasons; no frame with a lost reference kept
# and raw/ replayed through the protocol parsers gives the same frame count.
# Usage: scripts/soak.sh [MINUTES=10] [WORKDIR=/tmp/gs-soak]   (needs a built ardrone-gs)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/bin/ardrone-gs
minutes=${1:-10}
work=${2:-/tmp/gs-soak}
secs=$((minutes * 60))
port=${GS_SOAK_PORT_BASE:-25554}
rm -rf "$work"
mkdir -p "$work"
echo "soak: ${minutes} min, ports $port.., work in $work"
"$bin" sim --quiet --bind 127.0.0.1 --port-base "$port" --autopilot --scenario warehouse \
  --seconds $((secs + 30)) --loss 0.3 --reorder 0.05 --duplicate 0.05 --corrupt 0.05 \
  --video-reset-every 90 --video-reset-in-idr --blackout-every 120:1.5 \
  --reboot-at $((secs / 2)) --boot-ms 3000 >"$work/sim.log" 2>&1 &
sim=$!
trap 'kill "$sim" 2>/dev/null || true' EXIT
# Ready when its navdata port is bound (a loaded machine takes seconds to start it).
for _ in $(seq 150); do ss -Hunl "sport = :$port" | grep -q . && break; sleep 0.2; done
timer=()
[[ -x /usr/bin/time ]] && timer=(/usr/bin/time -v)  # peak memory, when the tool is there
"${timer[@]}" "$bin" record --drone 127.0.0.1 --port-base "$port" --seconds "$secs" --connect-timeout 30 \
  --quiet --out "$work/flight" --stats "$work/record.json" >"$work/record.log" 2>"$work/time.log" ||
  { cat "$work/record.log"; echo "soak: record failed"; exit 1; }
cat "$work/record.log"
"$bin" replay "$work/flight" --out "$work/replay" -q 2>"$work/replay.err" ||
  { cat "$work/replay.err"; echo "soak: replay failed"; exit 1; }

# The numbers (JSON fields are on lines of their own).
num() { grep -o "\"$2\": *[0-9]*" "$1" | head -1 | grep -o '[0-9]*$'; }
rows() { echo $(( $(wc -l <"$1") - 1 )); }
rec=$work/record.json sum=$work/replay/summary.json
frames=$(num "$rec" frames)
navdata=$(num "$rec" navdata)
accepted=$(num "$rec" navdata_accepted)
link_accepted=$(num "$rec" navdata_accepted_while_recording)
span=$(num "$rec" navdata_link_span)
connections=$(num "$rec" video_connections)
drops=$(num "$rec" drops)
frames_csv=$(rows "$work/flight/frames.csv")
navdata_csv=$(rows "$work/flight/navdata.csv")
connections_csv=$(rows "$work/flight/raw/video_connections.csv")
processed=$(num "$sum" processed)
unreadable=$(num "$sum" decode_errors)
rss=$(grep -o 'Maximum resident set size (kbytes): [0-9]*' "$work/time.log" | grep -o '[0-9]*$' || echo 0)
printf '%-44s %s\n' \
  "frames recorded / frames.csv / replayed" "$frames / $frames_csv / $processed ($unreadable unreadable)" \
  "navdata accepted (link) / recorder / rows" "$link_accepted / $accepted / $navdata_csv (status $navdata)" \
  "navdata accepted (link, first to last recorded)" "$span" \
  "video connections recorded / rows" "$connections / $connections_csv" \
  "drops (sum of reasons in record.json)" "$drops" \
  "record: peak RSS" "$((rss / 1024)) MB"
fail=0
check() { if ! eval "$1"; then echo "soak: MISMATCH: $2"; fail=1; fi; }
check "[[ $frames -eq $frames_csv && $frames_csv -eq $processed && $unreadable -eq 0 ]]" \
  "frames recorded = frames.csv rows = frames replayed"
check "[[ $accepted -eq $navdata_csv && $navdata -eq $navdata_csv ]]" \
  "navdata rows = samples the recorder took from the link"
check "[[ $span -eq $navdata_csv ]]" \
  "navdata rows = samples the link accepted from the first recorded one to the last"
# The link's own count, read from its status slot (published every 20 ms) at start and stop, may
# include up to 20 ms of samples (4 at 200 Hz) before the first and after the last recorded one.
check "[[ $link_accepted -ge $navdata_csv && $((link_accepted - navdata_csv)) -le 8 ]]" \
  "navdata rows = samples the link accepted while recording (within its status period at each end)"
check "[[ $connections -eq $connections_csv && $connections -ge 2 ]]" \
  "video connections = raw/video_connections.csv rows (the resets and the reboot are there)"
exit $fail
