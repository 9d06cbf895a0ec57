#!/usr/bin/env bash
# Opening and converting multi-page TIFFs of many pages (docs/BENCHMARKS.md, "Multi-page TIFFs"): stacks of
# PAGES pages of 64 x 64 uint16 (little-endian, each page's data before its directory, as ImageJ writes them),
# uncompressed or Deflate-compressed (COMPRESSION), written by a script; per page count, the wall seconds of
# `ropecast info` and `ropecast convert` with BUILD_DIR's ropecast, and with BEFORE_DIR's beside it when given
# (the same files, in turn, from the page cache).
# Usage: bench/tiff_pages.sh [BUILD_DIR] [BEFORE_DIR]   (default build/perf; BEFORE_DIR: a tools folder or a
# build, optional)
# Environment: PAGES ("500 1000 2000"), COMPRESSION (none or deflate; none), SCRATCH (a temporary directory).
set -euo pipefail
cd "$(dirname "$0")/.."
tool() { if [ -x "$1/tools/ropecast" ]; then realpath "$1/tools/ropecast"; else realpath "$1/ropecast"; fi; }
builds=("$(tool "${1:-build/perf}")")
[ -n "${2:-}" ] && builds+=("$(tool "$2")")
scratch=${SCRATCH:-$(mktemp -d /tmp/ropecast-tiff-pages-XXXXXX)}
mkdir -p "$scratch"
trap 'rm -rf "$scratch"' EXIT

write_stack() {  # PATH PAGES COMPRESSION
  python3 - "$1" "$2" "$3" <<'PY'
import struct, sys, zlib
path, pages, deflate = sys.argv[1], int(sys.argv[2]), sys.argv[3] == "deflate"
w = h = 64
out = bytearray(b"II*\0\0\0\0\0")
link = 4
for p in range(pages):
    data_at = len(out)
    data = struct.pack("<%dH" % (w * h), *[(x * 7 + y * 13 + p * 29) % 4096 for y in range(h) for x in range(w)])
    if deflate:
        data = zlib.compress(data)
    out += data
    if len(out) % 2:
        out += b"\0"
    directory = len(out)
    struct.pack_into("<I", out, link, directory)
    entries = [(256, 4, 1, w), (257, 4, 1, h), (258, 3, 1, 16), (259, 3, 1, 8 if deflate else 1), (262, 3, 1, 1),
               (273, 4, 1, data_at), (277, 3, 1, 1), (278, 4, 1, h), (279, 4, 1, len(data))]
    out += struct.pack("<H", len(entries))
    for tag, kind, count, value in entries:
        out += struct.pack("<HHI", tag, kind, count) + (struct.pack("<HH", value, 0) if kind == 3 else struct.pack("<I", value))
    link = len(out)
    out += b"\0\0\0\0"
open(path, "wb").write(out)
PY
}

seconds() {  # COMMAND...: wall seconds
  local start end
  start=$(date +%s%N)
  "$@" > /dev/null
  end=$(date +%s%N)
  awk -v ns=$((end - start)) 'BEGIN { print ns / 1e9 }'
}

compression=${COMPRESSION:-none}
case $compression in none | deflate) ;; *) echo "COMPRESSION: none or deflate, not $compression" >&2; exit 2 ;; esac
echo "pages of 64 x 64 uint16, compression: $compression"
printf '%-7s %-60s %9s %11s\n' pages ropecast "info s" "convert s"
for pages in ${PAGES:-500 1000 2000}; do
  write_stack "$scratch/stack_$pages.tif" "$pages" "$compression"
  for ropecast in "${builds[@]}"; do
    info=$(seconds "$ropecast" info "$scratch/stack_$pages.tif")
    rm -f "$scratch/out.rcast"
    convert=$(seconds "$ropecast" convert "$scratch/stack_$pages.tif" -o "$scratch/out.rcast" -q)
    printf '%-7s %-60s %9.2f %11.2f\n' "$pages" "$ropecast" "$info" "$convert"
  done
done
