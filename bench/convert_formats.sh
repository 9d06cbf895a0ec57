#!/usr/bin/env bash
# `ropecast convert` from HDF5 and Zarr against the same volume as a raw file (docs/BENCHMARKS.md, "Converting
# HDF5 and Zarr"): a CT-like uint16 field plus noise, written raw, as HDF5 datasets contiguous, chunked CHUNK^3
# and chunked with shuffle and deflate, and as Zarr arrays of CHUNK^3 blosc (lz4, shuffle) chunks (v2, and v3
# in shards of 1 x 8 x 8 chunks), each converted in turn from the page cache (ROUNDS rounds). Prints per input
# its size, the median wall time and peak RSS and their ratios to the raw file's, and checks that every store
# holds the raw store's level 1 (extracted and compared).
# Usage: bench/convert_formats.sh [BUILD_DIR]   (default build/perf)
# Environment: NX NY NZ (1024 1024 256: 512 MiB), CHUNK (64), ROUNDS (3), SCRATCH (a temporary directory).
set -euo pipefail
cd "$(dirname "$0")/.."
ropecast=$(realpath "${1:-build/perf}/tools/ropecast")
nx=${NX:-1024}; ny=${NY:-1024}; nz=${NZ:-256}; chunk=${CHUNK:-64}; rounds=${ROUNDS:-3}
scratch=${SCRATCH:-$(mktemp -d /tmp/ropecast-convert-formats-XXXXXX)}
mkdir -p "$scratch"
trap 'rm -rf "$scratch"' EXIT

# The writer: the field of bench/convert_bench.sh (waves over a ball, +-48 noise, 12 bits), raw, as HDF5 and
# as Zarr.
cat > "$scratch/gen.cpp" <<'CPP'
#include <blosc.h>
#include <hdf5.h>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>
int main(int argc, char** argv) {
  const hsize_t nx = atoi(argv[1]), ny = atoi(argv[2]), nz = atoi(argv[3]), c = atoi(argv[4]);
  const std::string base = argv[5];
  std::vector<uint16_t> v(nx * ny * nz);
  uint64_t s = 0x9E3779B97F4A7C15ull;
  for (hsize_t z = 0; z < nz; ++z) {
    const float tz = std::sin(z * 0.017f + 0.5f), dz = (z - nz * 0.5f) / (nz * 0.5f);
    for (hsize_t y = 0; y < ny; ++y) {
      const float dy = (y - ny * 0.5f) / (ny * 0.5f), ty = std::cos(y * 0.011f) + 0.5f * std::sin(y * 0.043f + 2.0f);
      for (hsize_t x = 0; x < nx; ++x) {
        const float dx = (x - nx * 0.5f) / (nx * 0.5f), tx = std::sin(x * 0.013f) + 0.5f * std::sin(x * 0.057f + 1.0f);
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        float f = dx * dx + dy * dy + dz * dz < 0.8f ? 1500.0f + 400.0f * (tx + ty + tz) : 40.0f;
        f += float(int(s >> 57) - 64) * 0.75f;
        v[(z * ny + y) * nx + x] = uint16_t(f < 0 ? 0 : f > 4095 ? 4095 : f);
      }
    }
  }
  FILE* raw = fopen((base + "_" + argv[1] + "x" + argv[2] + "x" + argv[3] + "_uint16.raw").c_str(), "wb");
  if (!raw || fwrite(v.data(), 2, v.size(), raw) != v.size() || fclose(raw) != 0) return 1;
  const hsize_t extent[3] = {nz, ny, nx}, chunk[3] = {c, c, c};
  for (const char* kind : {"contiguous", "chunked", "deflated"}) {
    const hid_t file = H5Fcreate((base + "_" + kind + ".h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t space = H5Screate_simple(3, extent, nullptr), create = H5Pcreate(H5P_DATASET_CREATE);
    if (std::string(kind) != "contiguous") H5Pset_chunk(create, 3, chunk);
    if (std::string(kind) == "deflated") H5Pset_shuffle(create), H5Pset_deflate(create, 4);
    const hid_t d = H5Dcreate2(file, "/volume", H5T_STD_U16LE, space, H5P_DEFAULT, create, H5P_DEFAULT);
    if (d < 0 || H5Dwrite(d, H5T_NATIVE_UINT16, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0) return 1;
    H5Dclose(d), H5Pclose(create), H5Sclose(space), H5Fclose(file);
  }
  const std::string zarr = base + ".zarr";
  std::system(("mkdir -p " + zarr).c_str());
  FILE* meta = fopen((zarr + "/.zarray").c_str(), "w");
  fprintf(meta, "{\"zarr_format\": 2, \"shape\": [%llu, %llu, %llu], \"chunks\": [%llu, %llu, %llu], "
          "\"dtype\": \"<u2\", \"compressor\": {\"id\": \"blosc\", \"cname\": \"lz4\", \"clevel\": 5, "
          "\"shuffle\": 1, \"blocksize\": 0}, \"fill_value\": 0, \"order\": \"C\", \"filters\": null}",
          nz, ny, nx, c, c, c);
  fclose(meta);
  // Every chunk packed once, for the v2 array and the v3 array's shards of 1 x 8 x 8 chunks.
  const hsize_t gz = (nz + c - 1) / c, gy = (ny + c - 1) / c, gx = (nx + c - 1) / c, per = 8;
  std::vector<std::string> packed(gz * gy * gx);
  std::vector<uint16_t> block(c * c * c);
  for (hsize_t kz = 0; kz < gz; ++kz)
    for (hsize_t ky = 0; ky < gy; ++ky)
      for (hsize_t kx = 0; kx < gx; ++kx) {
        for (hsize_t z = 0; z < c; ++z)
          for (hsize_t y = 0; y < c; ++y)
            for (hsize_t x = 0; x < c; ++x) {
              const hsize_t az = kz * c + z, ay = ky * c + y, ax = kx * c + x;
              block[(z * c + y) * c + x] = az < nz && ay < ny && ax < nx ? v[(az * ny + ay) * nx + ax] : 0;
            }
        std::string& out = packed[(kz * gy + ky) * gx + kx];
        out.resize(block.size() * 2 + BLOSC_MAX_OVERHEAD);
        out.resize(size_t(blosc_compress_ctx(5, BLOSC_SHUFFLE, 2, block.size() * 2, block.data(), out.data(),
                                             out.size(), "lz4", 0, 1)));
      }
  const auto write = [](const std::string& path, const std::string& bytes) {
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    FILE* f = fopen(path.c_str(), "wb");
    return f && fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && fclose(f) == 0;
  };
  for (hsize_t kz = 0; kz < gz; ++kz)
    for (hsize_t ky = 0; ky < gy; ++ky)
      for (hsize_t kx = 0; kx < gx; ++kx)
        if (!write(zarr + "/" + std::to_string(kz) + "." + std::to_string(ky) + "." + std::to_string(kx),
                   packed[(kz * gy + ky) * gx + kx]))
          return 1;
  const std::string zarr3 = base + "_sharded.zarr";
  char json[1024];
  snprintf(json, sizeof json,
           "{\"zarr_format\": 3, \"node_type\": \"array\", \"shape\": [%llu, %llu, %llu], \"data_type\": \"uint16\", "
           "\"chunk_grid\": {\"name\": \"regular\", \"configuration\": {\"chunk_shape\": [%llu, %llu, %llu]}}, "
           "\"chunk_key_encoding\": {\"name\": \"default\"}, \"fill_value\": 0, \"codecs\": [{\"name\": "
           "\"sharding_indexed\", \"configuration\": {\"chunk_shape\": [%llu, %llu, %llu], \"codecs\": [{\"name\": "
           "\"bytes\", \"configuration\": {\"endian\": \"little\"}}, {\"name\": \"blosc\", \"configuration\": "
           "{\"cname\": \"lz4\", \"clevel\": 5, \"shuffle\": \"shuffle\", \"typesize\": 2}}], \"index_codecs\": "
           "[{\"name\": \"bytes\", \"configuration\": {\"endian\": \"little\"}}]}}]}",
           nz, ny, nx, c, per * c, per * c, c, c, c);
  if (!write(zarr3 + "/zarr.json", json)) return 1;
  for (hsize_t kz = 0; kz < gz; ++kz)
    for (hsize_t sy = 0; sy * per < gy; ++sy)
      for (hsize_t sx = 0; sx * per < gx; ++sx) {
        std::string shard, index;
        const auto entry = [&](uint64_t value) { index.append(reinterpret_cast<const char*>(&value), 8); };
        for (hsize_t iy = 0; iy < per; ++iy)
          for (hsize_t ix = 0; ix < per; ++ix) {
            const hsize_t ky = sy * per + iy, kx = sx * per + ix;
            if (ky >= gy || kx >= gx) {
              entry(~uint64_t(0)), entry(~uint64_t(0));
              continue;
            }
            const std::string& bytes = packed[(kz * gy + ky) * gx + kx];
            entry(shard.size()), entry(bytes.size());
            shard += bytes;
          }
        if (!write(zarr3 + "/c/" + std::to_string(kz) + "/" + std::to_string(sy) + "/" + std::to_string(sx),
                   shard + index))
          return 1;
      }
  return 0;
}
CPP
# shellcheck disable=SC2046
c++ -O2 -o "$scratch/gen" "$scratch/gen.cpp" $(pkg-config --cflags --libs hdf5 blosc)
"$scratch/gen" "$nx" "$ny" "$nz" "$chunk" "$scratch/volume"
raw="$scratch/volume_${nx}x${ny}x${nz}_uint16.raw"
inputs=("$raw" "$scratch/volume_contiguous.h5" "$scratch/volume_chunked.h5" "$scratch/volume_deflated.h5"
  "$scratch/volume.zarr" "$scratch/volume_sharded.zarr")
names=(raw "HDF5 contiguous" "HDF5 chunked ${chunk}^3" "HDF5 chunked ${chunk}^3, shuffle+deflate"
  "Zarr ${chunk}^3, blosc lz4+shuffle" "Zarr v3, shards of 8x8 such chunks")

echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); ${nx}x${ny}x${nz} uint16, $rounds rounds"
for round in $(seq "$rounds"); do
  for i in "${!inputs[@]}"; do
    find "${inputs[$i]}" -type f -exec cat {} + > /dev/null  # every input from the page cache
    /usr/bin/time -f "%e %M" -o "$scratch/time_${i}_$round.txt" \
      "$ropecast" convert "${inputs[$i]}" -o "$scratch/store_$i.rcast" --quiet
  done
done
"$ropecast" extract "$scratch/store_0.rcast" --level 1 -o "$scratch/level1_0.raw" --quiet
printf "%-40s %10s %10s %8s %10s %8s  %s\n" input MiB seconds ratio "RSS MiB" ratio "level 1"
for i in "${!inputs[@]}"; do
  seconds=$(cat "$scratch"/time_"${i}"_*.txt | awk '{ print $1 }' | sort -n | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }')
  rss=$(cat "$scratch"/time_"${i}"_*.txt | awk '{ print $2 }' | sort -n | tail -1)
  [ "$i" = 0 ] && rawSeconds=$seconds && rawRss=$rss
  "$ropecast" extract "$scratch/store_$i.rcast" --level 1 -o "$scratch/level1_$i.raw" --quiet
  same=$(cmp -s "$scratch/level1_0.raw" "$scratch/level1_$i.raw" && echo same || echo DIFFERENT)
  awk -v n="${names[$i]}" -v b="$(du -sb "${inputs[$i]}" | cut -f1)" -v s="$seconds" -v rs="$rawSeconds" -v m="$rss" \
    -v rm="$rawRss" -v same="$same" \
    'BEGIN { printf "%-40s %10.1f %10.2f %8.2f %10.0f %8.2f  %s\n", n, b / 2^20, s, s / rs, m / 1024, m / rm, same }'
done
