#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test through CTest:
#   build/       Release (GCC), warnings as errors: the whole suite, each test program run as a
#                few GoogleTest shards (GS_TEST_SHARDS: one process start per shard, not per test);
#   build-asan/  clang 14, ASan+UBSan, -O1, no GUI: the drone/ tests, then every libFuzzer target
#                of tests/fuzz for GS_FUZZ_SECONDS (default 10) each, seeded from ../shared/fixtures
#                (scripts/fuzz.sh; the long run is `scripts/fuzz.sh long`);
#   build-tsan/  GCC, ThreadSanitizer, -O1, no GUI: the threaded parts (the link against the
#                virtual drone, the recorder, the video receiver's frame pool, the queues, and
#                app::Session without the window).
# Prints the time each stage took at the end.
set -euo pipefail
cd "$(dirname "$0")"
times=()
stage_start=$SECONDS
stage() {  # NAME: closes the stage that ran since the last call
    times+=("$(printf '%-34s %4d s' "$1" $((SECONDS - stage_start)))")
    stage_start=$SECONDS
}
scripts/install-deps.sh test
stage "packages"
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -DGS_WERROR=ON -DGS_TEST_SHARDS=ON
stage "build (Release)"
ctest --test-dir build --output-on-failure -j 2 --timeout 300
stage "tests (Release)"

# -O1 -g1: half the compile time of -O2 -g, line numbers in the reports all the same.
sanitizer_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1"
                 -DGS_WERROR=ON -DGS_BUILD_GUI=OFF)
# The ASan tree is built by clang (libFuzzer); a tree configured by another compiler is redone.
if [[ -f build-asan/CMakeCache.txt ]] &&
   ! grep -q '^CMAKE_CXX_COMPILER:.*clang' build-asan/CMakeCache.txt; then
    rm -rf build-asan
fi
CC=clang-14 CXX=clang++-14 GS_TARGETS="drone_tests fuzzers" scripts/build.sh build-asan \
  "${sanitizer_flags[@]}" -DGS_SANITIZE=address,undefined -DGS_FUZZ=ON \
  -DGS_FUZZ_SECONDS="${GS_FUZZ_SECONDS:-10}"
stage "build (ASan+UBSan, fuzzers)"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-asan --output-on-failure -j 2 --timeout 600 -L drone
stage "tests (ASan+UBSan)"
ctest --test-dir build-asan --output-on-failure -j 2 --timeout 300 -L fuzz
stage "fuzzing"
unset ASAN_OPTIONS UBSAN_OPTIONS

GS_TARGETS=threads_tests scripts/build.sh build-tsan "${sanitizer_flags[@]}" -DGS_SANITIZE=thread
stage "build (TSan)"
TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
  ctest --test-dir build-tsan --output-on-failure -j 2 --timeout 900 -L threads
stage "tests (TSan)"
printf '%s\n' "time per stage:" "${times[@]}" "total $SECONDS s"
