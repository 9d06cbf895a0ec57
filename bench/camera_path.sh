#!/usr/bin/env bash
# Asynchronous loader along a key-framed fly-by (docs/BENCHMARKS.md).
# Cold cache, bench/flyby_path.json (fast move, slow rotation, acceleration) over procedural:noise:1200 converted
# to a store (1200^3 uint8 = 1.61 GiB raw; kept in WORKDIR and reused), one run per configuration, side by side:
#   off      no upload budget
#   bytes    --upload-budget BUDGET
#   time     --upload-time-budget MS
#   pbo      --upload-budget BUDGET --upload-pbo
#   delay    --upload-budget BUDGET --io-delay-ms 20   (asynchrony: compared with "bytes")
#   paced    --upload-budget BUDGET --target-frame-ms TARGET_MS (the sample step grows while frames are slow)
# Prints per configuration: median / max frame_ms and their ratio (all frames and without frame 0; shaders
# compile before it), the median of frame_ms - raycast_ms (the loader's share), upload_ms, bricks uploaded,
# requests pending, the first frame from which the working set stayed converged, and the largest sample step
# (paced); then the frames to converge
# on the path's last camera from a cold cache, with and without --io-delay-ms 20.
# Usage: bench/camera_path.sh ROPECAST [WORKDIR] [SIZE] [FRAMES]
#   defaults: WORKDIR=/tmp/ropecast_bench SIZE=256x192 FRAMES=120; env BUDGET (default 2M), TIME_MS (default 1),
#   TARGET_MS (default 50),
#   REPS (default 2: the five runs are repeated, interleaved)
set -euo pipefail
ropecast="$1"
work="${2:-/tmp/ropecast_bench}"
size="${3:-256x192}"
frames="${4:-120}"
budget="${BUDGET:-2M}"
time_ms="${TIME_MS:-1}"
target_ms="${TARGET_MS:-50}"
here="$(cd "$(dirname "$0")" && pwd)"
path="$here/flyby_path.json"
export EGL_PLATFORM="${EGL_PLATFORM:-surfaceless}"
mkdir -p "$work"
store="$work/noise1200.rcast"
[ -f "$store" ] || "$ropecast" convert procedural:noise:1200 -o "$store" --quiet

reps="${REPS:-2}"
configs="off bytes time pbo delay paced"
args() {
  case "$1" in
    off) ;;
    bytes) echo --upload-budget "$budget" ;;
    time) echo --upload-time-budget "$time_ms" ;;
    pbo) echo --upload-budget "$budget" --upload-pbo ;;
    delay) echo --upload-budget "$budget" --io-delay-ms 20 ;;
    paced) echo --upload-budget "$budget" --target-frame-ms "$target_ms" ;;
  esac
}
# Interleaved repetitions: on a shared machine the load changes from run to run, so configurations are compared
# within one repetition (ratios), and every repetition is printed.
for rep in $(seq 1 "$reps"); do
  for c in $configs; do
    # shellcheck disable=SC2046
    "$ropecast" render "$store" --mode iso --size "$size" --path "$path" --frames "$frames" \
      --stats "$work/path_${c}_$rep.jsonl" -o "$work/path_$c.png" $(args "$c") >/dev/null
  done
done

# Frames to converge from a cold cache on the path's last camera (a close-up), with and without the delay.
for d in 0 20; do
  "$ropecast" render "$store" --mode iso --size "$size" --orbit 260,30,0.7 --converge --max-frames 5000 \
    --upload-budget "$budget" --io-delay-ms "$d" --stats "$work/converge_delay$d.jsonl" -o "$work/converge_$d.png" \
    >/dev/null
done

python3 - "$work" "$budget" "$time_ms" "$reps" "$configs" "$size" "$frames" "$target_ms" <<'PY'
import json, statistics, sys
work, budget, time_ms, reps, configs, size, frames, target_ms = sys.argv[1:9]
reps, configs = int(reps), configs.split()
def load(name, rep):
    return [json.loads(l) for l in open(f"{work}/path_{name}_{rep}.jsonl")]
def settled(rows):  # first frame from which every later frame is converged (None if never)
    first = None
    for r in rows:
        first = (r["frame"] if first is None else first) if r["converged"] else None
    return first
print(f"store procedural:noise:1200 (1.61 GiB raw), iso, {size}, {frames} frames of bench/flyby_path.json, "
      f"cold cache; bytes/pbo/delay/paced: --upload-budget {budget}; time: --upload-time-budget {time_ms}; "
      f"paced: --target-frame-ms {target_ms}")
print("frame_ms: median, max, max/median (all frames; frames > 0: without the first); rc.mx/md: "
      "max/median of raycast_ms alone (frames > 0); step.max: the largest step_voxels (0.5 = --step); "
      "loader = frame_ms - raycast_ms (refine + upload + index + "
      "overhead), median and max over frames > 0")
hdr = ["rep", "config", "med", "max", "max/med", "max/med>0", "rc.mx/md", "ldr.med", "ldr.max", "upl.med",
       "upl.max", "bricks", "br.max", "pend.max", "settled", "step.max"]
print(("{:<3} {:<6}" + " {:>8}" * 14).format(*hdr))
for rep in range(1, reps + 1):
    med = {}
    for name in configs:
        rows = load(name, rep)
        f = [r["frame_ms"] for r in rows]
        m = statistics.median(f)
        med[name] = m
        # The ray cast with the occlusion queries drawn between its tiles (timed apart since they were).
        rc = [r["raycast_ms"] + r.get("occlusion_draw_ms", 0.0) for r in rows[1:]]
        ldr = [r["frame_ms"] - x for r, x in zip(rows[1:], rc)]
        up = [r["upload_ms"] for r in rows]
        br = [r["bricks_uploaded"] for r in rows]
        steps = [r.get("step_voxels", 0.0) for r in rows]
        print(("{:<3} {:<6}" + " {:8.1f}" * 2 + " {:8.2f}" * 3 + " {:8.2f}" * 4 + " {:8d}" * 3 + " {:>8}" +
               " {:8.2f}").format(
            rep, name, m, max(f), max(f) / m, max(f[1:]) / m, max(rc) / statistics.median(rc),
            statistics.median(ldr), max(ldr),
            statistics.median(up), max(up), sum(br), max(br), max(r["requests_pending"] for r in rows),
            str(settled(rows)), max(steps)))
    pbo_sum = sum(r["upload_ms"] for r in load("pbo", rep))
    direct_sum = sum(r["upload_ms"] for r in load("bytes", rep))
    print(f"rep {rep}: asynchrony: median frame_ms with --io-delay-ms 20 / without = "
          f"{med['delay'] / med['bytes']:.3f}; uploads through a PBO / direct: total upload_ms "
          f"{pbo_sum:.1f} / {direct_sum:.1f} = {pbo_sum / direct_sum:.2f}")
for d in (0, 20):
    rows = [json.loads(l) for l in open(f"{work}/converge_delay{d}.jsonl")]
    f = [r["frame_ms"] for r in rows]
    print(f"converge on the last camera (orbit 260,30,0.7), --io-delay-ms {d}: converged={rows[-1]['converged']} "
          f"after {len(rows)} frames, median frame_ms {statistics.median(f):.1f}, "
          f"bricks uploaded {sum(r['bricks_uploaded'] for r in rows)}")
PY
