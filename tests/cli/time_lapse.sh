#!/usr/bin/env bash
# `ropecast render --times`: each time point of a series rendered as `render --time T` renders it, to numbered
# outputs (PNG, EXR, depth), one --stats file whose lines say their time point; a gzip-compressed series alike;
# the range's forms and its refusals (past the series, an input of one time point, with --time or --every, not a
# range); a time point that fails leaves no output of the others.
# Usage: bash time_lapse.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
# shellcheck source=tests/cli/lib/nifti_series.sh
source "$(dirname "$0")/lib/nifti_series.sh"
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
run() {  # run NAME COMMAND...: must exit 0
  local name="$1"; shift
  if "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then echo "ok   $name"; else fail "$name: exit $?: $(cat "$dir/err.txt")"; fi
}
refused() {  # refused NAME MESSAGE COMMAND...: must exit non-zero, saying MESSAGE
  local name="$1" message="$2"; shift 2
  if "$@" > /dev/null 2> "$dir/err.txt"; then fail "$name: exit 0"
  elif grep -qF -- "$message" "$dir/err.txt"; then echo "ok   $name"
  else fail "$name: expected '$message' in: $(cat "$dir/err.txt")"; fi
}
identical() {  # identical NAME A B
  if cmp -s "$2" "$3"; then echo "ok   $1"; else fail "$1: $2 and $3 differ"; fi
}

write_nifti_series "$dir/series.nii" || exit 1
view=(--size 64x64 --iso 1500)
run "render --time 0" "$ropecast" render "$dir/series.nii" "${view[@]}" -o "$dir/t0.png" --exr "$dir/t0.exr"
run "render --time 1" "$ropecast" render "$dir/series.nii" "${view[@]}" --time 1 -o "$dir/t1.png" --exr "$dir/t1.exr"
cmp -s "$dir/t0.png" "$dir/t1.png" && fail "the two time points drew the same image"

run "--times :" "$ropecast" render "$dir/series.nii" "${view[@]}" --times : -o "$dir/lapse.png" \
  --exr "$dir/lapse.exr" --depth "$dir/depth.exr" --stats "$dir/lapse.jsonl"
identical "time point 0 = render --time 0" "$dir/lapse_0000.png" "$dir/t0.png"
identical "time point 1 = render --time 1" "$dir/lapse_0001.png" "$dir/t1.png"
d=$("$ropecast" compare "$dir/lapse_0001.exr" "$dir/t1.exr") && grep -q '"max_abs":0.0,' <<< "$d" ||
  fail "time point 1's EXR differs from render --time 1's: $d"
for f in depth_0000.exr depth_0001.exr; do [ -s "$dir/$f" ] || fail "missing output $f"; done
[ ! -e "$dir/lapse.png" ] || fail "--times wrote -o's own name too"
points=$(python3 -c 'import json, sys; print(" ".join(str(json.loads(l)["time_point"]) for l in open(sys.argv[1])))' \
  "$dir/lapse.jsonl")
[ "$points" = "0 1" ] || fail "--stats time points: '$points', expected '0 1'"
grep -qF "time points 0 to 1 of $dir/series.nii" "$dir/err.txt" || fail "no line saying the range: $(cat "$dir/err.txt")"

# The range's other forms name the same time points.
run "--times 1:" "$ropecast" render "$dir/series.nii" "${view[@]}" --times 1: -o "$dir/from1.png"
identical "--times 1: = render --time 1" "$dir/from1_0001.png" "$dir/t1.png"
[ ! -e "$dir/from1_0000.png" ] || fail "--times 1: rendered time point 0"
run "--times :1" "$ropecast" render "$dir/series.nii" "${view[@]}" --times :1 -o "$dir/to1.png"
identical "--times :1 = render --time 0" "$dir/to1_0000.png" "$dir/t0.png"
[ ! -e "$dir/to1_0001.png" ] || fail "--times :1 rendered time point 1"

# A gzip-compressed series: the second time point read through the first's access points, the same images.
gzip -c "$dir/series.nii" > "$dir/series.nii.gz"
run "--times : of a .nii.gz" "$ropecast" render "$dir/series.nii.gz" "${view[@]}" --times : -o "$dir/gz.png"
identical "gzip time point 0" "$dir/gz_0000.png" "$dir/t0.png"
identical "gzip time point 1" "$dir/gz_0001.png" "$dir/t1.png"

refused "past the series" "--times 0:3: the input $dir/series.nii holds 2 time points (0 to 1)" \
  "$ropecast" render "$dir/series.nii" --times 0:3 -o "$dir/x.png"
refused "empty range" "--times 1:1: expected A:B, A:, :B or :" \
  "$ropecast" render "$dir/series.nii" --times 1:1 -o "$dir/x.png"
refused "not a range" "--times 1-2: expected A:B, A:, :B or :" \
  "$ropecast" render "$dir/series.nii" --times 1-2 -o "$dir/x.png"
refused "a procedural input" "holds one time point (it is generated)" \
  "$ropecast" render procedural:sphere:32 --times : -o "$dir/x.png"
refused "with --time" "--time excludes --times" \
  "$ropecast" render "$dir/series.nii" --times : --time 1 -o "$dir/x.png"
refused "with --every" "leave one of them out" \
  "$ropecast" render "$dir/series.nii" --times : --every 2 --converge -o "$dir/x.png"
refused "--stats that is the input" "the same file as the input" \
  "$ropecast" render "$dir/series.nii" --times : -o "$dir/x.png" --stats "$dir/series.nii"

# A series cut inside its second volume: time point 0 renders, 1 fails, and nothing of either is left.
head -c "$(($(stat -c %s "$dir/series.nii") - 100))" "$dir/series.nii" > "$dir/cut.nii"
refused "a time point that fails" "truncated" "$ropecast" render "$dir/cut.nii" "${view[@]}" --times : \
  -o "$dir/cut.png" --stats "$dir/cut.jsonl"
leftover=$(find "$dir" -name 'cut_*' -o -name 'cut.jsonl*' -o -name '.*' -newer "$dir/cut.nii" | head -n 3)
[ -z "$leftover" ] || fail "a failed time-lapse left: $leftover"

[ "$failures" -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "all time-lapse tests passed"
