#!/usr/bin/env bash
# An interrupted render (SIGINT, SIGTERM) dies of the signal and leaves no temporary: neither the --stats file
# being written nor an image half-written.
# Usage: bash render_interrupt.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
# shellcheck source=tests/cli/lib/interrupt.sh
source "$(dirname "$0")/lib/interrupt.sh"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
for signal in INT TERM; do
  # The stats temporary appears before frame 0; half a second more reaches the frame loop.
  SETTLE=0.5 expect_interrupted_leaves_nothing "$signal" "$dir" \
    "$ropecast" render procedural:sphere:64 --size 64x64 --frames 1000000 --stats "$dir/s.jsonl" \
    --exr "$dir/o.exr" -o "$dir/o.png" || exit 1
done
echo "render_interrupt: ok"
