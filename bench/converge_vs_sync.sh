#!/usr/bin/env bash
# Progressive loading against synchronous loading (docs/BENCHMARKS.md): the same view of the same store,
# rendered once with everything loaded first (`ropecast render`, one frame) and once with frames drawn while
# the asynchronous loader streams (`ropecast render --converge`), from a cold cache each time. Also
# --converge with --upload-budget, whose per-frame bound must hold (bytes_uploaded in --stats).
# The store: a CT-like int16 volume (a smooth field over a ball plus noise, the converter benchmark's
# generator), converted into WORK once and reused.
# Runs per repetition: sync (one synchronous frame), converge (--converge, the defaults: occlusion queries and
# ray feedback on), loader (--converge with them off: the streaming loader alone), budget (--converge
# --upload-budget). Once: a --converge run writing every frame, to find the first frame from which the image
# stays within 40 dB of the converged one (the rest of the frames wait for answers confirming the cut) and the
# first frame at least as close to full detail as the synchronous image, and a synchronous render with budgets
# that hold everything (full detail), against which the images are compared.
# Per repetition also sync and converge of the same cut with 16 times fewer pixels (IMAGE / 4 on a side,
# --voxels-per-pixel 4, which asks for the same bricks; frames several times cheaper): what the frames' cost on this machine adds.
# Prints per run: wall seconds, processor seconds (user and system), frames, bricks uploaded, MiB read, the
# share of the drawn frames' pixels cast (--converge casts only what changed on a still view); the
# ratios to synchronous (goal <= 1.3), the seconds to the final image and to the synchronous image's quality,
# the processor seconds against synchronous (on few cores the frames and the reads share them), and the
# largest bytes_uploaded of a frame against --upload-budget.
# Usage: bench/converge_vs_sync.sh [BUILD_DIR]   (default build/perf)
# env: DIMS (default 1024x1024x864, 1.7 GiB raw), ORBIT (30,20,1.6: a view that needs 2862 bricks of the
#      default store), IMAGE (512x512), GPU (256M), CPU (256M), UPLOAD (--upload-budget, 8M), REPS (2),
#      WORK (a folder kept between runs), RENDER_ARGS (more render options), EXT (png, or ppm for a build
#      without OpenImageIO: then the images are not compared).
# The page cache is dropped before each render when the script runs as root ("cold"), else it is warm.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
. "$here/lib/common.sh"
bench_setup converge_vs_sync "${1:-build/perf}"
DIMS=${DIMS:-1024x1024x864}
GPU=${GPU:-256M}
CPU=${CPU:-256M}
UPLOAD=${UPLOAD:-8M}
ORBIT=${ORBIT:-30,20,1.6}
REPS=${REPS:-2}
EXT=${EXT:-png}
store=$(ct_store "$DIMS")

cold() {
  if [ "$(id -u)" = 0 ] && sync && echo 3 >/proc/sys/vm/drop_caches 2>/dev/null; then echo cold; else echo warm; fi
}

# run NAME ARGS...: one render with --stats, its wall time in WORK/NAME.s; RUN_SIZE replaces IMAGE
run() {
  local name=$1
  shift
  local cache
  cache=$(cold)
  local t0 t1 TIMEFORMAT='%U %S'
  t0=$(date +%s.%N)
  # bash's `time`: the render's processor seconds, user and system, into WORK/NAME.cpu
  { time "$ROPECAST" render "$store" --mode iso --orbit "$ORBIT" --size "${RUN_SIZE:-$IMAGE}" --gpu-budget "$GPU" \
    --cpu-cache "$CPU" ${RENDER_ARGS:-} --stats "$WORK/$name.jsonl" -o "$WORK/$name.$EXT" "$@" >/dev/null \
    2>"$WORK/$name.err"; } 2>"$WORK/$name.cpu" ||
    { cat "$WORK/$name.err" >&2; return 1; }  # the pool's warning (it holds this view and little more) stays here
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f\n", b - a }' >"$WORK/$name.s"
  echo "$cache" >"$WORK/$name.cache"
}

IFS=x read -r width height <<<"$IMAGE"
small="$((width / 4))x$((height / 4))"
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); store $store ($(du -m "$store" | cut -f1) MiB)"
for rep in $(seq 1 "$REPS"); do
  run "sync$rep"
  run "converge$rep" --converge
  run "loader$rep" --converge --occlusion off --feedback off
  run "budget$rep" --converge --upload-budget "$UPLOAD"
  RUN_SIZE=$small run "sync_small$rep" --voxels-per-pixel 4
  RUN_SIZE=$small run "converge_small$rep" --converge --voxels-per-pixel 4
done
rm -rf "$WORK/frames" && mkdir -p "$WORK/frames"
run frames/every --converge --every 1
GPU=2G CPU=2G run full

python3 - "$WORK" "$REPS" "$UPLOAD" "$ROPECAST" "$EXT" "$small" "$IMAGE" <<'PY'
import glob, json, os, subprocess, sys
work, reps, upload, ropecast, ext, small, image = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6], sys.argv[7]
def psnr(a, b):
    if ext != "png":
        return float("nan")  # a build without OpenImageIO cannot read images back
    out = subprocess.run([ropecast, "compare", a, b], capture_output=True, text=True, check=True).stdout
    return float(json.loads(out)["psnr_db"])
# The first frame from which every frame is within 40 dB of the converged image.
frames = sorted(glob.glob(f"{work}/frames/every_*.{ext}"))  # every frame; the last is every.EXT too
final_frame = len(frames)
while final_frame > 0 and psnr(frames[final_frame - 1], f"{work}/frames/every.{ext}") >= 40.0:
    final_frame -= 1
# The first frame at least as close to full detail as the synchronous image (the defaults go on to a better one).
sync_quality = psnr(f"{work}/sync1.{ext}", f"{work}/full.{ext}")
quality_frame = next((i for i, f in enumerate(frames) if psnr(f, f"{work}/full.{ext}") >= sync_quality), None)
units = {"K": 1 << 10, "M": 1 << 20, "G": 1 << 30}
budget = int(float(upload[:-1]) * units[upload[-1]]) if upload[-1] in units else int(upload)
MiB = 1 << 20
def load(name):
    rows = [json.loads(l) for l in open(f"{work}/{name}.jsonl")]
    w, h = map(int, (small if name.startswith(("sync_small", "converge_small")) else image).split("x"))
    return {"s": float(open(f"{work}/{name}.s").read()), "cache": open(f"{work}/{name}.cache").read().strip(),
            "cpu": sum(float(v) for v in open(f"{work}/{name}.cpu").read().split()),
            "frames": len(rows), "uploaded": sum(r["bricks_uploaded"] for r in rows),
            "read": sum(r.get("bytes_read", 0) for r in rows) / MiB,
            "maxUpload": max(r["bytes_uploaded"] for r in rows), "converged": rows[-1]["converged"],
            # Of the pixels of the drawn frames, those cast (a frame of a still view casts what changed).
            "cast": sum(r["fragments"] for r in rows) / max(1, w * h * sum(r["drawn"] for r in rows)),
            "frameMs": sorted(r["frame_ms"] for r in rows)[len(rows) // 2]}
print(f"{'run':<16} {'cache':<5} {'wall s':>7} {'CPU s':>6} {'frames':>6} {'median frame ms':>15} {'bricks up':>9} "
      f"{'MiB read':>8} {'pixels cast':>11} {'converged':>9}")
for rep in range(1, reps + 1):
    runs = {n: load(f"{n}{rep}") for n in ("sync", "converge", "loader", "budget", "sync_small", "converge_small")}
    for n, r in runs.items():
        print(f"{n + str(rep):<16} {r['cache']:<5} {r['s']:7.2f} {r['cpu']:6.2f} {r['frames']:6d} {r['frameMs']:15.0f} "
              f"{r['uploaded']:9d} {r['read']:8.1f} {r['cast']:10.0%} {str(r['converged']):>9}")
    s = runs["sync"]["s"]
    rows = [json.loads(l) for l in open(f"{work}/converge{rep}.jsonl")]
    # Seconds until frame k ended: the run's wall time less the frames after k.
    until = lambda k: runs["converge"]["s"] - sum(r["frame_ms"] for r in rows[k + 1:]) / 1000
    final = f", to the final image (frame {final_frame}) {until(final_frame) / s:.2f}" if ext == "png" else ""
    if ext == "png" and quality_frame is not None:
        final += f", to the synchronous image's quality (frame {quality_frame}) {until(quality_frame) / s:.2f}"
    print(f"  converge / sync: {runs['converge']['s'] / s:.2f}{final}; "
          f"loader alone / sync: {runs['loader']['s'] / s:.2f} (goal <= 1.3)")
    cpu = runs["sync"]["cpu"]
    print(f"  processor seconds against sync: converge {runs['converge']['cpu'] / cpu:.2f}, "
          f"loader alone {runs['loader']['cpu'] / cpu:.2f} (on {os.cpu_count()} cores)")
    print(f"  the same cut at {small}, --voxels-per-pixel 4 (16x fewer pixels): converge / sync "
          f"{runs['converge_small']['s'] / runs['sync_small']['s']:.2f}")
    print(f"  with --upload-budget {upload}: "
          f"{runs['budget']['s'] / s:.2f}, largest frame upload {runs['budget']['maxUpload'] / MiB:.2f} MiB "
          f"({'within' if runs['budget']['maxUpload'] <= budget else 'OVER'} the budget)")
if ext != "png":
    print("images not compared: a build without OpenImageIO writes PPM and cannot read it back")
else:
    print(f"PSNR against a synchronous render with every brick it wants (budgets 2G): sync "
          f"{psnr(f'{work}/sync1.{ext}', f'{work}/full.{ext}'):.1f} dB, converge {psnr(f'{work}/converge1.{ext}', f'{work}/full.{ext}'):.1f} dB, "
          f"loader alone {psnr(f'{work}/loader1.{ext}', f'{work}/full.{ext}'):.1f} dB")
PY
