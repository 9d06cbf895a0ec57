#!/usr/bin/env bash
# convert -> info -> verify -> extract through the command line: level 0 is byte-identical to the raw source.
# Usage: bash store_roundtrip.sh /path/to/ropecast
set -euo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

# uint16 raw named the Open SciVis way (dims and type from the name).
head -c $((31 * 17 * 23 * 2)) /dev/urandom > "$dir/noise_31x17x23_uint16.raw"
"$ropecast" convert "$dir/noise_31x17x23_uint16.raw" -o "$dir/a.store" --brick 8 --quiet
"$ropecast" verify "$dir/a.store" --quiet
"$ropecast" extract "$dir/a.store" --level 0 -o "$dir/a0.raw" --quiet
cmp "$dir/noise_31x17x23_uint16.raw" "$dir/a0.raw"
# The same input and options give the same file, whatever the compression threads.
"$ropecast" convert "$dir/noise_31x17x23_uint16.raw" -o "$dir/a1thread.store" --brick 8 --threads 1 --quiet
"$ropecast" convert "$dir/noise_31x17x23_uint16.raw" -o "$dir/a4threads.store" --brick 8 --threads 4 --quiet
cmp "$dir/a1thread.store" "$dir/a4threads.store"
cmp "$dir/a.store" "$dir/a4threads.store"
"$ropecast" extract "$dir/a.store" --level 1 -o "$dir/a1.raw" --quiet
test "$(stat -c %s "$dir/a1.raw")" -eq $((16 * 9 * 12 * 2))

# convert --crop: the store of a box of voxels holds exactly those samples of the raw file, and says so.
"$ropecast" convert "$dir/noise_31x17x23_uint16.raw" --crop 4:29,:9,11: -o "$dir/crop.store" --brick 8 --quiet
"$ropecast" verify "$dir/crop.store" --quiet
"$ropecast" extract "$dir/crop.store" -o "$dir/crop0.raw" --quiet
python3 - "$dir/noise_31x17x23_uint16.raw" "$dir/crop0.raw" <<'PY'
import sys
whole, crop = open(sys.argv[1], "rb").read(), open(sys.argv[2], "rb").read()
expected = b"".join(whole[2 * ((z * 17 + y) * 31 + 4):2 * ((z * 17 + y) * 31 + 29)]
                    for z in range(11, 23) for y in range(0, 9))
sys.exit(0 if crop == expected else "convert --crop 4:29,:9,11: did not keep exactly the box's samples")
PY
"$ropecast" info "$dir/crop.store" | grep -q "^dims *25 x 9 x 12" || { "$ropecast" info "$dir/crop.store"; exit 1; }
"$ropecast" info "$dir/crop.store" | grep -q "cropped to 4:29,0:9,11:23"
# extract --crop: the same box of the whole store's level 0.
"$ropecast" extract "$dir/a.store" --crop 4:29,:9,11: -o "$dir/crop_extract.raw" --quiet
cmp "$dir/crop0.raw" "$dir/crop_extract.raw"

# int16 with --dims/--type/--spacing.
head -c $((20 * 20 * 9 * 2)) /dev/urandom > "$dir/ct.bin"
"$ropecast" convert "$dir/ct.bin" --dims 20,20,9 --type int16 --spacing 0.5,0.5,2 -o "$dir/b.store" --quiet
"$ropecast" extract "$dir/b.store" -o "$dir/b0.raw" --quiet
cmp "$dir/ct.bin" "$dir/b0.raw"
"$ropecast" verify "$dir/b.store" --quiet
"$ropecast" info "$dir/b.store" | grep -q "^type *int16 (stored as uint16, data = stored - 32768)$"

# A big-endian int32 raw file after a 100-byte header (a wide type whose range fits 16 bits: kept exactly):
# extract writes it back as little-endian int32.
python3 - "$dir/be.bin" "$dir/le.raw" <<'PY'
import struct, sys
values = [-20000 + (i * 7919) % 60001 for i in range(14 * 9 * 6)]
open(sys.argv[1], "wb").write(b"H" * 100 + struct.pack(">%di" % len(values), *values))
open(sys.argv[2], "wb").write(struct.pack("<%di" % len(values), *values))
PY
"$ropecast" convert "$dir/be.bin" --dims 14,9,6 --type int32 --byte-order big --header-bytes 100 \
  -o "$dir/be.store" --brick 4 --quiet
"$ropecast" info "$dir/be.store" | grep -q "^type *int32 (stored as uint16, data = stored - 20000)$"
# The store says how the file was read.
"$ropecast" info "$dir/be.store" | grep -q "^source *raw:$dir/be.bin (big-endian, 100 header bytes skipped) "
"$ropecast" info "$dir/b.store" | grep -q "^source *raw:$dir/ct.bin (by"
"$ropecast" verify "$dir/be.store" --quiet
"$ropecast" extract "$dir/be.store" -o "$dir/be0.raw" --quiet
cmp "$dir/le.raw" "$dir/be0.raw"

# A uint32 label stack (a folder of single-page TIFFs, deflate-compressed, as segmentation tools write them):
# labels spanning at most 65535 are kept exactly, and extract gives them back as uint32.
mkdir "$dir/labels"
python3 - "$dir/labels" "$dir/labels.raw" <<'PY'
import struct, sys, zlib
w, h, depth = 13, 11, 6
def write_tiff(path, samples):
    data = zlib.compress(struct.pack("<%dI" % len(samples), *samples))
    pad = len(data) % 2
    entries = [(256, 4, w), (257, 4, h), (258, 3, 32), (259, 3, 8), (262, 3, 1), (273, 4, 8),
               (277, 3, 1), (278, 4, h), (279, 4, len(data)), (339, 3, 1)]
    out = b"II*\0" + struct.pack("<I", 8 + len(data) + pad) + data + b"\0" * pad
    out += struct.pack("<H", len(entries))
    for tag, kind, value in entries:  # kind 3: a 16-bit value, 4: a 32-bit one
        packed = struct.pack("<HH", value, 0) if kind == 3 else struct.pack("<I", value)
        out += struct.pack("<HHI", tag, kind, 1) + packed
    open(path, "wb").write(out + struct.pack("<I", 0))
volume = []
for z in range(depth):
    labels = [0 if (x + y + z) % 5 == 0 else 1 + (x // 4 + 3 * (y // 4) + 7 * z) % 40
              for y in range(h) for x in range(w)]
    if z == 2:
        labels[5] = 65535
    write_tiff("%s/mask_%d.tif" % (sys.argv[1], z), labels)
    volume += labels
open(sys.argv[2], "wb").write(struct.pack("<%dI" % len(volume), *volume))
PY
"$ropecast" convert "$dir/labels" -o "$dir/labels.store" --brick 8 --quiet
"$ropecast" info "$dir/labels.store" | grep -q "^type *uint32 (stored as uint16, data = stored)$"
"$ropecast" verify "$dir/labels.store" --quiet
"$ropecast" extract "$dir/labels.store" -o "$dir/labels0.raw" --quiet
cmp "$dir/labels.raw" "$dir/labels0.raw"

# info: text and JSON name the dims, type and spacing.
"$ropecast" info "$dir/b.store" | grep -q "20 x 20 x 9 samples, spacing 0.5 x 0.5 x 2"
"$ropecast" info "$dir/b.store" --json > "$dir/info.json"
grep -q '"originalType": "int16"' "$dir/info.json"
grep -q '"compressionRatio"' "$dir/info.json"
# A store name that is not UTF-8 (Latin-1 'caf\xe9'): JSON gets U+FFFD for the byte.
cp "$dir/b.store" "$dir/caf"$'\xe9'".store"
"$ropecast" info "$dir/caf"$'\xe9'".store" --json | grep -q "caf"$'\xef\xbf\xbd'".store"
rm "$dir/caf"$'\xe9'".store"

# A procedural source with --discard-below: some nodes become empty.
"$ropecast" convert procedural:sphere:48 --brick 8 --discard-below 150 -o "$dir/c.store" --quiet
"$ropecast" info "$dir/c.store" --json | grep -A4 '"nodes": {' | grep -q '"empty": [1-9]'
"$ropecast" verify "$dir/c.store" --quiet
# Only the stores, the raw files and info.json: no temporaries left.
test -z "$(find "$dir" -name '*.tmp-*')"
echo "store_roundtrip: ok"
