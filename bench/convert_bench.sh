#!/usr/bin/env bash
# Converter benchmark (docs/BENCHMARKS.md): generates uint16 raw volumes of realistic entropy (a smooth field
# plus noise, not a repeated pattern) under a scratch directory and measures, in the same run:
#   - `ropecast convert` wall time against `zstd -T2 -3` compressing the same file (goal: ratio <= 2.0),
#   - peak resident memory of the conversion with /usr/bin/time -v at two source sizes (goal: <= 600 MiB, flat),
#   - store size against raw size.
# Usage: bench/convert_bench.sh /path/to/ropecast [SCRATCH_DIR] [NX NY NZ_SMALL NZ_LARGE]
# Defaults: scratch under /tmp, 1024 x 1024 x 768 (1.5 GiB) and 1024 x 1024 x 1536 (3 GiB).
set -euo pipefail
ropecast=$(realpath "$1")
scratch=${2:-$(mktemp -d /tmp/ropecast-convert-bench-XXXXXX)}
nx=${3:-1024}; ny=${4:-1024}; nzSmall=${5:-768}; nzLarge=${6:-1536}
mkdir -p "$scratch"
trap 'rm -rf "$scratch"' EXIT
need=$(( (nx * ny * nzLarge * 2) * 5 / 2 ))
avail=$(( $(df --output=avail -B1 "$scratch" | tail -1) ))
if [ "$avail" -lt "$need" ]; then
  echo "convert_bench: $scratch has $((avail >> 20)) MiB free, needs about $((need >> 20)) MiB" >&2
  exit 1
fi

# The generator: a smooth CT-like field (a few low-frequency waves over a ball) plus uniform noise of +-48,
# 12-bit values stored in uint16.
cat > "$scratch/gen.cpp" <<'CPP'
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>
int main(int argc, char** argv) {
  const int nx = atoi(argv[1]), ny = atoi(argv[2]), nz = atoi(argv[3]);
  FILE* out = fopen(argv[4], "wb");
  std::vector<float> tx(nx), ty(ny);
  for (int x = 0; x < nx; ++x) tx[x] = std::sin(x * 0.013f) + 0.5f * std::sin(x * 0.057f + 1.0f);
  for (int y = 0; y < ny; ++y) ty[y] = std::cos(y * 0.011f) + 0.5f * std::sin(y * 0.043f + 2.0f);
  std::vector<uint16_t> slice(size_t(nx) * ny);
  uint64_t s = 0x9E3779B97F4A7C15ull;
  for (int z = 0; z < nz; ++z) {
    const float tz = std::sin(z * 0.017f + 0.5f), dz = (z - nz * 0.5f) / (nz * 0.5f);
    for (int y = 0; y < ny; ++y) {
      const float dy = (y - ny * 0.5f) / (ny * 0.5f);
      for (int x = 0; x < nx; ++x) {
        const float dx = (x - nx * 0.5f) / (nx * 0.5f);
        const float r2 = dx * dx + dy * dy + dz * dz;
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        const float noise = float(int(s >> 57) - 64) * 0.75f;  // +-48
        float v = r2 < 0.8f ? 1500.0f + 400.0f * (tx[x] + ty[y] + tz) : 40.0f;
        v += noise;
        slice[size_t(y) * nx + x] = uint16_t(v < 0 ? 0 : v > 4095 ? 4095 : v);
      }
    }
    fwrite(slice.data(), 2, slice.size(), out);
  }
  return fclose(out) == 0 ? 0 : 1;
}
CPP
c++ -O2 -o "$scratch/gen" "$scratch/gen.cpp"

seconds() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }
now() { date +%s.%N; }

echo "machine: $(nproc) cores, $(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo), load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "ropecast: $ropecast; zstd: $(zstd --version | head -1)"
for nz in "$nzSmall" "$nzLarge"; do
  raw="$scratch/bench_${nx}x${ny}x${nz}_uint16.raw"
  "$scratch/gen" "$nx" "$ny" "$nz" "$raw"
  rawBytes=$(stat -c %s "$raw")
  cat "$raw" > /dev/null  # both runs read from the page cache

  t0=$(now)
  zstd -T2 -3 -q -f "$raw" -o "$scratch/raw.zst"
  t1=$(now)
  /usr/bin/time -v -o "$scratch/time.txt" "$ropecast" convert "$raw" -o "$scratch/bench.store" --quiet
  t2=$(now)
  zstdS=$(seconds "$t0" "$t1"); convertS=$(seconds "$t1" "$t2")
  rssKiB=$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$scratch/time.txt")
  storeBytes=$(stat -c %s "$scratch/bench.store"); zstBytes=$(stat -c %s "$scratch/raw.zst")
  echo "source ${nx}x${ny}x${nz} uint16: $(awk -v b="$rawBytes" 'BEGIN { printf "%.2f GiB", b / 2^30 }')"
  echo "  zstd -T2 -3:       ${zstdS} s, $(awk -v a="$zstBytes" -v b="$rawBytes" 'BEGIN { printf "%.1f MiB (%.3f of raw)", a / 2^20, a / b }')"
  echo "  ropecast convert:  ${convertS} s, store $(awk -v a="$storeBytes" -v b="$rawBytes" 'BEGIN { printf "%.1f MiB (%.3f of raw)", a / 2^20, a / b }')"
  echo "  time ratio convert / zstd: $(awk -v a="$convertS" -v b="$zstdS" 'BEGIN { printf "%.2f", a / b }') (goal <= 2.0)"
  echo "  convert peak RSS: $(awk -v k="$rssKiB" 'BEGIN { printf "%.0f MiB", k / 1024 }') (goal <= 600 MiB);" \
       "user $(awk -F': ' '/User time/ { print $2 }' "$scratch/time.txt") s, system $(awk -F': ' '/System time/ { print $2 }' "$scratch/time.txt") s"
  rm -f "$raw" "$scratch/raw.zst" "$scratch/bench.store"
done
