#!/usr/bin/env bash
# Occlusion queries on and off, side by side (docs/BENCHMARKS.md; Gobbetti et al. 2008, Sect. 6). A store with
# depth complexity (procedural:noise:SIZE converted into WORK once and reused: blobs behind blobs), at IMAGE,
# from a cold cache to convergence (`render --converge --frames FRAMES`: at least FRAMES frames, so a FRAMES
# beyond the convergence frame gives converged frames to time), an opaque isosurface and a semi-transparent DVR, each with --occlusion on and off, interleaved.
# Prints per mode and setting: the working set at convergence (bricks of the refined tree), bricks resident in
# the pool, bytes read and uploaded in total, frames and seconds to converge, the converged frame time, the
# query latency; then the ratios on / off and the PSNR of on against off.
# Usage: bench/occlusion.sh [BUILD_DIR]   env SIZE (512), IMAGE (1024x1024), FRAMES (1), MODES ("iso dvr"),
#   WORK (a fresh folder), GPU (--gpu-budget, 1G), CPU (--cpu-cache, 1G)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
source "$here/lib/common.sh"
SIZE=${SIZE:-512}
IMAGE=${IMAGE:-1024x1024}
bench_setup occlusion "${1:-build/perf}"
frames=${FRAMES:-1}
modes=${MODES:-iso dvr}
store="$WORK/noise$SIZE.rcast"
[ -f "$store" ] || "$ROPECAST" convert "procedural:noise:$SIZE" -o "$store" --quiet
write_ramp_tf "$WORK/ramp.json" 100

for mode in $modes; do
  case $mode in
    iso) args=(--mode iso) ;;
    dvr) args=(--mode dvr --tf "$WORK/ramp.json") ;;
  esac
  for occlusion in off on; do
    echo "occlusion.sh: $mode, --occlusion $occlusion" >&2
    "$ROPECAST" render "$store" "${args[@]}" --size "$IMAGE" --orbit 30,20,1.6 --converge --frames "$frames" \
      --gpu-budget "${GPU:-1G}" --cpu-cache "${CPU:-1G}" --occlusion "$occlusion" \
      --stats "$WORK/$mode-$occlusion.jsonl" -o "$WORK/$mode-$occlusion.png"
  done
  "$ROPECAST" compare "$WORK/$mode-on.png" "$WORK/$mode-off.png" >"$WORK/$mode-psnr.json"
done

python3 - "$WORK" "$modes" "$IMAGE" "$SIZE" <<'PY'
import json, statistics, sys
work, modes, image, size = sys.argv[1], sys.argv[2].split(), sys.argv[3], sys.argv[4]
MiB = 1 << 20
print(f"procedural:noise:{size} store, {image}, cold cache to convergence")
def summary(rows):
    first = next((i for i, r in enumerate(rows) if r["converged"]), len(rows) - 1)
    c = rows[first]
    after = [r["frame_ms"] for r in rows[first + 1:]] or [c["frame_ms"]]
    return {"working set": c["working_set_bricks"], "resident": c["bricks_resident"],
            "read MiB": sum(r["bytes_read"] for r in rows[:first + 1]) / MiB,
            "uploaded MiB": sum(r["bytes_uploaded"] for r in rows[:first + 1]) / MiB,
            "frames": first + 1, "seconds": sum(r["frame_ms"] for r in rows[:first + 1]) / 1000,
            "frame ms": statistics.median(after), "latency": c["occlusion_latency_frames"],
            "converged": rows[first]["converged"]}
keys = ["working set", "resident", "read MiB", "uploaded MiB", "frames", "seconds", "frame ms", "latency"]
for mode in modes:
    s = {o: summary([json.loads(l) for l in open(f"{work}/{mode}-{o}.jsonl")]) for o in ("off", "on")}
    psnr = float(json.load(open(f"{work}/{mode}-psnr.json"))["psnr_db"])
    print(f"\n{mode}: " + " ".join(f"{k:>12}" for k in keys))
    for o in ("off", "on"):
        print(f"  {o:<4} " + " ".join(f"{s[o][k]:12.1f}" for k in keys) +
              ("" if s[o]["converged"] else "  (not converged)"))
    ratio = lambda k: s["on"][k] / s["off"][k] if s["off"][k] else float("nan")
    print(f"  on/off working set {ratio('working set'):.2f} ({100 * (1 - ratio('working set')):.0f} % smaller), "
          f"read {ratio('read MiB'):.2f}, uploaded {ratio('uploaded MiB'):.2f}, "
          f"seconds {ratio('seconds'):.2f}, converged frame time {ratio('frame ms'):.2f}; "
          f"image on vs off {psnr:.1f} dB")
PY
