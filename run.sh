#!/usr/bin/env bash
# Installs what is missing, builds (Release) and runs the ground station's main job.
set -euo pipefail
cd "$(dirname "$0")"
scripts/install-deps.sh build
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release
echo "ardrone-gs: the window does not exist yet; showing what the protocol stack reads from a real AR.Drone 2 capture:"
exec build/bin/ardrone-gs "$@"
