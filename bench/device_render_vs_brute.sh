#!/usr/bin/env bash
# bench/render_vs_brute.sh on a lent NVIDIA device machine, in one call: the GL loader packages carried in .gl
# unpacked (nothing can be installed there otherwise), NVIDIA's EGL vendor file named, and the carried
# OpenImageIO-free ropecast run with the carried libraries through a wrapper (scripts/device_prepare makes all
# of them). First, if carried, the GL index tests (the GLSL rope traversal in a compute shader against the CPU
# reference, on the GPU); then the benchmark. Results and stats under $OUT (the device tool fetches them); the
# table is printed last.
#
#   run(command="bench/device_render_vs_brute.sh", carry=[".gl", ".devlibs", "build/vg/tools/ropecast",
#       "build/vg/tests/index_gltests"], timeout_s=540)
#
# Environment as bench/render_vs_brute.sh (defaults here: IMAGE 512x512, FRAMES 20, STILL 12, ROUNDS 3).
# Off the device (no $OUT, no NVIDIA driver) it runs the same against whatever GL this machine has.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-$(mktemp -d /tmp/device_render_vs_brute.XXXXXX)}
source bench/lib/device.sh
device_gl_setup

export ROPECAST_SHADER_DIR=$PWD  # the GL index test reads its test shader from the tree (ropecast embeds its own)
if [ -x build/vg/tests/index_gltests ]; then
  LD_LIBRARY_PATH=$DEVICE_LIBS build/vg/tests/index_gltests 2>&1 |
    tee "$OUT/index_gltests.txt" | grep -E "^GL:|compared|PASSED|FAILED" || true
fi
wrapper=$(device_ropecast_build)

EXT=ppm IMAGE=${IMAGE:-512x512} FRAMES=${FRAMES:-20} STILL=${STILL:-12} ROUNDS=${ROUNDS:-3} WORK="$OUT/work" \
  bench/render_vs_brute.sh "$wrapper" 2>&1 | tee "$OUT/render_vs_brute.txt"
rm -f "$OUT"/work/*.rcast "$OUT"/work/*.ppm  # stores and images stay on the device; the stats come back
