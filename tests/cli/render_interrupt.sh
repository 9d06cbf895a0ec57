#!/usr/bin/env bash
# An interrupted render (SIGINT, SIGTERM, SIGQUIT) dies of the signal and leaves no temporary: neither the
# --stats file being written nor an image half-written. An image that cannot be written whole (past the file
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
for out in "-o $dir/o.png" "--exr $dir/o.exr -o $dir/o.png"; do
  # shellcheck disable=SC2086  # $out is an option and its value
  err=$( (ulimit -f 8 && "$ropecast" render procedural:noise:32 --size 256x256 $out) 2>&1)
  rc=$?
  [ "$rc" -ne 0 ] || { echo "FAIL: $out past the file size limit exited 0"; exit 1; }
  grep -q "too large" <<< "$err" || { echo "FAIL: $out past the file size limit: $err"; exit 1; }
  [ -z "$(ls "$dir")" ] || { echo "FAIL: $out past the file size limit left: $(ls "$dir")"; exit 1; }
  echo "ok   $out past the file size limit: exit $rc, nothing left"
done
echo "render_interrupt: ok"
