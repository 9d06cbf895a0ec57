#!/usr/bin/env bash
# `ropecast convert` of HDF5 files, end to end through the image module: a file of two volumes is refused,
# listing both, and writes nothing; FILE:/DATASET converts that dataset to a store of its size, type, spacing
# (element_size_um) and values; the file may not be overwritten by the store, nor through a BigDataViewer XML
# that names it; ropecast itself loads no HDF5 library at start.
# Usage: bash hdf5.sh /path/to/ropecast  (ROPECAST_HDF5_WRITER: tests/cli/write_hdf5_volume, which ctest sets)
set -uo pipefail
ropecast="$1"
writer="${ROPECAST_HDF5_WRITER:?the HDF5 writer (tests/cli/write_hdf5_volume) is not set}"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

if readelf -d "$ropecast" | grep NEEDED | grep -qi hdf5; then
  fail "ropecast needs HDF5 at start:"; readelf -d "$ropecast" | grep -i hdf5
fi
"$writer" "$dir/scan.h5" || exit 1

# Two volumes: refused, naming both, writing nothing.
"$ropecast" convert "$dir/scan.h5" -o "$dir/scan.rcast" --quiet 2> "$dir/err.txt"
rc=$?
[ "$rc" -ge 1 ] && [ "$rc" -le 127 ] || fail "a file of two volumes: exit $rc"
grep -qF "2 datasets that are volumes: /scan/ct, /scan/mask" "$dir/err.txt" ||
  { fail "the two volumes are not listed:"; cat "$dir/err.txt"; }
[ ! -e "$dir/scan.rcast" ] || fail "a refused file left $dir/scan.rcast"

# One named: 16x12x10 int16 of 0.5 x 0.75 x 2.5, values x + 16 y - 7 z - 500.
"$ropecast" convert "$dir/scan.h5:/scan/ct" -o "$dir/ct.rcast" --quiet 2> "$dir/err.txt" ||
  { fail "convert of /scan/ct"; cat "$dir/err.txt"; }
"$ropecast" info "$dir/ct.rcast" > "$dir/info.txt" || fail "info of the converted dataset"
for expected in "16 x 12 x 10 samples, spacing 0.5 x 0.75 x 2.5" "type       int16" "values     [-563, -309]" \
  "hdf5:$dir/scan.h5:/scan/ct"; do
  grep -qF -- "$expected" "$dir/info.txt" || { fail "info does not say '$expected':"; cat "$dir/info.txt"; }
done
"$ropecast" extract "$dir/ct.rcast" --level 0 -o "$dir/level0.raw" --quiet || fail "extract"
python3 - "$dir/level0.raw" <<'PY' || fail "the extracted values are not the dataset's"
import struct, sys
data = open(sys.argv[1], "rb").read()
values = struct.unpack("<%dh" % (len(data) // 2), data)
expected = [x + 16 * y - 7 * z - 500 for z in range(10) for y in range(12) for x in range(16)]
sys.exit(0 if list(values) == expected else 1)
PY

# The file is the input, whichever dataset is read.
sum=$(md5sum < "$dir/scan.h5")
"$ropecast" convert "$dir/scan.h5:/scan/mask" -o "$dir/scan.h5" --quiet 2> "$dir/err.txt" &&
  fail "convert wrote its store onto the HDF5 file it read"
grep -qF "refusing to overwrite an input" "$dir/err.txt" || { fail "no refusal:"; cat "$dir/err.txt"; }
[ "$(md5sum < "$dir/scan.h5")" = "$sum" ] || fail "the HDF5 file was changed"

# A BigDataViewer XML names its HDF5 file, which is an input too (its dataset need not exist to be guarded).
printf '<SpimData version="0.2"><BasePath type="relative">.</BasePath><SequenceDescription><ImageLoader format="bdv.hdf5"><hdf5 type="relative">scan.h5</hdf5></ImageLoader><ViewSetups><ViewSetup><id>0</id></ViewSetup></ViewSetups><Timepoints type="range"><first>0</first><last>0</last></Timepoints></SequenceDescription></SpimData>\n' > "$dir/scan.xml"
"$ropecast" convert "$dir/scan.xml" -o "$dir/scan.h5" --quiet 2> "$dir/err.txt" &&
  fail "convert wrote its store onto the HDF5 file of the BigDataViewer XML it read"
grep -qF "refusing to overwrite an input" "$dir/err.txt" || { fail "no refusal for the XML's file:"; cat "$dir/err.txt"; }
[ "$(md5sum < "$dir/scan.h5")" = "$sum" ] || fail "the XML's HDF5 file was changed"
"$ropecast" info "$dir/scan.xml" > /dev/null 2> "$dir/err.txt" && fail "info of an XML whose view is not in its file"
grep -qF "has no object /t00000/s00/0/cells" "$dir/err.txt" || { fail "the missing view:"; cat "$dir/err.txt"; }

if [ "$failures" -ne 0 ]; then
  echo "hdf5.sh: $failures failure(s)"
  exit 1
fi
echo "hdf5.sh: all passed"
