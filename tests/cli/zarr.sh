#!/usr/bin/env bash
# `ropecast convert` of a Zarr array end to end: an uncompressed array with nested chunk keys ("/") and edge
# chunks converts to a store of its size, type and values; a group of two arrays is refused, listing them, and
# writes nothing; no output may land on the array's metadata or on a chunk file at any depth. The same of an
# N5 dataset zarr-python wrote (tests/data/n5): its store, its container refused listing the datasets, no
# output onto its attributes or a block.
# Usage: bash zarr.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

# z, y, x = 5, 6, 9 int16 in chunks of 2 x 4 x 4, values x + 10 y - 100 z; under group.zarr/a and group.zarr/b.
python3 - "$dir/group.zarr" <<'PY' || exit 1
import json, os, struct, sys
root = sys.argv[1]
shape, chunks = (5, 6, 9), (2, 4, 4)
for name in ("a", "b"):
    folder = os.path.join(root, name)
    os.makedirs(folder)
    json.dump({"zarr_format": 2, "shape": shape, "chunks": chunks, "dtype": "<i2", "compressor": None,
               "fill_value": 0, "order": "C", "filters": None, "dimension_separator": "/"},
              open(os.path.join(folder, ".zarray"), "w"))
    for kz in range(3):
        for ky in range(2):
            for kx in range(3):
                values = []
                for z in range(kz * 2, kz * 2 + 2):
                    for y in range(ky * 4, ky * 4 + 4):
                        for x in range(kx * 4, kx * 4 + 4):
                            inside = z < 5 and y < 6 and x < 9
                            values.append(x + 10 * y - 100 * z if inside else 0)
                path = os.path.join(folder, str(kz), str(ky), str(kx))
                os.makedirs(os.path.dirname(path), exist_ok=True)
                open(path, "wb").write(struct.pack("<%dh" % len(values), *values))
json.dump({"zarr_format": 2}, open(os.path.join(root, ".zgroup"), "w"))
PY

"$ropecast" convert "$dir/group.zarr" -o "$dir/group.rcast" --quiet 2> "$dir/err.txt"
rc=$?
[ "$rc" -ge 1 ] && [ "$rc" -le 127 ] || fail "a group of two arrays: exit $rc"
grep -qF "give one of its arrays' folders: a, b" "$dir/err.txt" || { fail "the arrays are not listed:"; cat "$dir/err.txt"; }
[ ! -e "$dir/group.rcast" ] || fail "a refused group left $dir/group.rcast"

"$ropecast" convert "$dir/group.zarr/a" -o "$dir/a.rcast" --quiet 2> "$dir/err.txt" ||
  { fail "convert of an array"; cat "$dir/err.txt"; }
"$ropecast" info "$dir/a.rcast" > "$dir/info.txt" || fail "info of the converted array"
for expected in "9 x 6 x 5 samples, spacing 1 x 1 x 1" "type       int16" "values     [-400, 58]" "zarr:$dir/group.zarr/a"; do
  grep -qF -- "$expected" "$dir/info.txt" || { fail "info does not say '$expected':"; cat "$dir/info.txt"; }
done
"$ropecast" extract "$dir/a.rcast" --level 0 -o "$dir/level0.raw" --quiet || fail "extract"
python3 - "$dir/level0.raw" <<'PY' || fail "the extracted values are not the array's"
import struct, sys
data = open(sys.argv[1], "rb").read()
values = struct.unpack("<%dh" % (len(data) // 2), data)
sys.exit(0 if list(values) == [x + 10 * y - 100 * z for z in range(5) for y in range(6) for x in range(9)] else 1)
PY

for output in "group.zarr/a/.zarray" "group.zarr/a/2/1/2"; do
  sum=$(md5sum < "$dir/$output")
  "$ropecast" convert "$dir/group.zarr/a" -o "$dir/$output" --quiet 2> "$dir/err.txt" &&
    fail "convert wrote its store onto $output of the array it read"
  grep -qF "refusing to overwrite an input" "$dir/err.txt" || { fail "no refusal for $output:"; cat "$dir/err.txt"; }
  [ "$(md5sum < "$dir/$output")" = "$sum" ] || fail "$output was changed"
done

cp -r "$(dirname "$0")/../data/n5/zarr.n5" "$dir/zarr.n5"
"$ropecast" convert "$dir/zarr.n5/gzip" -o "$dir/n5.rcast" --quiet 2> "$dir/err.txt" ||
  { fail "convert of an N5 dataset"; cat "$dir/err.txt"; }
"$ropecast" info "$dir/n5.rcast" > "$dir/info.txt" || fail "info of the converted N5 dataset"
for expected in "9 x 7 x 5 samples, spacing 1 x 1 x 1" "type       uint16" "values     [0, 468]" "n5:$dir/zarr.n5/gzip"; do
  grep -qF -- "$expected" "$dir/info.txt" || { fail "info does not say '$expected':"; cat "$dir/info.txt"; }
done
"$ropecast" convert "$dir/zarr.n5" -o "$dir/container.rcast" --quiet 2> "$dir/err.txt" &&
  fail "an N5 container of datasets was converted"
grep -qF "give one of its datasets' folders: blosc, bzip2, gzip, lz4, raw, xz, zlib, zstd" "$dir/err.txt" ||
  { fail "the datasets are not listed:"; cat "$dir/err.txt"; }
[ ! -e "$dir/container.rcast" ] || fail "a refused container left $dir/container.rcast"
for output in "zarr.n5/gzip/attributes.json" "zarr.n5/gzip/1/1/1"; do
  sum=$(md5sum < "$dir/$output")
  "$ropecast" convert "$dir/zarr.n5/gzip" -o "$dir/$output" --quiet 2> "$dir/err.txt" &&
    fail "convert wrote its store onto $output of the dataset it read"
  grep -qF "refusing to overwrite an input" "$dir/err.txt" || { fail "no refusal for $output:"; cat "$dir/err.txt"; }
  [ "$(md5sum < "$dir/$output")" = "$sum" ] || fail "$output was changed"
done

if [ "$failures" -ne 0 ]; then
  echo "zarr.sh: $failures failure(s)"
  exit 1
fi
echo "zarr.sh: all passed"
