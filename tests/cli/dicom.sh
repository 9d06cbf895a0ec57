#!/usr/bin/env bash
# `ropecast convert` of DICOM series, end to end through the image module: a folder of one series (names in the
# reverse of the slices' order) converts to a store of its size, type, spacing and values; one image of a
# folder of two series converts its own series, and is refused an output onto another image of it; the folder
# alone is refused, listing both, and writes nothing; a disc's top folder converts the series in its folders,
# whose images may not be overwritten. A tilted gantry's series converts to the grid that holds its slices,
# with a warning that says so.
# Usage: bash dicom.sh /path/to/ropecast  (ROPECAST_DICOM_WRITER: tests/cli/write_dicom_series, which ctest sets)
set -uo pipefail
ropecast="$1"
writer="${ROPECAST_DICOM_WRITER:?the DICOM series writer (tests/cli/write_dicom_series) is not set}"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

mkdir "$dir/ct" "$dir/two"
"$writer" "$dir/ct" 6 || exit 1
"$writer" "$dir/two" 3 1.2.826.0.1.3680043.9.7607.1 a || exit 1
"$writer" "$dir/two" 2 1.2.826.0.1.3680043.9.7607.2 b || exit 1

# A series: 5x4 pixels of 0.5 x 0.75 mm, 6 slices 2.5 mm apart; values 100 + 37 z + 3 i - 1024.
"$ropecast" convert "$dir/ct" -o "$dir/ct.rcast" --quiet 2> "$dir/err.txt" || { fail "convert of a series"; cat "$dir/err.txt"; }
"$ropecast" info "$dir/ct.rcast" > "$dir/info.txt" || fail "info of the converted series"
for expected in "5 x 4 x 6 samples, spacing 0.5 x 0.75 x 2.5" "type       int16" "values     [-924, -682]" "dicom:"; do
  grep -qF -- "$expected" "$dir/info.txt" || { fail "info does not say '$expected':"; cat "$dir/info.txt"; }
done
# Level 0 extracted as int16: the slices in position order, the first at the last name.
"$ropecast" extract "$dir/ct.rcast" --level 0 -o "$dir/level0.raw" --quiet || fail "extract"
python3 - "$dir/level0.raw" <<'PY' || fail "the extracted values are not the series'"
import struct, sys
data = open(sys.argv[1], "rb").read()
values = struct.unpack("<%dh" % (len(data) // 2), data)
expected = [100 + 37 * z + 3 * i - 1024 for z in range(6) for i in range(20)]
sys.exit(0 if list(values) == expected else 1)
PY

# Two series in one folder: refused, naming both, writing nothing; one image converts its series.
"$ropecast" convert "$dir/two" -o "$dir/two.rcast" --quiet 2> "$dir/err.txt"
rc=$?
[ "$rc" -ge 1 ] && [ "$rc" -le 127 ] || fail "a folder of two series: exit $rc"
grep -qF "holds 2 series" "$dir/err.txt" && grep -qF "7607.2: CT, 2 images" "$dir/err.txt" ||
  { fail "the two series are not listed:"; cat "$dir/err.txt"; }
[ ! -e "$dir/two.rcast" ] || fail "a refused series left $dir/two.rcast"
# The other images of the series are inputs too: writing onto one is refused, and leaves it as it was.
sum=$(md5sum < "$dir/two/b2")
"$ropecast" convert "$dir/two/b1" -o "$dir/two/b2" --quiet 2> "$dir/err.txt" &&
  fail "convert wrote its store onto an image of the series it read"
grep -qF "refusing to overwrite an input" "$dir/err.txt" || { fail "no refusal:"; cat "$dir/err.txt"; }
[ "$(md5sum < "$dir/two/b2")" = "$sum" ] || fail "an image of the series was changed"
"$ropecast" convert "$dir/two/b1" -o "$dir/b.rcast" --quiet || fail "convert of one image's series"
"$ropecast" info "$dir/b.rcast" | grep -qF "5 x 4 x 2 samples" || fail "one image's series is not its 2 images"

# A disc's layout: the top folder converts the series in its folders, and the series' images count as inputs.
mkdir -p "$dir/disc/DICOM/PA0/ST0/SE0"
"$writer" "$dir/disc/DICOM/PA0/ST0/SE0" 6 || exit 1
"$ropecast" convert "$dir/disc" -o "$dir/disc.rcast" --quiet 2> "$dir/err.txt" || { fail "convert of a disc"; cat "$dir/err.txt"; }
"$ropecast" info "$dir/disc.rcast" | grep -qF "5 x 4 x 6 samples" || fail "the disc's series is not its 6 images"
sum=$(md5sum < "$dir/disc/DICOM/PA0/ST0/SE0/IM3")
"$ropecast" convert "$dir/disc" -o "$dir/disc/DICOM/PA0/ST0/SE0/IM3" --quiet 2> "$dir/err.txt" &&
  fail "convert wrote its store onto an image of the disc it read"
grep -qF "refusing to overwrite an input" "$dir/err.txt" || { fail "no refusal for the disc:"; cat "$dir/err.txt"; }
[ "$(md5sum < "$dir/disc/DICOM/PA0/ST0/SE0/IM3")" = "$sum" ] || fail "an image of the disc was changed"

# A tilted gantry's series: 0.8 mm further down the columns a slice, 4 slices: resampled onto 5 x 8 x 4.
mkdir "$dir/tilted"
"$writer" "$dir/tilted" 4 1.2.826.0.1.3680043.9.7607.3 t 0.8 || exit 1
"$ropecast" convert "$dir/tilted" -o "$dir/tilted.rcast" 2> "$dir/err.txt" || { fail "convert of a tilted series"; cat "$dir/err.txt"; }
grep -qF "warning: the DICOM slices lie off their normal" "$dir/err.txt" && grep -qF "gantry tilted 17.7 degrees" "$dir/err.txt" ||
  { fail "no warning of the tilt:"; cat "$dir/err.txt"; }
"$ropecast" info "$dir/tilted.rcast" | grep -qF "5 x 8 x 4 samples, spacing 0.5 x 0.75 x 2.5" ||
  { fail "the tilted series is not on its grid:"; "$ropecast" info "$dir/tilted.rcast"; }

if [ "$failures" -ne 0 ]; then
  echo "dicom.sh: $failures failure(s)"
  exit 1
fi
echo "dicom.sh: all passed"
