#!/usr/bin/env bash
# No command overwrites what it reads: every output option of convert, render, extract and bench modes (regress's
# in regress.sh) aimed at an input (by its name, a symlink or a hard link; a file of an input folder or glob) or
# at another output of the same run fails with 1..127 and a message naming both, writes nothing and leaves the
# inputs as they were; so does an output that names a folder, a FIFO or a device, and an input that is a FIFO.
# Usage: bash output_guard.sh /path/to/ropecast
set -uo pipefail
ropecast="$(realpath "$1")"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

# Fingerprint of the folder: every name with its content's checksum (links as links).
# (One md5sum for all files: a shell per file made this check most of the script's time.)
fingerprint() { (cd "$dir" && {
  find . -path ./err.txt -prune -o -type l -printf '%p -> %l\n' -o ! -type f -printf '%p/\n'
  find . -path ./err.txt -prune -o -type f -print0 | xargs -0 -r md5sum; } | LC_ALL=C sort); }

# refused NAME PATTERN1 PATTERN2 COMMAND...: exit 1..127, stderr names both patterns, the folder unchanged.
refused() {
  local name="$1" first="$2" second="$3"
  shift 3
  local before after rc
  before=$(fingerprint)
  "$@" > /dev/null 2> "$dir/err.txt"
  rc=$?
  after=$(fingerprint)
  if [ "$rc" -lt 1 ] || [ "$rc" -gt 127 ]; then fail "$name: exit $rc"; return; fi
  if ! grep -qF -- "$first" "$dir/err.txt" || ! grep -qF -- "$second" "$dir/err.txt"; then
    fail "$name: stderr does not name '$first' and '$second': $(cat "$dir/err.txt")"; return
  fi
  if [ "$before" != "$after" ]; then fail "$name: the folder changed: $(diff <(echo "$before") <(echo "$after"))"; return; fi
  echo "ok   $name (exit $rc): $(head -c 200 "$dir/err.txt" | tr '\n' ' ')"
}

cd "$dir" || exit 1
head -c $((8 * 8 * 8)) /dev/urandom > scan_8x8x8_uint8.raw
"$ropecast" convert scan_8x8x8_uint8.raw --brick 8 -o s.rcast --quiet || fail "convert for the setup"
ln -s scan_8x8x8_uint8.raw scan_link.raw
ln scan_8x8x8_uint8.raw scan_hard.raw
ln -s s.rcast s_link.png
ln s.rcast s_hard.exr
ln s.rcast out_0003.png
mkdir slices
printf 'a' > slices/s0.png
printf 'b' > slices/s1.png
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 8 8 8\nencoding: raw\ndata file: scan_8x8x8_uint8.raw\n' > v.nhdr
printf 'NDims = 3\nDimSize = 8 8 8\nElementType = MET_UCHAR\nElementDataFile = scan_8x8x8_uint8.raw\n' > v.mhd
for z in 1 2; do head -c 64 /dev/urandom > "slice$z.raw"; done
printf 'NDims = 3\nDimSize = 8 8 2\nElementType = MET_UCHAR\nElementDataFile = slice%%d.raw 1 2 1\n' > listed.mhd
printf '{"points": [[0, 0, 0, 0, 0], [255, 1, 1, 1, 1]]}' > tf.json
printf '[{"orbit": [0, 20, 3]}, {"orbit": [90, 20, 2.5]}]' > path.json

# convert -o: the input, a symlink and a hard link to it, a slice of an input folder or glob, NRRD and MetaImage
# detached data.
refused "convert -o input" "-o scan_8x8x8_uint8.raw" "the input scan_8x8x8_uint8.raw" \
  "$ropecast" convert scan_8x8x8_uint8.raw -o scan_8x8x8_uint8.raw
refused "convert -o symlink" "-o scan_link.raw" "the input scan_8x8x8_uint8.raw" \
  "$ropecast" convert scan_8x8x8_uint8.raw -o scan_link.raw
refused "convert -o hard link" "-o scan_hard.raw" "the input" \
  "$ropecast" convert scan_8x8x8_uint8.raw -o scan_hard.raw
refused "convert -o slice of folder" "-o slices/s1.png" "the input slices" \
  "$ropecast" convert slices -o slices/s1.png
refused "convert -o slice of glob" "-o slices/s0.png" "the input slices/s0.png" \
  "$ropecast" convert 'slices/s*.png' -o slices/s0.png
refused "convert -o NRRD data file" "-o scan_hard.raw" "the input" "$ropecast" convert v.nhdr -o scan_hard.raw
refused "convert -o MetaImage data file" "-o scan_hard.raw" "the input" "$ropecast" convert v.mhd -o scan_hard.raw
refused "convert -o a MetaImage slice's file" "-o slice2.raw" "the input" "$ropecast" convert listed.mhd -o slice2.raw
# A header longer than 64 KiB (comments) still names its data file to the guard as it does to the source.
{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 8 8 8\nencoding: raw\n'
  for _ in $(seq 1 2000); do printf '# a comment line of some length, repeated to pass 64 KiB of header\n'; done
  printf 'data file: scan_8x8x8_uint8.raw\n'; } > long.nhdr
refused "convert -o NRRD data file (long header)" "-o scan_8x8x8_uint8.raw" "the input" \
  "$ropecast" convert long.nhdr -o scan_8x8x8_uint8.raw

# render: each output option onto the store, --tf and --path files, and two outputs on one file.
refused "render -o symlink" "-o s_link.png" "the input s.rcast" "$ropecast" render s.rcast -o s_link.png
refused "render --exr hard link" "--exr s_hard.exr" "the input s.rcast" \
  "$ropecast" render s.rcast -o a.png --exr s_hard.exr
refused "render --depth hard link" "--depth s_hard.exr" "the input s.rcast" \
  "$ropecast" render s.rcast -o a.png --depth s_hard.exr
refused "render --stats input" "--stats s.rcast" "the input s.rcast" "$ropecast" render s.rcast -o a.png --stats s.rcast
refused "render --stats --tf file" "--stats tf.json" "--tf tf.json" \
  "$ropecast" render s.rcast --mode dvr --tf tf.json -o a.png --stats tf.json
refused "render --stats --path file" "--stats path.json" "--path path.json" \
  "$ropecast" render s.rcast --path path.json --frames 2 -o a.png --stats path.json
refused "render --every onto a hard link" "--every ./out_NNNN.png would write" "the input s.rcast" \
  "$ropecast" render s.rcast -o out.png --frames 5 --every 1
refused "render --exr and --depth" "--exr a.exr" "--depth a.exr" \
  "$ropecast" render s.rcast -o a.png --exr a.exr --depth a.exr
refused "render --stats a folder" "--stats slices" "a folder" "$ropecast" render s.rcast -o a.png --stats slices
refused "convert -o a folder" "-o slices" "a folder" "$ropecast" convert scan_8x8x8_uint8.raw -o slices
refused "render --stats onto a --every frame" "--every" "--stats b_0002.png" \
  "$ropecast" render s.rcast -o b.png --frames 5 --every 1 --stats b_0002.png

# extract -o: the store by name, symlink and hard link.
refused "extract -o input" "-o s.rcast" "the store s.rcast" "$ropecast" extract s.rcast -o s.rcast
refused "extract -o symlink" "-o s_link.png" "the store s.rcast" "$ropecast" extract s.rcast -o s_link.png
refused "extract -o hard link" "-o s_hard.exr" "the store s.rcast" "$ropecast" extract s.rcast -o s_hard.exr

# bench modes --out DIR: its files there onto --tf or the input.
mkdir -p bm/images && cp tf.json bm/bench.json && cp s.rcast bm/images/s.rcast
refused "bench modes --out onto --tf" "--out bm/bench.json" "--tf bm/bench.json" \
  "$ropecast" bench modes s.rcast --mode dvr --tf bm/bench.json --out bm --frames 1 --reps 1 --no-plot
refused "bench modes --out images onto the input" "bm/images/s.rcast" "the input bm/images/s.rcast" \
  "$ropecast" bench modes bm/images/s.rcast --out bm --frames 1 --reps 1 --no-plot

# Outputs that are not files (a FIFO, a link to a device) are refused, not replaced by a file; inputs that are
# not files are refused, not waited on (opening a FIFO blocks until a writer comes).
mkfifo fifo
ln -s /dev/null to_null.json
refused "render --stats onto a FIFO" "--stats fifo" "not a regular file" \
  timeout 20 "$ropecast" render procedural:sphere:16 --size 16x16 -o a.png --stats fifo
refused "render --stats onto a link to /dev/null" "--stats to_null.json" "under /dev" \
  timeout 20 "$ropecast" render procedural:sphere:16 --size 16x16 -o a.png --stats to_null.json
for args in "render fifo -o a.png" "render procedural:sphere:16 --tf fifo -o a.png" \
  "render procedural:sphere:16 --path fifo -o a.png" "info fifo" "convert fifo -o fifo.rcast" "compare fifo fifo" \
  "regress fifo"; do
  # shellcheck disable=SC2086  # $args is a command line
  refused "$args: a FIFO input" "fifo" "not a regular file" timeout 20 "$ropecast" $args
done
rm fifo to_null.json
# An output that is a link to a file is written where the link leads; the link stays.
ln -s linked_target.json linked.json
if "$ropecast" render procedural:sphere:16 --size 16x16 -o linked.png --stats linked.json 2> "$dir/err.txt" &&
  [ -L linked.json ] && [ -s linked_target.json ]; then
  echo "ok   --stats through a link: the link stays, its target written"
else
  fail "--stats through a link: $(ls -l linked.json linked_target.json 2>&1) $(cat "$dir/err.txt")"
fi

# Other names are fine: the guard lets ordinary runs through.
"$ropecast" extract s.rcast -o level0.raw --quiet && cmp level0.raw scan_8x8x8_uint8.raw && echo "ok   extract to a new file" ||
  fail "extract to a new file"

[ "$failures" -eq 0 ] && echo "all ok" || echo "$failures failure(s)"
[ "$failures" -eq 0 ]
