#!/usr/bin/env bash
# The installed program runs from its prefix (issue 15 item 7): `cmake --install` into a temporary
# prefix, then --help, --version (which names the assets folder it uses), a flight generated from
# the installed scenes and replayed headless, the ARDRONE_GS_ASSETS override, and the Debian
# package's contents and dependencies.
# Usage: install_test.sh BUILD_DIR CMAKE CPACK
set -euo pipefail
build=$1 cmake=$2 cpack=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

prefix=$tmp/prefix
"$cmake" --install "$build" --prefix "$prefix" >/dev/null
for f in bin/ardrone-gs share/ardrone-gs/calibration/ardrone2_front.json \
         share/ardrone-gs/calibration/ardrone2_bottom.json share/ardrone-gs/scenes/warehouse.json \
         share/applications/ardrone-gs.desktop share/icons/hicolor/scalable/apps/ardrone-gs.svg \
         share/man/man1/ardrone-gs.1.gz; do
  [[ -f $prefix/$f ]] || fail "not installed: $f"
done
[[ ! -e $prefix/share/ardrone-gs/screenshots ]] || fail "the README's screenshots were installed"
[[ ! -e $prefix/share/ardrone-gs/desktop ]] || fail "the desktop files were installed as assets"
# Each output is captured whole before it is searched: `producer | grep -q` under pipefail fails
# when grep stops at an early match and the producer dies of SIGPIPE (it did in CI, stop 34).
man=$(zcat "$prefix/share/man/man1/ardrone-gs.1.gz")
grep -q '^\.SS "ardrone-gs replay"' <<<"$man" || fail "the man page lacks the replay subcommand"
grep -q '^\.B ARDRONE_GS_ASSETS' <<<"$man" || fail "the man page lacks the environment section"

exe=$prefix/bin/ardrone-gs
unset ARDRONE_GS_ASSETS
help=$("$exe" --help)
grep -q "replay" <<<"$help" || fail "--help does not list replay"
version=$("$exe" --version)
expected="assets: $(cd "$prefix/share/ardrone-gs" && pwd -P) (installed)"
grep -qxF "$expected" <<<"$version" || fail "--version said '$version', expected '$expected'"

# A flight rendered from the installed scenes, replayed headless from the installed program.
"$exe" generate --scene thesis_pillar_center --max-seconds 2 --out "$tmp/flight" -q >/dev/null
"$exe" replay "$tmp/flight" --out "$tmp/replay" -q
grep -q '"frames"' "$tmp/replay/summary.json" || fail "replay wrote no summary"
[[ $(wc -l <"$tmp/replay/decisions.csv") -gt 10 ]] || fail "replay decided on too few frames"

# The installed assets are the ones read: a scene removed from them is not found, although the
# source tree still has it.
rm "$prefix/share/ardrone-gs/scenes/thesis_pillar_left.json"
if "$exe" generate --scene thesis_pillar_left --max-seconds 1 --out "$tmp/left" -q 2>"$tmp/err"; then
  fail "generate found a scene that is not in the installed assets"
fi

# ARDRONE_GS_ASSETS overrides; naming no folder is an error that says so (--help and --version
# still answer, so the folder in use can be looked at).
mkdir -p "$tmp/other"
version=$(ARDRONE_GS_ASSETS=$tmp/other "$exe" --version)
grep -qxF "assets: $tmp/other (environment)" <<<"$version" || fail "ARDRONE_GS_ASSETS was not used"
if ARDRONE_GS_ASSETS=$tmp/missing "$exe" replay "$tmp/flight" --out "$tmp/replay2" -q 2>"$tmp/err"; then
  fail "a missing ARDRONE_GS_ASSETS folder was accepted"
fi
grep -q "ARDRONE_GS_ASSETS=$tmp/missing is not a folder" "$tmp/err" || fail "unclear error: $(cat "$tmp/err")"

# The Debian package: the same files under /usr, and its dependencies are Debian's libraries.
(cd "$tmp" && "$cpack" -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/deb" >/dev/null)
deb=$(ls "$tmp"/deb/ardrone-gs_*.deb)
contents=$(dpkg-deb -c "$deb")
for f in ./usr/bin/ardrone-gs ./usr/share/ardrone-gs/calibration/ardrone2_front.json \
         ./usr/share/applications/ardrone-gs.desktop ./usr/share/man/man1/ardrone-gs.1.gz; do
  grep -qF " $f" <<<"$contents" || fail "the package lacks $f"
done
depends=$(dpkg-deb -f "$deb" Depends)
for lib in libavcodec libopencv-core libglfw3 libc6; do
  grep -q "$lib" <<<"$depends" || fail "the package does not depend on $lib: $depends"
done
echo "installed, replayed and packaged from $prefix"
