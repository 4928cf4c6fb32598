#!/usr/bin/env bash
# Installs the Debian 12 packages ardrone-gs needs, only those missing. Idempotent.
# Usage: scripts/install-deps.sh [build|test]
set -euo pipefail
mode=${1:-build}
cd "$(dirname "$0")/.."

pkgs=(cmake ninja-build g++ lld pkg-config
      libopencv-dev libavcodec-dev libavformat-dev libavutil-dev libswscale-dev libx264-dev
      libimgui-dev libstb-dev libglfw3-dev libgl-dev libeigen3-dev
      libcli11-dev nlohmann-json3-dev help2man)
if [[ $mode == test ]]; then
  pkgs+=(libgtest-dev libgmock-dev xvfb xauth libgl1-mesa-dri)
  # The sanitizer and fuzzing tree: clang 14 with its runtimes (libFuzzer, ASan, UBSan).
  pkgs+=(clang-14 libclang-rt-14-dev)
  # The install test builds a Debian package: cpack needs dpkg-shlibdeps and file.
  pkgs+=(dpkg-dev file)
  # node and npm run the independent-client interop test; a node installed outside apt is fine.
  if ! command -v node >/dev/null || ! command -v npm >/dev/null; then pkgs+=(nodejs npm); fi
fi

missing=()
for p in "${pkgs[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [[ ${#missing[@]} -gt 0 ]]; then
  echo "ardrone-gs: installing missing packages: ${missing[*]}"
  sudo=""
  if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The interop test's independent client, pinned by tests/node/package-lock.json.
if [[ $mode == test && ! -f tests/node/node_modules/ar-drone/package.json ]]; then
  echo "ardrone-gs: installing the node-ar-drone test client (npm ci)"
  (cd tests/node && npm ci --no-audit --no-fund --loglevel=error)
fi
