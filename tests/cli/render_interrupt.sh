#!/usr/bin/env bash
# An interrupted render (SIGINT, SIGTERM, SIGQUIT) dies of the signal and leaves no temporary: neither the
# --stats file being written nor an image half-written, nor --every's frames; nor does a render that fails
# after frames were drawn. An image that cannot be written whole (past the file
# size limit, as on a full disk) is an error that names it, and nothing is left either.
# Usage: bash render_interrupt.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
# shellcheck source=tests/cli/lib/interrupt.sh
source "$(dirname "$0")/lib/interrupt.sh"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
ulimit -c 0  # SIGQUIT would dump core
for signal in INT TERM QUIT; do
  # The stats temporary appears before frame 0; half a second more reaches the frame loop.
  SETTLE=0.5 expect_interrupted_leaves_nothing "$signal" "$dir" \
    "$ropecast" render procedural:sphere:64 --size 64x64 --frames 1000000 --stats "$dir/s.jsonl" \
    --exr "$dir/o.exr" -o "$dir/o.png" || exit 1
done
# --every's frames are outputs too: an interrupted progressive render leaves none of them.
SETTLE=1.5 expect_interrupted_leaves_nothing TERM "$dir" \
  "$ropecast" render procedural:sphere:64 --size 64x64 --frames 1000000 --every 1 -o "$dir/o.png" || exit 1
# Nor does one that fails after frames were drawn: a store whose bricks below depth 1 are damaged fails when
# the loader reaches them, after frame 0.
store_dir=$(mktemp -d)
trap 'rm -rf "$dir" "$store_dir"' EXIT
"$ropecast" convert procedural:sphere:64 --brick 8 -o "$store_dir/s.rcast" -q || exit 1
python3 - "$store_dir/s.rcast" <<'PY'
import struct, sys
path = sys.argv[1]
data = bytearray(open(path, 'rb').read())
table, count = struct.unpack_from('<QQ', data, 32)  # nodeTableOffset, nodeCount (docs/FORMAT.md)
entries = [struct.unpack_from('<QI', data, table + 24 * i) for i in range(count)]  # payloadOffset, payloadBytes
for offset, size in entries[9:]:  # in node order: the root and depth 1 stay whole
    if size:
        data[offset + size // 2] ^= 0xFF
open(path, 'wb').write(data)
PY
err=$("$ropecast" render "$store_dir/s.rcast" --converge --every 1 --size 64x64 -o "$dir/o.png" -q 2>&1)
rc=$?
[ "$rc" -ge 1 ] && [ "$rc" -le 127 ] || { echo "FAIL: --every from a damaged store: exit $rc"; exit 1; }
grep -q "damaged brick" <<< "$err" || { echo "FAIL: --every from a damaged store: $err"; exit 1; }
[ -z "$(ls -A "$dir")" ] || { echo "FAIL: --every from a damaged store left: $(ls -A "$dir")"; exit 1; }
echo "ok   --every from a damaged store: exit $rc, no frame left"
for out in "-o $dir/o.png" "--exr $dir/o.exr -o $dir/o.png"; do
  # shellcheck disable=SC2086  # $out is an option and its value
  err=$( (ulimit -f 8 && "$ropecast" render procedural:noise:32 --size 256x256 $out) 2>&1)
  rc=$?
  [ "$rc" -ne 0 ] || { echo "FAIL: $out past the file size limit exited 0"; exit 1; }
  grep -q "too large" <<< "$err" || { echo "FAIL: $out past the file size limit: $err"; exit 1; }
  [ -z "$(ls -A "$dir")" ] || { echo "FAIL: $out past the file size limit left: $(ls -A "$dir")"; exit 1; }
  echo "ok   $out past the file size limit: exit $rc, nothing left"
done
echo "render_interrupt: ok"
