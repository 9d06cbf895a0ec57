#!/usr/bin/env bash
# Peak memory of the asynchronous loader against its budgets (docs/BENCHMARKS.md). Two stores of different
# sizes (procedural:noise:600 and :1200, converted into WORKDIR once and reused), the same budgets (--cpu-cache
# CPU, --gpu-budget GPU: under llvmpipe the pool is system memory) and a camera path that needs more bricks
# than both hold; plus a baseline (a 32^3 volume, 1 MiB budgets) for the
# fixed overhead of the process (GL driver, shaders, buffers). Peak RSS from /usr/bin/time -v.
# Prints per store: peak RSS, budgets, RSS - budgets, the largest cpu_cache_bytes and gpu_pool_used reported.
# Usage: bench/loader_memory.sh ROPECAST [WORKDIR]   env CPU (default 256M), GPU (default 256M), FRAMES (60)
set -euo pipefail
export EGL_PLATFORM="${EGL_PLATFORM:-surfaceless}"
here="$(cd "$(dirname "$0")" && pwd)"
ropecast="$1"
work="${2:-/tmp/ropecast_bench}"
cpu="${CPU:-256M}"
gpu="${GPU:-256M}"
frames="${FRAMES:-60}"
mkdir -p "$work"
for n in 600 1200; do
  [ -f "$work/noise$n.rcast" ] || "$ropecast" convert procedural:noise:$n -o "$work/noise$n.rcast" --quiet
done

peak_kib() {  # peak_kib NAME ARGS...: runs ropecast under /usr/bin/time -v, prints the peak RSS in KiB
  local name="$1"; shift
  /usr/bin/time -v "$ropecast" "$@" 2>"$work/mem_$name.time" >/dev/null
  awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$work/mem_$name.time"
}
base=$(peak_kib base render procedural:sphere:32 --brick 8 --size 256x192 --frames 3 --cpu-cache 1M \
  --gpu-budget 1M -o "$work/mem_base.png")
for n in 600 1200; do
  peak_kib noise$n render "$work/noise$n.rcast" --mode iso --size 256x192 --path "$here/flyby_path.json" \
    --frames "$frames" --cpu-cache "$cpu" --gpu-budget "$gpu" --stats "$work/mem_noise$n.jsonl" \
    -o "$work/mem_noise$n.png" >"$work/mem_noise$n.kib"
done

python3 - "$work" "$cpu" "$gpu" "$base" <<'PY'
import json, os, sys
work, cpu, gpu, base = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
def parse(s):
    units = {"K": 1 << 10, "M": 1 << 20, "G": 1 << 30}
    return int(float(s[:-1]) * units[s[-1]]) if s[-1] in units else int(s)
budgets = parse(cpu) + parse(gpu)
MiB = 1 << 20
print(f"budgets: --cpu-cache {cpu} + --gpu-budget {gpu} = {budgets / MiB:.0f} MiB; "
      f"baseline process (32^3, 1 MiB budgets): {base / 1024:.0f} MiB peak RSS")
print(f"{'store':<10} {'raw MiB':>8} {'file MiB':>8} {'peak RSS':>9} {'RSS-budgets':>11} {'RSS-budgets-base':>16} "
      f"{'cpu_cache max':>13} {'gpu_pool max':>12}")
for n in (600, 1200):
    kib = int(open(f"{work}/mem_noise{n}.kib").read())
    rows = [json.loads(l) for l in open(f"{work}/mem_noise{n}.jsonl")]
    rss = kib * 1024
    print(f"noise{n:<5} {n**3 / MiB:8.0f} {os.path.getsize(f'{work}/noise{n}.rcast') / MiB:8.1f} "
          f"{rss / MiB:9.0f} {(rss - budgets) / MiB:11.0f} {(rss - budgets - base * 1024) / MiB:16.0f} "
          f"{max(r['cpu_cache_bytes'] for r in rows) / MiB:13.0f} {max(r['gpu_pool_used'] for r in rows) / MiB:12.0f}")
PY
