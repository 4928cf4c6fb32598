#!/usr/bin/env bash
# A fault soak anyone can run (not part of ./test.sh): the virtual drone with every fault knob
# (`ardrone-gs sim`: navdata loss, reordering, duplicates, bad checksums; a video reset inside an
# IDR frame every 90 s; a navdata blackout every 120 s; a reboot half-way) recorded by
# `ardrone-gs record` for MINUTES, then every counter checked against the dataset:
#   frames recorded            = frames.csv rows = frames `replay` decodes, none unreadable
#   navdata accepted (link)    = navdata.csv rows = the recorder's accepted samples = the link's
#                                count from the first recorded sample to the last (0 lost)
#   video connections (link)   = raw/video_connections.csv rows
#   drops                      = the sum of their reasons (record --stats)
#   no frame with a lost reference kept: replay decodes every frame and conceals no more of them
#                                than the live decoder did
#   no two frames share a capture time (frames.csv t_ms strictly increases)
#   raw/ replayed through the protocol parsers (`dataset check-raw`) = frames.csv, row for row,
#                                with no warning (nothing cut short)
# Runs shorter than 5 minutes reset the video every MINUTES*60/3 s and black out navdata every
# MINUTES*60*2/5 s instead, so that a short run (`scripts/soak.sh 1`) meets every fault.
# Usage: scripts/soak.sh [MINUTES=10] [WORKDIR=/tmp/gs-soak]   (needs a built ardrone-gs)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/bin/ardrone-gs
minutes=${1:-10}
work=${2:-/tmp/gs-soak}
secs=$((minutes * 60))
reset_every=90 blackout_every=120
if ((secs < 300)); then reset_every=$((secs / 3)) blackout_every=$((secs * 2 / 5)); fi
port=${GS_SOAK_PORT_BASE:-25554}
rm -rf "$work"
mkdir -p "$work"
echo "soak: ${minutes} min, ports $port.., work in $work"
"$bin" sim --quiet --bind 127.0.0.1 --port-base "$port" --autopilot --scenario warehouse \
  --seconds $((secs + 30)) --loss 0.3 --reorder 0.05 --duplicate 0.05 --corrupt 0.05 \
  --video-reset-every "$reset_every" --video-reset-in-idr --blackout-every "$blackout_every:1.5" \
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

# raw/ through the protocol parsers, row for row against frames.csv (exit 1 at a difference).
raw_ok=0
"$bin" dataset check-raw "$work/flight" >"$work/check-raw.log" 2>&1 || raw_ok=$?

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
reasons=0
for r in dropped_link dropped_writer dropped_tap dropped_reference_lost dropped_no_picture \
  dropped_not_h264 dropped_cut_by_reset; do
  reasons=$((reasons + $(num "$rec" $r)))
done
concealed=$(num "$rec" concealed)
frames_csv=$(rows "$work/flight/frames.csv")
navdata_csv=$(rows "$work/flight/navdata.csv")
connections_csv=$(rows "$work/flight/raw/video_connections.csv")
processed=$(num "$sum" processed)
unreadable=$(num "$sum" decode_errors)
replay_concealed=$(num "$sum" concealed_frames)
raw_frames=$(grep -o '^  frames: [0-9]* replayed' "$work/check-raw.log" | grep -o '[0-9]*' || echo -1)
raw_warnings=$(grep -c '^  warning: ' "$work/check-raw.log" || true)
# frames.csv rows whose t_ms is not after the previous row's (the column found by its header).
same_time=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "t_ms") c = i; next }
  NR > 2 && $c + 0 <= prev { ++n } { prev = $c + 0 } END { print n + 0 }' "$work/flight/frames.csv")
rss=$(grep -o 'Maximum resident set size (kbytes): [0-9]*' "$work/time.log" | grep -o '[0-9]*$' || echo 0)
printf '%-44s %s\n' \
  "frames recorded / frames.csv / replayed" "$frames / $frames_csv / $processed ($unreadable unreadable)" \
  "navdata accepted (link) / recorder / rows" "$link_accepted / $accepted / $navdata_csv (status $navdata)" \
  "navdata accepted (link, first to last recorded)" "$span" \
  "video connections recorded / rows" "$connections / $connections_csv" \
  "drops / sum of their reasons" "$drops / $reasons" \
  "concealed frames live / replay" "$concealed / $replay_concealed" \
  "frames sharing a capture time" "$same_time" \
  "raw/ replay (check-raw): frames / warnings" "$raw_frames / $raw_warnings (exit $raw_ok)" \
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
check "[[ $drops -eq $reasons ]]" "drops = the sum of their reasons"
check "[[ $replay_concealed -le $concealed ]]" \
  "no frame with a lost reference kept (replay conceals no more frames than the live decoder)"
check "[[ $same_time -eq 0 ]]" "no two frames share a capture time"
check "[[ $raw_ok -eq 0 && $raw_frames -eq $frames_csv && $raw_warnings -eq 0 ]]" \
  "raw/ replayed through the protocol parsers = frames.csv (see $work/check-raw.log)"
exit $fail
