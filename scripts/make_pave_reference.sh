#!/usr/bin/env bash
# Regenerates tests/data/pave_reference/: the frames of node-ar-drone_pave.bin decoded by an
# H.264 decoder independent of ours (Cisco OpenH264 through GStreamer; ours is libavcodec).
# One-off: the tests only read the PNGs. Needs (Debian 12):
#   apt-get install gstreamer1.0-tools gstreamer1.0-plugins-base gstreamer1.0-plugins-bad libopenh264-7
# Usage: scripts/make_pave_reference.sh [FIXTURES_DIR]   (default ../shared/fixtures)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
fixtures=${1:-$repo/../shared/fixtures}
capture=$fixtures/ardrone/node-ar-drone_pave.bin
out=$repo/tests/data/pave_reference
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

gst-inspect-1.0 openh264dec >/dev/null  # fails loudly when the decoder is missing

# 1. PaVE -> Annex-B elementary stream, from the first IDR (frame_type 1) on. Every size is
#    read from the header as docs/protocol.md §4.1 describes; the capture has no corruption.
python3 - "$capture" "$tmp/stream.h264" <<'PY'
import struct, sys
data = open(sys.argv[1], 'rb').read()
pos, started, frames = 0, False, 0
with open(sys.argv[2], 'wb') as out:
    while pos + 12 <= len(data):
        assert data[pos:pos + 4] == b'PaVE', pos
        header_size, payload_size = struct.unpack_from('<HI', data, pos + 6)
        frame_type = data[pos + 30]
        started = started or frame_type == 1
        if started:
            out.write(data[pos + header_size:pos + header_size + payload_size])
            frames += 1
        pos += header_size + payload_size
print(f'{frames} access units from the first IDR', file=sys.stderr)
PY

# 2. Decode with OpenH264 to raw I420 (the decoder's own output, no colour conversion).
gst-launch-1.0 -q filesrc location="$tmp/stream.h264" ! h264parse ! openh264dec \
  ! video/x-raw,format=I420,width=640,height=360 ! filesink location="$tmp/frames.i420"

# 3. One 8-bit greyscale PNG per frame holding the I420 planes stacked (640x540: Y, then U, V),
#    the layout of OpenCV's COLOR_YUV2BGR_I420. Written with the Python standard library only.
rm -f "$out"/*.png
python3 - "$tmp/frames.i420" "$out" <<'PY'
import struct, sys, zlib
w, h = 640, 540
def chunk(tag, body):
    return struct.pack('>I', len(body)) + tag + body + struct.pack('>I', zlib.crc32(tag + body))
raw = open(sys.argv[1], 'rb').read()
assert len(raw) % (w * h) == 0
for i in range(len(raw) // (w * h)):
    pix = raw[i * w * h:(i + 1) * w * h]
    rows, prev = bytearray(), bytes(w)
    for y in range(h):  # per row: PNG filter None, Sub or Up, whichever is smallest
        row = pix[y * w:(y + 1) * w]
        sub = bytes((row[x] - (row[x - 1] if x else 0)) & 255 for x in range(w))
        up = bytes((row[x] - prev[x]) & 255 for x in range(w))
        cost = lambda r: sum(v if v < 128 else 256 - v for v in r)
        kind, body = min(((0, row), (1, sub), (2, up)), key=lambda kb: cost(kb[1]))
        rows.append(kind)
        rows += body
        prev = row
    png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 0, 0, 0, 0))
    png += chunk(b'IDAT', zlib.compress(bytes(rows), 9)) + chunk(b'IEND', b'')
    open(f'{sys.argv[2]}/{i:06d}.png', 'wb').write(png)
print(f'{len(raw) // (w * h)} reference frames written', file=sys.stderr)
PY
