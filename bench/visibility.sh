#!/usr/bin/env bash
# Visibility-driven refinement side by side (docs/BENCHMARKS.md): occlusion queries (Gobbetti et al. 2008,
# Sect. 6) and ray feedback (Crassin et al. 2009), in four configurations on the same store, camera and budgets:
#   priority   --occlusion off --feedback off   (projected voxel size only)
#   occlusion  --occlusion on  --feedback off
#   feedback   --occlusion off --feedback on
#   both       --occlusion on  --feedback on
# The store has depth complexity: procedural:menger:SIZE (a Menger sponge: holes behind holes), converted into
# WORK once and reused.
# 1. Cold cache to convergence at IMAGE, `render --converge`, an opaque isosurface and a semi-transparent DVR
#    (a ramp reaching opacity 0.3 per voxel, gradients computed): the working set at convergence (bricks of
#    the refined tree), bricks resident, bytes read and uploaded in total, frames and seconds to converge, the
#    converged frame time (median of STEADY frames past the convergence, from a second run), the query and
#    feedback latencies, the PSNR of each image against priority, and the frame from which the image stays
#    within 40 dB of the converged one, with the seconds to it (every frame is written to
#    WORK/frames-MODE-CONFIG/ for that; the seconds are frame times, which the writes do not enter).
# 1b. Iso from the page cache again, the same cut with 16 times fewer pixels (IMAGE / 4 on a side,
#    --voxels-per-pixel 4, which asks for the same bricks), CHEAP_REPS times: frames and seconds to converge,
#    medians (what the frames' cost on this machine adds to the answers' round trips).
# 2. The same, iso only, with a slow disk (--io-delay-ms SLOW_IO per brick read, --io-threads 2: the same disk
#    on every machine): answers come back while the tree is still being read, as in Gobbetti et al. 2008's
#    out-of-core setting.
# 3. Cold cache, then bench/flyby_path.json (FRAMES frames at PATH_IMAGE) with GPU and CPU budgets smaller than
#    the path's working set: frame time median and max, bytes read and uploaded, evictions of bricks the rays
#    used in the frame before (used_evictions); PATH_REPS times, the configurations taking turns (frame times
#    move between runs more than between configurations), medians over the repetitions.
# Usage: bench/visibility.sh [BUILD_DIR]   env SIZE (729), IMAGE (1024x1024), PATH_IMAGE (512x512), FRAMES (120),
#   MODES ("iso dvr"), CONFIGS ("priority occlusion feedback both"), STEADY (4), GPU (1G), CPU (1G),
#   PATH_GPU (128M), PATH_CPU (128M), PATH_REPS (1), SLOW_IO (2, milliseconds; 0 skips part 2), MAX_FRAMES (400,
#   the frame limit of a run to convergence: fast GPU frames need more from a slow disk), WORK (a fresh folder),
#   CHEAP_REPS (3; 0 skips part 1b), SKIP_PATH=1 skips part 3, SKIP_CONVERGE=1 reuses the results of parts 1 and 2 in WORK, EXT (png, or ppm
#   for a build without OpenImageIO: then the images are not compared, and PSNR and "final at" read nan)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
source "$here/lib/common.sh"
SIZE=${SIZE:-729}
IMAGE=${IMAGE:-1024x1024}
bench_setup visibility "${1:-build/perf}"
path_image=${PATH_IMAGE:-512x512}
frames=${FRAMES:-120}
modes=${MODES:-iso dvr}
configs=${CONFIGS:-priority occlusion feedback both}
steady=${STEADY:-4}
max_frames=${MAX_FRAMES:-400}
slow_io=${SLOW_IO:-2}
EXT=${EXT:-png}
store="$WORK/menger$SIZE.rcast"
[ -f "$store" ] || "$ROPECAST" convert "procedural:menger:$SIZE" -o "$store" --quiet
printf '{"points": [[0, 0.0, 0.0, 0.0, 0.0], [100, 0.9, 0.6, 0.3, 0.0], [255, 1.0, 0.9, 0.7, 0.3]]}\n' \
  >"$WORK/semi.json"

flags() {
  case $1 in
    priority) echo --occlusion off --feedback off ;;
    occlusion) echo --occlusion on --feedback off ;;
    feedback) echo --occlusion off --feedback on ;;
    both) echo --occlusion on --feedback on ;;
  esac
}
# DVR computes its gradients: stored ones take 8 more bytes per pool texel, and the pool would bound the
# working set instead of the view.
mode_args() { [ "$1" = iso ] && echo --mode iso || echo --mode dvr --tf "$WORK/semi.json" --gradients computed; }

for mode in $modes; do
  [ "${SKIP_CONVERGE:-0}" = 1 ] && break  # summarize the results already in WORK
  for config in $configs; do
    echo "visibility.sh: converge, $mode, $config" >&2
    frames_dir="$WORK/frames-$mode-$config"
    rm -rf "$frames_dir" && mkdir -p "$frames_dir"
    # shellcheck disable=SC2046
    "$ROPECAST" render "$store" $(mode_args "$mode") --size "$IMAGE" --orbit 30,20,1.6 --converge \
      --max-frames "$max_frames" --gpu-budget "${GPU:-1G}" --cpu-cache "${CPU:-1G}" $(flags "$config") \
      --stats "$WORK/converge-$mode-$config.jsonl" --every 1 -o "$frames_dir/f.$EXT"
    cp "$frames_dir/f.$EXT" "$WORK/converge-$mode-$config.$EXT"
    # The converged frame time: the same start again, STEADY frames past the convergence.
    n=$(wc -l <"$WORK/converge-$mode-$config.jsonl")
    # shellcheck disable=SC2046
    "$ROPECAST" render "$store" $(mode_args "$mode") --size "$IMAGE" --orbit 30,20,1.6 --frames $((n + steady)) \
      --gpu-budget "${GPU:-1G}" --cpu-cache "${CPU:-1G}" $(flags "$config") \
      --stats "$WORK/steady-$mode-$config.jsonl" -o "$WORK/steady-$mode-$config.$EXT"
  done
done
cheap_reps=${CHEAP_REPS:-3}
IFS=x read -r width height <<<"$IMAGE"
cheap_image="$((width / 4))x$((height / 4))"
if [ "${SKIP_CONVERGE:-0}" != 1 ]; then
  for rep in $(seq 1 "$cheap_reps"); do
    for config in $configs; do
      echo "visibility.sh: converge with cheap frames, iso, $config, $rep" >&2
      # shellcheck disable=SC2046
      "$ROPECAST" render "$store" --mode iso --size "$cheap_image" --voxels-per-pixel 4 --orbit 30,20,1.6 \
        --converge --max-frames "$max_frames" --gpu-budget "${GPU:-1G}" --cpu-cache "${CPU:-1G}" $(flags "$config") \
        --stats "$WORK/cheap-iso-$config-$rep.jsonl" -o "$WORK/cheap-iso-$config.$EXT"
    done
  done
fi
if [ "${SKIP_CONVERGE:-0}" != 1 ] && [ "$slow_io" != 0 ]; then
  for config in $configs; do
    echo "visibility.sh: converge with a slow disk, iso, $config" >&2
    # shellcheck disable=SC2046
    "$ROPECAST" render "$store" --mode iso --size "$IMAGE" --orbit 30,20,1.6 --converge --max-frames "$max_frames" \
      --gpu-budget "${GPU:-1G}" --cpu-cache "${CPU:-1G}" $(flags "$config") --io-delay-ms "$slow_io" \
      --io-threads 2 --stats "$WORK/slow-iso-$config.jsonl" -o "$WORK/slow-iso-$config.$EXT"
  done
fi
path_reps=${PATH_REPS:-1}
if [ "${SKIP_PATH:-0}" != 1 ]; then
  rm -f "$WORK"/path-*.jsonl
  for rep in $(seq "$path_reps"); do
    for config in $configs; do
      echo "visibility.sh: path, $config, repetition $rep" >&2
      # shellcheck disable=SC2046
      "$ROPECAST" render "$store" --mode iso --size "$path_image" --path "$here/flyby_path.json" --frames "$frames" \
        --gpu-budget "${PATH_GPU:-128M}" --cpu-cache "${PATH_CPU:-128M}" $(flags "$config") \
        --stats "$WORK/path-$config-$rep.jsonl" -o "$WORK/path-$config.$EXT"
    done
  done
fi

python3 - "$WORK" "$modes" "$configs" "$IMAGE" "$SIZE" "$path_image" "${SKIP_PATH:-0}" "$ROPECAST" "$slow_io" "$EXT" "$cheap_image" "$cheap_reps" <<'PY'
import glob, json, os, statistics, subprocess, sys
work, modes, configs, image, size, path_image, skip_path, ropecast, slow_io, ext, cheap_image, cheap_reps = sys.argv[1:]
modes, configs = modes.split(), configs.split()
MiB = 1 << 20
def rows(name):
    return [json.loads(l) for l in open(f"{work}/{name}.jsonl")]
def psnr(a, b):
    if ext != "png":
        return float("nan")  # a build without OpenImageIO cannot read images back
    out = subprocess.run([ropecast, "compare", a, b], capture_output=True, text=True, check=True).stdout
    return float(json.loads(out)["psnr_db"])
def steady_ms(mode, config):
    # Median frame time of the second run's frames past the convergence (converged ones only).
    ms = [x["frame_ms"] for x in rows(f"steady-{mode}-{config}")[len(rows(f"converge-{mode}-{config}")):]
          if x["converged"]]
    return statistics.median(ms) if ms else float("nan")
def final_frame(mode, config):
    # The first frame from which every frame is within 40 dB of the converged image (the last frame, also
    # written as f.png).
    if ext != "png":
        return float("nan")
    frames = sorted(glob.glob(f"{work}/frames-{mode}-{config}/f_*.png"))
    k = len(frames)
    while k > 0 and psnr(frames[k - 1], f"{work}/frames-{mode}-{config}/f.png") >= 40.0:
        k -= 1
    return k
# Parts 1 and 2 are summarized when their results are in WORK (SKIP_CONVERGE=1 with a fresh WORK has none).
converged = [m for m in modes if os.path.exists(f"{work}/converge-{m}-{configs[0]}.jsonl")]
if converged:
    print(f"procedural:menger:{size} store, cold cache to convergence at {image}")
for mode in converged:
    head = ["working set", "resident", "read MiB", "upload MiB", "frames", "seconds", "final at", "s to final",
            "frame ms", "q.lat", "fb.lat", "PSNR"]
    print(f"\n{mode:<10}" + "".join(f"{h:>12}" for h in head))
    base = None
    for config in configs:
        r = rows(f"converge-{mode}-{config}")
        last = r[-1]
        k = final_frame(mode, config)
        s = {"working set": last["working_set_bricks"], "resident": last["bricks_resident"],
             "final at": k, "s to final": sum(x["frame_ms"] for x in r[:k + 1]) / 1000 if k == k else k,
             "read MiB": sum(x["bytes_read"] for x in r) / MiB, "upload MiB": sum(x["bytes_uploaded"] for x in r) / MiB,
             "frames": len(r), "seconds": sum(x["frame_ms"] for x in r) / 1000, "frame ms": steady_ms(mode, config),
             "q.lat": last["occlusion_latency_frames"], "fb.lat": last["feedback_latency_frames"],
             "PSNR": psnr(f"{work}/converge-{mode}-{config}.{ext}", f"{work}/converge-{mode}-{configs[0]}.{ext}")}
        base = base or s
        print(f"{config:<10}" + "".join(f"{s[h]:12.1f}" for h in head) + ("" if last["converged"] else "  NOT CONVERGED"))
    print("  " + mode + ", against " + configs[0] + ": working set " + ", ".join(
        f"{c} {rows(f'converge-{mode}-{c}')[-1]['working_set_bricks'] / base['working set']:.2f}" for c in configs[1:]))
if int(cheap_reps) > 0 and os.path.exists(f"{work}/cheap-iso-{configs[0]}-1.jsonl"):
    print(f"\niso, the same cut with 16x fewer pixels ({cheap_image}, --voxels-per-pixel 4), cold cache to "
          f"convergence, medians of {cheap_reps}")
    head = ["working set", "frames", "seconds", "vs " + configs[0]]
    print(f"{'':<10}" + "".join(f"{h:>12}" for h in head))
    base = None
    for config in configs:
        runs = [rows(f"cheap-iso-{config}-{k}") for k in range(1, int(cheap_reps) + 1)]
        seconds = statistics.median(sum(x["frame_ms"] for x in r) / 1000 for r in runs)
        base = base or seconds
        s = {"working set": runs[0][-1]["working_set_bricks"], "frames": statistics.median(len(r) for r in runs),
             "seconds": seconds, "vs " + configs[0]: seconds / base}
        print(f"{config:<10}" + "".join(f"{s[h]:12.2f}" for h in head) +
              ("" if all(r[-1]["converged"] for r in runs) else "  NOT CONVERGED"))
if slow_io != "0" and os.path.exists(f"{work}/slow-iso-{configs[0]}.jsonl"):
    print(f"\niso with --io-delay-ms {slow_io} per brick read (a slow disk), cold cache to convergence at {image}")
    head = ["working set", "read MiB", "upload MiB", "frames", "seconds", "PSNR"]
    print(f"{'':<10}" + "".join(f"{h:>12}" for h in head))
    for config in configs:
        r = rows(f"slow-iso-{config}")
        s = {"working set": r[-1]["working_set_bricks"], "read MiB": sum(x["bytes_read"] for x in r) / MiB,
             "upload MiB": sum(x["bytes_uploaded"] for x in r) / MiB, "frames": len(r),
             "seconds": sum(x["frame_ms"] for x in r) / 1000,
             "PSNR": psnr(f"{work}/slow-iso-{config}.{ext}", f"{work}/slow-iso-{configs[0]}.{ext}")}
        print(f"{config:<10}" + "".join(f"{s[h]:12.1f}" for h in head) + ("" if r[-1]["converged"] else "  NOT CONVERGED"))
if skip_path != "1":
    reps = sorted(glob.glob(f"{work}/path-{configs[0]}-*.jsonl"))
    print(f"\nflyby_path.json at {path_image}, iso" + (f", medians of {len(reps)} repetitions" if len(reps) > 1 else ""))
    head = ["frame med", "frame max", "raycast med", "read MiB", "upload MiB", "used evict"]
    print(f"{'':<10}" + "".join(f"{h:>12}" for h in head))
    for config in configs:
        runs = []
        for path in sorted(glob.glob(f"{work}/path-{config}-*.jsonl")):
            r = [json.loads(line) for line in open(path)]
            ms = [x["frame_ms"] for x in r[1:]]
            runs.append({"frame med": statistics.median(ms), "frame max": max(ms),
                         "raycast med": statistics.median(x["raycast_ms"] for x in r[1:]),
                         "read MiB": sum(x["bytes_read"] for x in r) / MiB,
                         "upload MiB": sum(x["bytes_uploaded"] for x in r) / MiB,
                         "used evict": sum(x["used_evictions"] for x in r)})
        s = {h: statistics.median(run[h] for run in runs) for h in head}
        print(f"{config:<10}" + "".join(f"{s[h]:12.1f}" for h in head))
PY
