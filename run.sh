#!/usr/bin/env bash
# Installs what is missing, builds (Release) and runs the ground station's main job.
set -euo pipefail
cd "$(dirname "$0")"
scripts/install-deps.sh build
GS_TARGETS=ardrone-gs scripts/build.sh build -DCMAKE_BUILD_TYPE=Release
# The ground-station window, on the built-in virtual drone (warehouse scenario) unless arguments
# say otherwise (--sim SCENARIO, --replay DATASET, or a subcommand). Without a display the program
# says so and points to the headless subcommands.
exec build/bin/ardrone-gs "$@"
