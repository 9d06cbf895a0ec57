#!/usr/bin/env bash
# Isosurface caps (docs/RENDERING.md "Caps"): where --crop or --clip-plane cuts an isosurface, it is closed by
# the cut's face, by every renderer alike (the octree's single pass, multi-pass, brute force, the CPU
# reference, progressive frames with occlusion queries and feedback); the leaves wholly inside it are capped
# without a brick (leaves_solid); --caps off leaves it open as before; DVR and MIP ignore it with a warning.
# Usage: bash caps.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
same() {  # same NAME A.png B.png: at least 40 dB apart
  if "$ropecast" compare "$2" "$3" --min-psnr 40 > "$dir/cmp.txt" 2>&1; then echo "ok   $1"
  else fail "$1: $(cat "$dir/cmp.txt")"; fi
}
differ() {  # differ NAME A.png B.png: below 30 dB (compare exits 3)
  "$ropecast" compare "$2" "$3" --min-psnr 30 > "$dir/cmp.txt" 2>&1
  if [ $? -eq 3 ]; then echo "ok   $1"; else fail "$1: $(cat "$dir/cmp.txt")"; fi
}
render() {  # render INPUT OPTIONS...
  "$ropecast" render "$1" --size 96x96 "${@:2}" 2> "$dir/err.txt" || fail "render $*: $(cat "$dir/err.txt")"
}

# A cube cut from the middle of a ball (bricks of 8: the leaves inside it are wholly inside the surface).
sphere=(procedural:sphere:64 --brick 8)
cube=(--crop 24:40,24:40,28:44)
render "${sphere[@]}" "${cube[@]}" -o "$dir/cube.png" --stats "$dir/cube.jsonl"
render "${sphere[@]}" "${cube[@]}" --caps off -o "$dir/cube_open.png"
render "${sphere[@]}" "${cube[@]}" --reference -o "$dir/cube_ref.png"
render "${sphere[@]}" "${cube[@]}" --caps off --reference -o "$dir/cube_open_ref.png"
render "${sphere[@]}" "${cube[@]}" --backend multipass -o "$dir/cube_multipass.png"
render "${sphere[@]}" "${cube[@]}" --backend compute -o "$dir/cube_compute.png"
render "${sphere[@]}" "${cube[@]}" --backend brute -o "$dir/cube_brute.png"
render "${sphere[@]}" "${cube[@]}" --converge -o "$dir/cube_converge.png" --stats "$dir/converge.jsonl"
same "caps: the octree's image is the reference's" "$dir/cube.png" "$dir/cube_ref.png"
same "caps off: the octree's image is the reference's" "$dir/cube_open.png" "$dir/cube_open_ref.png"
same "caps: multi-pass" "$dir/cube.png" "$dir/cube_multipass.png"
same "caps: the compute entry point" "$dir/cube.png" "$dir/cube_compute.png"
same "caps: brute force" "$dir/cube.png" "$dir/cube_brute.png"
same "caps: --converge" "$dir/cube.png" "$dir/cube_converge.png"
differ "caps off opens the surface" "$dir/cube.png" "$dir/cube_open.png"
solid=$(grep -o '"leaves_solid":[0-9]*' "$dir/cube.jsonl" | cut -d: -f2)
[ "${solid:-0}" -gt 0 ] && echo "ok   leaves_solid $solid" || fail "no solid leaves: $(cat "$dir/cube.jsonl")"
# The converged frame, kept rather than drawn again, counts its cut's solid leaves too.
tail -n 1 "$dir/converge.jsonl" | grep -q "\"leaves_solid\":$solid," && echo "ok   leaves_solid of the converged frame" ||
  fail "leaves_solid of the converged frame: $(tail -n 1 "$dir/converge.jsonl")"
render "${sphere[@]}" "${cube[@]}" --caps off --stats "$dir/open.jsonl" -o "$dir/x.png"
grep -q '"leaves_solid":0' "$dir/open.jsonl" && echo "ok   no solid leaves without caps" ||
  fail "solid leaves without caps: $(cat "$dir/open.jsonl")"

# A clip plane through an oblique noise surface; crop faces on the volume's own boundary (no cut there).
noise=(procedural:noise:48 --clip-plane 24,24,24,-1,-0.6,0.3)
render "${noise[@]}" -o "$dir/plane.png"
render "${noise[@]}" --reference -o "$dir/plane_ref.png"
render "${noise[@]}" --caps off -o "$dir/plane_open.png"
same "caps on a clip plane: the reference's" "$dir/plane.png" "$dir/plane_ref.png"
differ "caps off opens the plane's cut" "$dir/plane.png" "$dir/plane_open.png"
# (At this isovalue the ball is larger than the volume: open where the volume's faces cut it.)
render procedural:sphere:64 --iso 60 --crop 0:64,:,0:64 -o "$dir/whole.png"
render procedural:sphere:64 --iso 60 --crop 0:64,:,0:64 --caps off -o "$dir/whole_open.png"
"$ropecast" compare "$dir/whole.png" "$dir/whole_open.png" | grep -q '"max_abs":0.0,' &&
  echo "ok   the volume's own faces are no cut" || fail "caps on the volume's own faces"

# Refusals and warnings.
if "$ropecast" render procedural:sphere:32 --caps maybe -o "$dir/bad.png" 2> "$dir/err.txt"; then
  fail "--caps maybe accepted"
elif grep -q -- "--caps" "$dir/err.txt" && [ ! -e "$dir/bad.png" ]; then echo "ok   --caps maybe refused"
else fail "--caps maybe: $(cat "$dir/err.txt")"; fi
"$ropecast" render procedural:sphere:32 --size 32x32 --mode dvr --caps off -o "$dir/dvr.png" 2> "$dir/err.txt"
grep -q "warning: --caps: no effect with --mode dvr" "$dir/err.txt" && echo "ok   --caps with dvr warns" ||
  fail "--caps with dvr: $(cat "$dir/err.txt")"

[ "$failures" -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "caps: all passed"
