#!/usr/bin/env bash
# render (and so view, bench modes and regress, through the same opening) given a volume instead of a store:
# converted to a temporary store under $TMPDIR that is gone when the run ends, drawn as the store `convert`
# makes of it is drawn; --brick sets its brick size; a raw file without its dimensions in its name is refused,
# pointing at convert; the volume is an input no output may overwrite.
# Usage: bash volume_inputs.sh /path/to/ropecast
set -uo pipefail
# shellcheck source=tests/cli/lib/nifti_series.sh
source "$(dirname "$0")/lib/nifti_series.sh"
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
export TMPDIR="$dir/tmp"
mkdir -p "$TMPDIR"

# A 24x20x16 uint16 ball, values rising towards its centre.
python3 - "$dir/ball_24x20x16_uint16.raw" <<'PY' || exit 1
import struct, sys
values = [max(0, int(4000 - 300 * ((x - 12) ** 2 + (y - 10) ** 2 + (z - 8) ** 2) ** 0.5))
          for z in range(16) for y in range(20) for x in range(24)]
open(sys.argv[1], "wb").write(struct.pack("<%dH" % len(values), *values))
PY
cp "$dir/ball_24x20x16_uint16.raw" "$dir/unnamed.raw"
render=(render --size 48x40 --iso 2000 -q)

"$ropecast" "${render[@]}" "$dir/ball_24x20x16_uint16.raw" -o "$dir/direct.png" 2> "$dir/err.txt" ||
  { fail "render of a volume"; cat "$dir/err.txt"; }
"$ropecast" convert "$dir/ball_24x20x16_uint16.raw" -o "$dir/ball.rcast" --quiet || fail "convert"
"$ropecast" "${render[@]}" "$dir/ball.rcast" -o "$dir/store.png" || fail "render of the store"
cmp -s "$dir/direct.png" "$dir/store.png" || fail "the volume rendered directly differs from its store's image"
[ -z "$(ls -A "$TMPDIR")" ] || { fail "the temporary store stayed:"; ls -la "$TMPDIR"; }

# Not quiet: it says what it does.
"$ropecast" render --size 48x40 --iso 2000 "$dir/ball_24x20x16_uint16.raw" -o "$dir/said.png" 2> "$dir/err.txt" ||
  fail "render of a volume, not quiet"
grep -qF "is a volume: converting it to a temporary store" "$dir/err.txt" || { fail "no word of the conversion:"; cat "$dir/err.txt"; }

# --brick: the volume's bricks; refused for a store.
"$ropecast" "${render[@]}" --brick 8 --stats "$dir/stats.jsonl" "$dir/ball_24x20x16_uint16.raw" -o "$dir/b8.png" ||
  fail "render of a volume with --brick 8"
grep -qE '"leaves": *([2-9]|[1-9][0-9]+)' "$dir/stats.jsonl" || { fail "--brick 8 made no finer cut:"; cat "$dir/stats.jsonl"; }
"$ropecast" "${render[@]}" --brick 8 "$dir/ball.rcast" -o "$dir/x.png" 2> "$dir/err.txt" && fail "--brick with a store"
grep -qF "the brick size it was converted with" "$dir/err.txt" || { fail "no --brick refusal:"; cat "$dir/err.txt"; }

# A raw file that does not name its dimensions: read with convert's options (and info's), refused without
# them, naming them; they are refused for a store and a procedural volume, which they cannot describe.
"$ropecast" "${render[@]}" "$dir/unnamed.raw" -o "$dir/x.png" 2> "$dir/err.txt"
rc=$?
[ "$rc" -ge 1 ] && [ "$rc" -le 127 ] || fail "an unnamed raw file: exit $rc"
grep -qF -- "--dims" "$dir/err.txt" || { fail "no word of --dims:"; cat "$dir/err.txt"; }
[ ! -e "$dir/x.png" ] || fail "a refused render left $dir/x.png"
"$ropecast" "${render[@]}" "$dir/unnamed.raw" --dims 24,20,16 --type uint16 -o "$dir/unnamed.png" 2> "$dir/err.txt" ||
  { fail "render of a raw file with --dims and --type"; cat "$dir/err.txt"; }
cmp -s "$dir/unnamed.png" "$dir/store.png" || fail "the raw file with --dims and --type differs from its named twin's image"
"$ropecast" "${render[@]}" "$dir/unnamed.raw" --dims 24,20,16 --type uint16 --spacing 1,1,2 -o "$dir/spaced.png" ||
  fail "render with --spacing"
cmp -s "$dir/spaced.png" "$dir/store.png" && fail "--spacing changed nothing"
"$ropecast" info "$dir/unnamed.raw" --dims 24,20,16 --type u16 --byte-order big > "$dir/info.txt" || fail "info with --dims"
grep -q "^dims       24 x 20 x 16 samples" "$dir/info.txt" || fail "info with --dims: $(cat "$dir/info.txt")"
for input in "$dir/ball.rcast" procedural:sphere:16; do
  "$ropecast" "${render[@]}" "$input" --type uint8 -o "$dir/x.png" 2> "$dir/err.txt" && fail "--type with $input"
  grep -qF -- "--type applies to a volume read from its file" "$dir/err.txt" || { fail "no --type refusal for $input:"; cat "$dir/err.txt"; }
done
"$ropecast" info "$dir/ball.rcast" --spacing 1,1,1 > /dev/null 2> "$dir/err.txt" && fail "info of a store with --spacing"
grep -qF -- "--spacing applies to a volume read from its file; the store" "$dir/err.txt" || { fail "no --spacing refusal:"; cat "$dir/err.txt"; }
[ ! -e "$dir/x.png" ] || fail "a refused render left $dir/x.png"

# A file of several volumes (a NIfTI time series of two): the first read, with a warning naming --time; --time
# picks the other; an index past the series, and --time for a store or a single volume, refused.
write_nifti_series "$dir/series.nii" || exit 1
"$ropecast" info "$dir/series.nii" > "$dir/info.txt" 2>&1 || fail "info of a time series"
grep -qF "holds 2 time points: time point 0 of 2 is read; --time T (0 to 1) picks another" "$dir/info.txt" ||
  { fail "info of a time series gave no warning:"; cat "$dir/info.txt"; }
"$ropecast" info "$dir/series.nii" --time 1 --json > "$dir/info.json" || fail "info --json of a time series"
python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); sys.exit(not (j["timePoints"] == 2 and j["timePoint"] == 1 and j["channels"] == 1))' "$dir/info.json" ||
  { fail "info --json gives no time points:"; cat "$dir/info.json"; }
"$ropecast" "${render[@]}" "$dir/series.nii" -o "$dir/t.png" || fail "render of a time series"
cmp -s "$dir/t.png" "$dir/store.png" || fail "a time series' first volume differs from the ball's image"
"$ropecast" "${render[@]}" "$dir/series.nii" --time 1 -o "$dir/t1.png" || fail "render --time 1"
cmp -s "$dir/t1.png" "$dir/store.png" && fail "--time 1 drew the first volume"
"$ropecast" convert "$dir/series.nii" --time 1 -o "$dir/t1.rcast" -q || fail "convert --time 1"
"$ropecast" info "$dir/t1.rcast" | grep -qF "(time point 1 of 2)" || fail "the store does not say its time point"
"$ropecast" "${render[@]}" "$dir/series.nii" --time 2 -o "$dir/x.png" 2> "$dir/err.txt" && fail "--time 2 of 2"
grep -qF -- "--time 2: NIfTI file $dir/series.nii holds 2 time points (--time 0 to 1)" "$dir/err.txt" ||
  { fail "no refusal of --time 2:"; cat "$dir/err.txt"; }
"$ropecast" "${render[@]}" "$dir/ball.rcast" --time 1 -o "$dir/x.png" 2> "$dir/err.txt" && fail "--time with a store"
grep -qF -- "--time applies to a volume read from its file" "$dir/err.txt" || { fail "no --time refusal for a store:"; cat "$dir/err.txt"; }
"$ropecast" "${render[@]}" "$dir/ball_24x20x16_uint16.raw" --channel 1 -o "$dir/x.png" 2> "$dir/err.txt" &&
  fail "--channel 1 of a raw volume"
grep -qF -- "holds 1 channel (--channel 0 alone)" "$dir/err.txt" || { fail "no --channel refusal for a raw file:"; cat "$dir/err.txt"; }
[ ! -e "$dir/x.png" ] || fail "a refused render left $dir/x.png"

# The volume is an input.
sum=$(md5sum < "$dir/ball_24x20x16_uint16.raw")
ln "$dir/ball_24x20x16_uint16.raw" "$dir/hard.png"
"$ropecast" "${render[@]}" "$dir/ball_24x20x16_uint16.raw" -o "$dir/hard.png" 2> "$dir/err.txt" &&
  fail "render wrote onto the volume it read"
grep -qF "refusing to overwrite an input" "$dir/err.txt" || { fail "no refusal:"; cat "$dir/err.txt"; }
[ "$(md5sum < "$dir/ball_24x20x16_uint16.raw")" = "$sum" ] || fail "the volume was changed"

if [ "$failures" -ne 0 ]; then
  echo "volume_inputs.sh: $failures failure(s)"
  exit 1
fi
echo "volume_inputs.sh: all passed"
