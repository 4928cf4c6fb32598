#!/usr/bin/env bash
# The libFuzzer targets of tests/fuzz (clang, ASan+UBSan), built by ./test.sh into build-asan.
#
#   scripts/fuzz.sh run NAME BINARY [SECONDS=15]
#       What the test suite runs for each target: every regression input in
#       tests/fuzz/regressions/NAME once, then SECONDS of fuzzing seeded from tests/fuzz/corpus/NAME
#       and the real captures in ../shared/fixtures. New inputs go to a work folder in the build
#       tree, never into the repository.
#   scripts/fuzz.sh long [RUNS=10000000] [NAME...]
#       The long run: RUNS executions of each target (all by default), one target per core
#       (GS_FUZZ_JOBS=N: N at a time),
#       each with its counts in build-asan/fuzz/NAME.log and a summary at the end (ok, FINDING,
#       or interrupted: stopped with SIGINT, no reproducer written). Needs the
#       targets built: GS_TARGETS=fuzzers scripts/build.sh build-asan ... (as ./test.sh does).
#
# GS_FUZZ_TIMEOUT (seconds, default 20): how long one input may run before it counts as a hang.
# libFuzzer measures wall time, so a long run sharing a busy machine at a low priority needs more.
#
# A finding stops the run with the reproducer in the work folder (crash-*, leak-*, timeout-*):
# fix the bug, then copy the reproducer into tests/fuzz/regressions/NAME so it stays fixed.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
shared=${GS_SHARED_DIR:-$repo/../shared}
fixtures=$shared/fixtures

# seeds NAME DIR: the real captures (and shipped files) that seed NAME, cut to 64 KiB, with the
# reader-selector byte the multi-reader targets (csv, json) expect in front.
seeds() {
    local name=$1 dir=$2 f
    mkdir -p "$dir"
    put() {  # SELECTOR FILE
        [[ -f $2 ]] || return 0
        { [[ -n $1 ]] && printf "\\x$(printf %02x "$1")"; head -c 65536 "$2"; } \
            > "$dir/$(basename "$(dirname "$2")")_$(basename "$2")"
    }
    case $name in
        navdata) for f in "$fixtures"/ardrone/*navdata*.bin; do put "" "$f"; done ;;
        pave) for f in "$fixtures"/ardrone/*pave*.bin "$fixtures"/ardrone/*stream_dump*.bin; do
                  put "" "$f"; done ;;
        h264) for f in "$fixtures"/ardrone/*pave*.bin "$fixtures"/real/video/*.h264; do
                  put "" "$f"; done ;;
        annexb) for f in "$fixtures"/real/video/*.h264; do put "" "$f"; done ;;
        csv) for f in "$repo"/tests/data/flights/*/frames.csv; do put 0 "$f"; done
             for f in "$fixtures"/real/navdata_logs/*.csv; do put 1 "$f"; done
             for f in "$repo"/tests/data/flights/*/labels.csv; do put 2 "$f"; done ;;
        json) for f in "$repo"/tests/data/flights/*/flight.json; do put 0 "$f"; done
              for f in "$repo"/tests/data/flights/*/labels.json; do put 1 "$f"; done
              for f in "$repo"/assets/calibration/*.json; do put 2 "$f"; put 3 "$f"; done ;;
        *) ;;
    esac
}

# The largest input each target is given: readers scan their input linearly, so a smaller
# bound means more executions per second; each still covers several records, frames or units.
max_len() {
    case $1 in
        pave) echo 32768 ;;
        h264 | annexb | csv | json | raw) echo 8192 ;;
        *) echo 4096 ;;
    esac
}

run_target() {  # NAME BINARY WORK EXTRA_ARGS...
    local name=$1 bin=$2 work=$3
    shift 3
    local corpus=$repo/tests/fuzz/corpus/$name regress=$repo/tests/fuzz/regressions/$name
    mkdir -p "$work/corpus" "$work/artifacts"
    seeds "$name" "$work/seeds"
    if compgen -G "$regress/*" >/dev/null; then
        "$bin" -runs=1 "$regress"/* >"$work/regressions.log" 2>&1 ||
            { cat "$work/regressions.log"; echo "fuzz.$name: a regression input fails"; return 1; }
    fi
    local dirs=("$work/corpus" "$work/seeds")
    [[ -d $corpus ]] && dirs+=("$corpus")
    "$bin" -timeout="${GS_FUZZ_TIMEOUT:-20}" -rss_limit_mb=2560 -max_len="$(max_len "$name")" -print_final_stats=1 \
        -artifact_prefix="$work/artifacts/" "$@" "${dirs[@]}"
}

case ${1:-} in
    run)
        name=$2 bin=$3 secs=${4:-15}
        work=$PWD/fuzz/$name
        rm -rf "$work/seeds"
        log=$work/run.log
        mkdir -p "$work"
        if ! run_target "$name" "$bin" "$work" -max_total_time="$secs" >"$log" 2>&1; then
            tail -n 60 "$log"
            echo "fuzz.$name: FINDING (reproducer in $work/artifacts)"
            exit 1
        fi
        echo "fuzz.$name: $(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 |
                           grep -o '[0-9]*$') executions in ${secs} s, 0 findings"
        ;;
    long)
        shift
        runs=10000000
        if [[ ${1:-} =~ ^[0-9]+$ ]]; then runs=$1; shift; fi
        names=("$@")
        if [[ ${#names[@]} -eq 0 ]]; then
            for f in "$repo"/tests/fuzz/*_fuzz.cpp; do b=$(basename "$f"); names+=("${b%_fuzz.cpp}"); done
        fi
        out=$repo/build-asan/fuzz
        mkdir -p "$out"
        jobs=${GS_FUZZ_JOBS:-$(nproc)}
        pids=()
        for name in "${names[@]}"; do
            bin=$repo/build-asan/bin/${name}_fuzz
            [[ -x $bin ]] || { echo "missing $bin: build the fuzzers first"; exit 1; }
            while [[ $(jobs -rp | wc -l) -ge $jobs ]]; do sleep 5; done
            ( t0=$(date +%s)
              if run_target "$name" "$bin" "$out/long_$name" -runs="$runs" >"$out/$name.log" 2>&1; then
                  r=ok
              elif grep -q 'libFuzzer: run interrupted' "$out/$name.log" &&
                   ! compgen -G "$out/long_$name/artifacts/[!s]*" >/dev/null; then
                  # (slow-unit-* files are inputs that took over 10 s once, on a busy machine
                  # too: noted below, not findings; crash-, leak-, timeout- and oom- are.)
                  r=interrupted  # stopped (SIGINT): its executions count, nothing was found
              else
                  r=FINDING
              fi
              echo "$name $r $(grep -o 'stat::number_of_executed_units: [0-9]*' "$out/$name.log" |
                  tail -1 | grep -o '[0-9]*$') executions $(( $(date +%s) - t0 )) s$(
                  n=$(compgen -G "$out/long_$name/artifacts/slow-unit-*" | wc -l)
                  [[ $n -gt 0 ]] && echo ", $n slow units in $out/long_$name/artifacts")" \
                  >"$out/$name.result" ) &
            pids+=($!)
        done
        wait "${pids[@]}" || true
        echo "target result executions seconds"
        cat "$out"/*.result
        ! grep -q FINDING "$out"/*.result
        ;;
    *)
        sed -n '2,20p' "$0"
        exit 2
        ;;
esac
