#!/usr/bin/env bash
# Bad input for convert/info/verify/extract: an exit code in 1..127, a message naming the file, no output left.
# Usage: bash store_errors.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failures=0

# expect_failure NAME PATTERN COMMAND...: the command must fail with 1..127 and print PATTERN on stderr.
expect_failure() {
  local name="$1" pattern="$2"
  shift 2
  "$@" > "$dir/out.txt" 2> "$dir/err.txt"
  rc=$?
  if [ "$rc" -lt 1 ] || [ "$rc" -gt 127 ]; then
    echo "FAIL $name: exit code $rc"; failures=$((failures + 1)); return
  fi
  if ! grep -qF -- "$pattern" "$dir/err.txt"; then
    echo "FAIL $name: stderr does not name '$pattern':"; cat "$dir/err.txt"; failures=$((failures + 1)); return
  fi
  echo "ok   $name (exit $rc): $(head -c 200 "$dir/err.txt")"
}
# expect_usage NAME PATTERN COMMAND...: as expect_failure, and the exit status is 2 (a usage error: README.md).
expect_usage() {
  local before=$failures
  expect_failure "$@"
  [ "$failures" != "$before" ] || [ "$rc" = 2 ] || { echo "FAIL $1: exit $rc, a usage error exits 2"; failures=$((failures + 1)); }
}
expect_absent() {
  if [ -e "$1" ] || [ -n "$(find "$(dirname "$1")" -name "$(basename "$1").tmp-*")" ]; then
    echo "FAIL: $1 (or a temporary of it) was left behind"; failures=$((failures + 1))
  fi
}

head -c $((24 * 20 * 16 * 2)) /dev/urandom > "$dir/v_24x20x16_uint16.raw"
"$ropecast" convert "$dir/v_24x20x16_uint16.raw" --brick 8 -o "$dir/good.store" --quiet || exit 1
size=$(stat -c %s "$dir/good.store")

# Unwritable output: its parent is a regular file / does not exist.
touch "$dir/plainfile"
expect_failure "unwritable output" "$dir/plainfile/x.store" \
  "$ropecast" convert "$dir/v_24x20x16_uint16.raw" -o "$dir/plainfile/x.store" --quiet
expect_failure "missing output directory" "$dir/nodir/x.store" \
  "$ropecast" convert "$dir/v_24x20x16_uint16.raw" -o "$dir/nodir/x.store" --quiet

# A truncated raw source leaves no store.
head -c 10000 "$dir/v_24x20x16_uint16.raw" > "$dir/cut_24x20x16_uint16.raw"
expect_failure "truncated raw" "cut_24x20x16_uint16.raw" \
  "$ropecast" convert "$dir/cut_24x20x16_uint16.raw" -o "$dir/cut.store" --quiet
expect_absent "$dir/cut.store"
# A multi-page TIFF (four 16x16 uint8 pages, each page's data then its directory) cut in page 2's data.
python3 - "$dir/pages.tif" <<'PY'
import struct, sys
out = bytearray(b"II*\x00\x00\x00\x00\x00")
link = 4
for page in range(4):
    data = out.__len__()
    out += bytes((i + 40 * page) % 256 for i in range(256))
    struct.pack_into("<I", out, link, len(out))
    tags = [(256, 16), (257, 16), (258, 8), (259, 1), (262, 1), (273, data), (277, 1), (278, 16), (279, 256)]
    out += struct.pack("<H", len(tags))
    for tag, value in tags:
        out += struct.pack("<HHII", tag, 4, 1, value)
    link = len(out)
    out += b"\x00\x00\x00\x00"
open(sys.argv[1], "wb").write(out)
PY
"$ropecast" convert "$dir/pages.tif" -o "$dir/pages.store" --quiet ||
  { echo "FAIL: the whole multi-page TIFF does not convert"; failures=$((failures + 1)); }
head -c $((8 + 2 * (256 + 114) + 100)) "$dir/pages.tif" > "$dir/cut.tif"
expect_failure "truncated multi-page TIFF" "$dir/cut.tif (page 2)" \
  "$ropecast" convert "$dir/cut.tif" -o "$dir/cut_tif.store" --quiet
expect_absent "$dir/cut_tif.store"
expect_usage "bad brick size" "--brick" \
  "$ropecast" convert "$dir/v_24x20x16_uint16.raw" --brick 12 -o "$dir/b12.store" --quiet
expect_absent "$dir/b12.store"
expect_usage "zero spacing" "--spacing 0,1,1" \
  "$ropecast" convert "$dir/v_24x20x16_uint16.raw" --spacing 0,1,1 -o "$dir/s0.store" --quiet
expect_absent "$dir/s0.store"
expect_usage "huge spacing" "[1e-12, 1e+12]" \
  "$ropecast" convert "$dir/v_24x20x16_uint16.raw" --spacing 1e300,1,1 -o "$dir/s300.store" --quiet
expect_absent "$dir/s300.store"
expect_usage "convert --crop past the volume" "--crop: the y range 3:17 does not lie in the volume's voxels 0:16 along y (16x16x16)" \
  "$ropecast" convert procedural:sphere:16 --crop :,3:17,: -o "$dir/crop.store" --quiet
expect_absent "$dir/crop.store"
expect_usage "convert --crop reversed" "--crop: expected a range of voxels A:B with A < B" \
  "$ropecast" convert procedural:sphere:16 --crop :,:,9:2 -o "$dir/crop.store" --quiet
"$ropecast" convert procedural:sphere:16 --brick 8 -o "$dir/sphere.store" --quiet
expect_usage "extract --crop past the level" "--crop: the x range 0:9 does not lie in level 1's voxels 0:8 along x (8x8x8)" \
  "$ropecast" extract "$dir/sphere.store" --level 1 --crop 0:9,:,: -o "$dir/crop.raw" --quiet
expect_absent "$dir/crop.raw"
expect_usage "convert to an empty name" "--output: expected a file name, got ''" \
  "$ropecast" convert procedural:sphere:16 -o "" --quiet
expect_usage "convert to standard output" "--output: expected a file name, got '-'" \
  "$ropecast" convert procedural:sphere:16 -o - --quiet
expect_usage "dims for a source that states its own" "procedural:sphere:16: --dims applies to raw files only" \
  "$ropecast" convert procedural:sphere:16 --dims 16,16,16 -o "$dir/d.store" --quiet
expect_absent "$dir/d.store"
# The raw layout options apply to raw files only: a NRRD header states its own byte order and where its data
# starts, a procedural volume has no file.
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n' > "$dir/u8.nrrd"
head -c 64 /dev/zero >> "$dir/u8.nrrd"
expect_usage "--byte-order for a NRRD" "$dir/u8.nrrd: --byte-order applies to raw files only" \
  "$ropecast" convert "$dir/u8.nrrd" --byte-order big -o "$dir/bo.store" --quiet
expect_absent "$dir/bo.store"
expect_usage "--header-bytes for a procedural volume" "procedural:sphere:16: --header-bytes applies to raw files only" \
  "$ropecast" convert procedural:sphere:16 --header-bytes 10 -o "$dir/hb.store" --quiet
expect_absent "$dir/hb.store"
expect_usage "unknown byte order" "--byte-order" \
  "$ropecast" convert "$dir/v_24x20x16_uint16.raw" --byte-order middle -o "$dir/bm.store" --quiet
expect_absent "$dir/bm.store"
# A header the file does not have room for: the expected size counts it.
expect_failure "raw with a header, too short" "expected 15424 (64 header bytes + 24x20x16 uint16 = 15360 bytes)" \
  "$ropecast" convert "$dir/v_24x20x16_uint16.raw" --header-bytes 64 -o "$dir/h64.store" --quiet
expect_absent "$dir/h64.store"
expect_usage "zstd level beyond zstd's" "--zstd-level 100: expected a value in" \
  "$ropecast" convert "$dir/v_24x20x16_uint16.raw" --zstd-level 100 -o "$dir/z100.store" --quiet
expect_absent "$dir/z100.store"
# A raw file whose name states neither dimensions nor type needs the options.
cp "$dir/v_24x20x16_uint16.raw" "$dir/plain.raw"
expect_usage "raw without --type" "plain.raw: sample type unknown; give --type" \
  "$ropecast" convert "$dir/plain.raw" --dims 24,20,16 -o "$dir/p.store" --quiet
expect_usage "raw without --dims" "plain.raw: dimensions unknown; give --dims" \
  "$ropecast" convert "$dir/plain.raw" -o "$dir/p.store" --quiet
expect_absent "$dir/p.store"
# A store, or one PNG, given where a volume is wanted: said as such, not read as a raw file of unknown size.
expect_failure "a store to convert" "good.store is a ropecast store already" \
  "$ropecast" convert "$dir/good.store" -o "$dir/again.store" --quiet
expect_absent "$dir/again.store"
head -c 64 /dev/urandom > "$dir/one.png"
expect_failure "one PNG to convert" "one.png is a single image; give its folder or a pattern" \
  "$ropecast" convert "$dir/one.png" -o "$dir/png.store" --quiet
expect_absent "$dir/png.store"
# A detached NRRD header whose data file is missing: the message names both.
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: gone.raw\n\n' > "$dir/h.nhdr"
expect_failure "NRRD data file missing" "NRRD header $dir/h.nhdr names data file gone.raw" \
  "$ropecast" convert "$dir/h.nhdr" -o "$dir/h.store" --quiet
printf 'NDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = gone.raw\n' > "$dir/h.mhd"
expect_failure "MetaImage data file missing" "MetaImage header $dir/h.mhd names data file gone.raw" \
  "$ropecast" convert "$dir/h.mhd" -o "$dir/h.store" --quiet
expect_absent "$dir/h.store"
expect_failure "no such input" "$dir/none.raw: no such file or directory" \
  "$ropecast" convert "$dir/none.raw" -o "$dir/n.store" --quiet
# More samples per axis than a store holds: refused before writing (the reader would refuse the store).
truncate -s 1048577 "$dir/long.raw"
expect_usage "dims beyond 2^20" "--dims" \
  "$ropecast" convert "$dir/long.raw" --dims 1048577,1,1 --type uint8 -o "$dir/long.store" --quiet
expect_absent "$dir/long.store"
expect_usage "too many threads" "--threads" \
  "$ropecast" convert "$dir/v_24x20x16_uint16.raw" --threads 100000 -o "$dir/t.store" --quiet
expect_absent "$dir/t.store"

# Damaged header: one flipped byte in the header.
cp "$dir/good.store" "$dir/header.store"
printf '\x55' | dd of="$dir/header.store" bs=1 seek=20 conv=notrunc status=none
expect_failure "damaged header (info)" "$dir/header.store" "$ropecast" info "$dir/header.store"
expect_failure "damaged header (verify)" "$dir/header.store" "$ropecast" verify "$dir/header.store" --quiet

# Not a store at all, though named as one.
head -c 4096 "$dir/v_24x20x16_uint16.raw" > "$dir/fake.rcast"
expect_failure "not a store" "bad magic" "$ropecast" info "$dir/fake.rcast"
# A volume given to info: what convert would read of it, without converting.
for input in "$dir/v_24x20x16_uint16.raw" procedural:sphere:16; do
  if "$ropecast" info "$input" > "$dir/info.txt" 2>&1 && grep -qF "not a store" "$dir/info.txt" &&
    grep -qE "^dims +(24 x 20 x 16|16 x 16 x 16) samples" "$dir/info.txt"; then
    echo "ok   info of the volume $input"
  else
    echo "FAIL: info of the volume $input:"; cat "$dir/info.txt"; failures=$((failures + 1))
  fi
done
expect_usage "procedural spec to verify" "is a procedural volume" "$ropecast" verify procedural:menger:27

# Truncated store.
head -c $((size - 100)) "$dir/good.store" > "$dir/short.store"
expect_failure "truncated store" "$dir/short.store" "$ropecast" info "$dir/short.store"

# Damaged brick: a byte in the middle of the payloads; verify names the node.
cp "$dir/good.store" "$dir/brick.store"
printf '\x00\xff\x00\xff' | dd of="$dir/brick.store" bs=1 seek=200 conv=notrunc status=none
"$ropecast" info "$dir/brick.store" > /dev/null || { echo "FAIL: info should still read a store with a bad brick"; failures=$((failures + 1)); }
expect_failure "damaged brick (verify)" "node depth" "$ropecast" verify "$dir/brick.store" --quiet
expect_failure "damaged brick (extract)" "node depth" "$ropecast" extract "$dir/brick.store" -o "$dir/brick.raw" --quiet
expect_absent "$dir/brick.raw"

# Extract: level out of range, unwritable output.
expect_usage "extract level" "--level 9: the store has levels 0..2" \
  "$ropecast" extract "$dir/good.store" --level 9 -o "$dir/l9.raw" --quiet
expect_absent "$dir/l9.raw"
expect_failure "extract unwritable" "$dir/plainfile/x.raw" \
  "$ropecast" extract "$dir/good.store" -o "$dir/plainfile/x.raw" --quiet

# A --discard-below above every sample is not an error, but the empty store it makes is said, even with -q.
if "$ropecast" convert "$dir/v_24x20x16_uint16.raw" --brick 8 --discard-below 1e9 -o "$dir/empty.store" --quiet \
  2> "$dir/err.txt" && grep -qF "every sample lies below --discard-below 1e+09" "$dir/err.txt"; then
  echo "ok   --discard-below above the data: warned"
else
  echo "FAIL --discard-below above the data: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi

# NaN and infinite samples convert, and how they were stored is said, even with -q.
python3 - "$dir/nan_6x5x4_float32.raw" <<'PY'
import struct, sys
values = [0.25 * (i % 9) for i in range(6 * 5 * 4)]
values[3], values[7], values[8], values[50] = float("nan"), float("nan"), float("inf"), float("-inf")
open(sys.argv[1], "wb").write(struct.pack("<%df" % len(values), *values))
PY
if "$ropecast" convert "$dir/nan_6x5x4_float32.raw" -o "$dir/nan.store" --quiet 2> "$dir/err.txt" &&
  grep -qxF "ropecast convert: warning: 2 samples are NaN; stored as the value range's low end, 0" "$dir/err.txt" &&
  grep -qxF "ropecast convert: warning: 2 samples are infinite; stored as the nearer end of the value range [0, 2]" \
    "$dir/err.txt"; then
  echo "ok   NaN and infinite samples: warned"
else
  echo "FAIL NaN and infinite samples: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi

# A NRRD whose space directions are not at right angles converts, and the warning says only lengths were used.
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\nspace directions: (1,0,0) (0.5,1,0) (0,0,1)\n\n' \
  > "$dir/shear.nrrd"
head -c 64 /dev/zero >> "$dir/shear.nrrd"
if "$ropecast" convert "$dir/shear.nrrd" -o "$dir/shear.store" --quiet 2> "$dir/err.txt" &&
  grep -qF "warning: $dir/shear.nrrd: its space directions are not three vectors at right angles; only their lengths" "$dir/err.txt"; then
  echo "ok   NRRD space directions not at right angles: warned"
else
  echo "FAIL NRRD space directions not at right angles: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi

# The good store is still fine.
"$ropecast" verify "$dir/good.store" --quiet > /dev/null || { echo "FAIL: good store does not verify"; failures=$((failures + 1)); }
[ "$failures" -eq 0 ] && echo "store_errors: ok" || { echo "store_errors: $failures failure(s)"; exit 1; }
