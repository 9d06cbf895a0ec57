#!/usr/bin/env bash
# The prepared GPU bench (docs/BENCHMARKS.md "On a lent GPU"): on a lent NVIDIA device machine, in one call,
# what only a GPU can measure, most wanted first, each part bounded by PART_S seconds so that a slow part
# leaves time for the others:
#   1. the GL index tests: the GLSL rope traversal (compute shader) against the CPU reference, on the GPU;
#      then all the GL render tests (part "visgl"): the ray caster against its CPU mirror, the backends against
#      each other, the occlusion queries (each node's count of visible samples against a count from the depth
#      image), the rays' requests and usage against their CPU twin, convergence with both on;
#   2. bench/modes.sh: the single pass against the multi-pass renderer, iso and DVR, 512x512 and 1024x1024
#      (the goal: >= 2x on a GPU);
#   3. bench/converge_vs_sync.sh: progressive loading against a synchronous render of the CT-like store, with
#      occlusion and feedback on and off (the goal: <= 1.3x; generating and converting the store included),
#      three repetitions, since the first on a fresh machine can be slower with the same work (most likely
#      the driver compiling shaders the synchronous render did not use);
#   4. bench/visibility.sh, iso from the page cache and a slow disk: what occlusion queries and ray feedback
#      cost a GPU frame (frame ms, occlusion_draw_ms in the stats) and how fast they converge;
#   5. bench/render_vs_brute.sh at 512x512, then at 2048x2048 (part "brute2k": 512x512 rays are about as many
#      threads as a GPU keeps in flight at once, so there a frame lasts as long as its slowest rays; 16 times
#      the rays measure throughput instead);
#   6. bench/converge_vs_sync.sh again with two I/O threads (`--io-threads 2`, the count before the default
#      became one per core): what the device's cores add to loading (part "iothreads", the store of part 3).
#
#   run(command="bench/device_bench.sh", carry=[".gl", ".devlibs", "build/vg/tools/ropecast",
#       "build/vg/tests/index_gltests", "build/vg/tests/render_gltests", "build/vg/ct_gen"], timeout_s=590)
#
# scripts/device_prepare makes what is carried. Each part's output is in $OUT/PART.txt and its stats under
# $OUT/PART/ (stores and images stay on the device); the parts' tables are printed last, with each part's exit
# status and seconds. Env: PART_S (110), PARTS ("index visgl modes converge visibility brute brute2k
# iothreads"). Off the device it runs the same against whatever GL this machine has (slowly on llvmpipe: narrow
# it with PARTS and PART_S).
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
OUT=${OUT:-$(mktemp -d /tmp/device_bench.XXXXXX)}
mkdir -p "$OUT"
PART_S=${PART_S:-110}
PARTS=${PARTS:-"index visgl modes converge visibility brute brute2k iothreads"}
source bench/lib/device.sh
device_gl_setup
build=$(device_ropecast_build) || exit 1
export ROPECAST_SHADER_DIR=${ROPECAST_SHADER_DIR:-$PWD} # the GL index tests read their test shader from the tree
[ -x build/vg/ct_gen ] && export CT_GEN=$PWD/build/vg/ct_gen

# part NAME COMMAND...: runs COMMAND for at most PART_S seconds into $OUT/NAME.txt.
summary=()
part() {
  local name=$1 t0 rc
  shift
  echo "device_bench: $name" >&2
  t0=$(date +%s)
  timeout --kill-after=5 "$PART_S" "$@" >"$OUT/$name.txt" 2>&1
  rc=$?
  summary+=("$name: exit $rc$([ "$rc" = 124 ] && echo ' (timed out)') in $(($(date +%s) - t0)) s")
}

for p in $PARTS; do
  case $p in
    index)
      if [ -x build/vg/tests/index_gltests ]; then
        part index env LD_LIBRARY_PATH="$DEVICE_LIBS" build/vg/tests/index_gltests
      fi
      ;;
    visgl)
      # Not the readback test that reads the sources by the path they had where the tests were built.
      if [ -x build/vg/tests/render_gltests ]; then
        part visgl env LD_LIBRARY_PATH="$DEVICE_LIBS" build/vg/tests/render_gltests \
          --gtest_filter='-Feedback.ReadbackNeverWaits*'
      fi
      ;;
    modes) part modes env PLOT=0 REPS=2 WORK="$OUT/modes" bench/modes.sh "$build" ;;
    converge) part converge env EXT=ppm REPS=3 WORK="$OUT/converge" bench/converge_vs_sync.sh "$build" ;;
    visibility)
      part visibility env EXT=ppm MODES=iso SKIP_PATH=1 STEADY=4 MAX_FRAMES=4000 WORK="$OUT/visibility" bench/visibility.sh "$build"
      ;;
    brute)
      part brute env EXT=ppm IMAGE="${IMAGE:-512x512}" FRAMES=20 STILL=12 ROUNDS=3 WORK="$OUT/brute" \
        bench/render_vs_brute.sh "$build"
      ;;
    brute2k)
      part brute2k env EXT=ppm IMAGE=2048x2048 FRAMES=20 STILL=12 ROUNDS=3 WORK="$OUT/brute2k" \
        bench/render_vs_brute.sh "$build"
      ;;
    iothreads)
      mkdir -p "$OUT/iothreads"
      ln -sf "$OUT"/converge/ct_*.rcast "$OUT/iothreads/" 2>/dev/null # part 3's store, if it made one
      part iothreads env EXT=ppm REPS=3 RENDER_ARGS="--io-threads 2" WORK="$OUT/iothreads" \
        bench/converge_vs_sync.sh "$build"
      ;;
    *) summary+=("$p: unknown part (index, visgl, modes, converge, visibility, brute, brute2k, iothreads)") ;;
  esac
done
# What comes back: stats and tables, not stores, raw volumes or images.
find "$OUT" \( -name '*.rcast' -o -name '*.raw' -o -name '*.ppm' -o -name 'gen' \) -delete 2>/dev/null
for p in $PARTS; do
  [ -f "$OUT/$p.txt" ] || continue
  echo "=== $p"
  case $p in
    index | visgl) grep -E "^GL:|compared|PASSED|FAILED" "$OUT/$p.txt" | tail -8 ;;
    *) tail -40 "$OUT/$p.txt" ;;
  esac
done
printf '%s\n' "${summary[@]}"
