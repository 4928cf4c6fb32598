#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test through CTest:
#   build/       Release, warnings as errors, the whole suite;
#   build-asan/  ASan+UBSan, no GUI, the drone/ tests (codecs, link, datasets).
set -euo pipefail
cd "$(dirname "$0")"
scripts/install-deps.sh test
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -DGS_WERROR=ON
ctest --test-dir build --output-on-failure -j 2 --timeout 300
# -O1 -g1: half the compile time of -O2 -g, line numbers in the reports all the same.
GS_TARGETS=drone_tests scripts/build.sh build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DGS_WERROR=ON \
  -DGS_SANITIZE=address,undefined -DGS_BUILD_GUI=OFF
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j 2 --timeout 600 -L drone
