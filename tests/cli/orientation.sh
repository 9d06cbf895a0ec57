#!/usr/bin/env bash
# A volume is drawn as its file places it: one whose axes are turned (a sagittal stack: x toward the back, y
# down, z to the right) or mirrored (x to the right) draws the image of the same volume resampled into the
# world's axes, from the same orbit, and --eye/--target and --clip-plane are world points; `info` says where
# the axes point, for the file and for its store (whose x a mirroring volume keeps reversed), and where a file
# that places its first sample places it; extract's NRRDs place their samples as the file did; the viewer's
# probe names the same world point's sample in each, and where the file places that point.
# Usage: bash orientation.sh /path/to/ropecast
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

# W: 20x16x12 in the world's axes (LPS), an off-centre ball and a bar along +x, so that a turn or a mirror
# shows. T: the same samples on sagittal axes, T[i,j,k] = W[19-k, i, 11-j]; M: mirrored, M[i,j,k] = W[19-i, j, k].
python3 - "$dir" <<'PY' || exit 1
import struct, sys
W = (20, 16, 12)
def w(x, y, z):
    ball = max(0.0, 200.0 - 40.0 * ((x - 6) ** 2 + (y - 9) ** 2 + (z - 5) ** 2) ** 0.5)
    bar = 180.0 if x >= 8 and 6 <= y <= 8 and 3 <= z <= 5 else 0.0
    return int(max(ball, bar))
def save(name, dims, value, space_directions):
    samples = bytes(value(i, j, k) for k in range(dims[2]) for j in range(dims[1]) for i in range(dims[0]))
    header = ("NRRD0004\ntype: uchar\ndimension: 3\nspace: left-posterior-superior\nsizes: %d %d %d\n"
              "space directions: %s\nencoding: raw\n\n" % (dims + (space_directions,)))
    open(sys.argv[1] + "/" + name, "wb").write(header.encode() + samples)
save("w.nrrd", W, w, "(1,0,0) (0,1,0) (0,0,1)")
save("t.nrrd", (16, 12, 20), lambda i, j, k: w(19 - k, i, 11 - j), "(0,1,0) (0,0,-1) (-1,0,0)")
save("m.nrrd", W, lambda i, j, k: w(19 - i, j, k), "(-1,0,0) (0,1,0) (0,0,1)")
PY

# Bricks of 8 over axes of different lengths: the trees differ, so full detail (--voxels-per-pixel) for both.
render=(render --size 64x56 --iso 100 --voxels-per-pixel 16 -q)
for v in w t m; do "$ropecast" convert "$dir/$v.nrrd" -o "$dir/$v.rcast" --brick 8 > "$dir/$v.txt" 2>&1 || fail "convert $v"; done
grep -q "^axes" "$dir/w.txt" && fail "convert of an unturned volume speaks of its axes: $(cat "$dir/w.txt")"
grep -qx "axes PIR" "$dir/t.txt" || fail "convert of the turned volume: $(cat "$dir/t.txt")"
grep -qx "axes RPS (mirroring: the store keeps x reversed)" "$dir/m.txt" || fail "convert of the mirrored volume: $(cat "$dir/m.txt")"
for view in "--orbit 30,20,3" "--orbit 200,-35,2.5" "--orbit 115,70,2"; do
  for v in w t m; do
    "$ropecast" "${render[@]}" "$dir/$v.rcast" $view -o "$dir/$v.png" 2> "$dir/err.txt" || fail "render $v $view: $(cat "$dir/err.txt")"
  done
  same "turned axes = the world's ($view)" "$dir/w.png" "$dir/t.png"
  same "mirrored axes = the world's ($view)" "$dir/w.png" "$dir/m.png"
done
# The turn is not a no-op: the sagittal samples drawn as if on the world's axes look otherwise.
sed -i 's/space directions: (0,1,0) (0,0,-1) (-1,0,0)/space directions: (1,0,0) (0,1,0) (0,0,1)/' "$dir/t.nrrd"
"$ropecast" "${render[@]}" "$dir/t.nrrd" --orbit 30,20,3 -o "$dir/t_unturned.png" || fail "render t unturned"
"$ropecast" "${render[@]}" "$dir/w.rcast" --orbit 30,20,3 -o "$dir/w.png" || fail "render w"
if "$ropecast" compare "$dir/w.png" "$dir/t_unturned.png" --min-psnr 40 > /dev/null 2>&1; then
  fail "the sagittal samples on the world's axes draw the world's image: the test shows nothing"
else echo "ok   the turn matters"; fi

# A patient's volume (its space anatomical) is seen by default facing the patient (--orbit -60,20,3); one in no
# patient's frame (scanner-xyz) from the default orbit, 30,20,3.
"$ropecast" info "$dir/w.rcast" | grep -qx "frame      a patient's (LPS): the default view faces the patient" ||
  fail "info of a patient's store: $("$ropecast" info "$dir/w.rcast")"
"$ropecast" "${render[@]}" "$dir/w.rcast" -o "$dir/w_default.png" || fail "render w by default"
"$ropecast" "${render[@]}" "$dir/w.rcast" --orbit -60,20,3 -o "$dir/w_facing.png" || fail "render w facing"
same "a patient's volume by default = --orbit -60,20,3" "$dir/w_default.png" "$dir/w_facing.png"
sed 's/space: left-posterior-superior/space: scanner-xyz/' "$dir/w.nrrd" > "$dir/s.nrrd"
"$ropecast" info "$dir/s.nrrd" | grep -q "^frame" && fail "info of a scanner-xyz volume names a patient's frame"
"$ropecast" "${render[@]}" "$dir/s.nrrd" -o "$dir/s_default.png" || fail "render s by default"
same "a volume in no patient's frame by default = --orbit 30,20,3" "$dir/s_default.png" "$dir/w.png"

# World points: an eye and target, and a clip plane, given in the world draw the same on either volume. The
# turned volume's centre is its own extent's (8,6,10), the world one's (10,8,6): the same world offsets.
"$ropecast" "${render[@]}" "$dir/w.rcast" --eye 40,-20,30 --target 10,8,6 --clip-plane 10,8,6,1,0.3,0 -o "$dir/wp.png" || fail "render w with a plane"
"$ropecast" "${render[@]}" "$dir/t.rcast" --eye 38,-22,34 --target 8,6,10 --clip-plane 8,6,10,1,0.3,0 -o "$dir/tp.png" || fail "render t with a plane"
same "eye, target and clip plane in the world" "$dir/wp.png" "$dir/tp.png"
"$ropecast" "${render[@]}" "$dir/w.rcast" --eye 40,-20,30 --target 10,8,6 -o "$dir/wn.png" || fail "render w without a plane"
if "$ropecast" compare "$dir/wp.png" "$dir/wn.png" --min-psnr 40 > /dev/null 2>&1; then
  fail "the clip plane cut nothing: the test shows nothing"
fi
# --reference (the CPU ray marcher) turns the camera as the GL renderer does.
"$ropecast" render --size 64x56 --iso 100 -q "$dir/t.rcast" --orbit 200,-35,2.5 --reference -o "$dir/tr.png" || fail "render t --reference"
"$ropecast" render --size 64x56 --iso 100 -q "$dir/w.rcast" --orbit 200,-35,2.5 --reference -o "$dir/wr.png" || fail "render w --reference"
same "--reference on turned axes = the world's" "$dir/wr.png" "$dir/tr.png"

# Named views: the sides of the patient in the world (LPS), whatever the file's axes. Left and anterior are
# orbits about +z (eye toward +x; toward -y); superior looks down with anterior (-y) up; a turned volume's
# named view is the world one's.
for v in w t; do
  for view in left anterior superior; do
    "$ropecast" "${render[@]}" "$dir/$v.rcast" --view $view -o "$dir/${v}_$view.png" 2> "$dir/err.txt" ||
      fail "render $v --view $view: $(cat "$dir/err.txt")"
  done
done
"$ropecast" "${render[@]}" "$dir/w.rcast" --orbit 0,0,3 -o "$dir/w_orbit_left.png" || fail "render w --orbit 0,0,3"
"$ropecast" "${render[@]}" "$dir/w.rcast" --orbit -90,0,3 -o "$dir/w_orbit_anterior.png" || fail "render w --orbit -90,0,3"
"$ropecast" "${render[@]}" "$dir/w.rcast" --eye 10,8,$(python3 -c 'print(6 + 3 * 0.5 * (20**2 + 16**2 + 12**2) ** 0.5)') \
  --target 10,8,6 --up 0,-1,0 -o "$dir/w_eye_superior.png" || fail "render w from above"
same "--view left = --orbit 0,0,3" "$dir/w_left.png" "$dir/w_orbit_left.png"
same "--view anterior = --orbit -90,0,3" "$dir/w_anterior.png" "$dir/w_orbit_anterior.png"
same "--view superior = from above, anterior up" "$dir/w_superior.png" "$dir/w_eye_superior.png"
for view in left anterior superior; do same "--view $view of turned axes = the world's" "$dir/w_$view.png" "$dir/t_$view.png"; done
if "$ropecast" compare "$dir/w_left.png" "$dir/w_anterior.png" --min-psnr 40 > /dev/null 2>&1; then
  fail "left and anterior views draw the same image: the test shows nothing"
fi
# A camera path's named views are --view's: a one-keyframe path of each draws the same image.
for view in left superior; do
  printf '[{"view": "%s"}]\n' "$view" > "$dir/path_$view.json"
  "$ropecast" "${render[@]}" "$dir/w.rcast" --path "$dir/path_$view.json" -o "$dir/w_path_$view.png" 2> "$dir/err.txt" ||
    fail "render --path of view $view: $(cat "$dir/err.txt")"
  same "a path's view $view = --view $view" "$dir/w_path_$view.png" "$dir/w_$view.png"
done
"$ropecast" "${render[@]}" "$dir/w.rcast" --view anterior --orbit 0,0,3 -o "$dir/x.png" 2> "$dir/err.txt" &&
  fail "--view with --orbit accepted"
grep -q -- "--orbit excludes --view" "$dir/err.txt" || fail "--view with --orbit: $(cat "$dir/err.txt")"

# --marks draws the orientation marks into the PNGs (-o and --every's), not into the EXR: the data stays the
# render's. (Where each mark lies: tests/tools/image_marks_test.cpp.)
"$ropecast" "${render[@]}" "$dir/w.rcast" --view anterior --marks -o "$dir/wm.png" --exr "$dir/wm.exr" \
  --converge --every 1 || fail "render --marks"
"$ropecast" "${render[@]}" "$dir/w.rcast" --view anterior -o "$dir/wu.png" --exr "$dir/wu.exr" --converge --every 1 ||
  fail "render without marks"
"$ropecast" compare "$dir/wm.exr" "$dir/wu.exr" | grep -q '"psnr_db":"inf"' || fail "--marks changed the EXR"
last=$(cd "$dir" && ls wm_*.png | tail -n 1)  # the converged frame, as -o's: the same without marks
for image in wm.png "$last"; do
  if "$ropecast" compare "$dir/$image" "$dir/${image/wm/wu}" | grep -q '"psnr_db":"inf"'; then
    fail "--marks drew nothing into $image"
  else echo "ok   --marks drew into $image"; fi
done

# info: where the axes point, the file's and its store's.
"$ropecast" info "$dir/m.nrrd" > "$dir/info.txt" || fail "info m.nrrd"
grep -q "^axes       RPS, mirroring: a store keeps x reversed, as LPS$" "$dir/info.txt" || fail "info of the mirrored file: $(grep axes "$dir/info.txt")"
"$ropecast" info "$dir/m.rcast" > "$dir/info.txt" || fail "info m.rcast"
grep -q "^axes       LPS$" "$dir/info.txt" || fail "info of the mirrored file's store: $(grep axes "$dir/info.txt")"
grep -q "x kept reversed: its file's axes mirror (RPS); voxel indices (--crop, extract, the viewer's probe) are the file's" \
  "$dir/info.txt" || fail "info of the mirrored file's store does not say x is kept reversed: $(cat "$dir/info.txt")"

# The mirrored store's voxel indices are its file's: extract gives the file's samples back in its order, a
# level-1 NRRD says where they lie (x toward the right), and --crop's x counts from the file's first sample:
# M's x 2:7 is W's 13:18.
"$ropecast" extract "$dir/m.rcast" -o "$dir/m0.raw" -q || fail "extract m.rcast"
tail -c 3840 "$dir/m.nrrd" | cmp -s - "$dir/m0.raw" || fail "the mirrored store's extract is not its file's samples"
"$ropecast" extract "$dir/m.rcast" --level 1 --crop 1:,2:,: -o "$dir/m1.nrrd" -q || fail "extract m.rcast --level 1"
grep -qx "space directions: (-2,0,0) (0,2,0) (0,0,2)" "$dir/m1.nrrd" --text &&
  grep -qx "space origin: (17,5,1)" "$dir/m1.nrrd" --text ||
  fail "the mirrored store's level-1 NRRD: $(head -c 400 "$dir/m1.nrrd" | tr -c '[:print:]\n' '?')"
"$ropecast" "${render[@]}" "$dir/m.rcast" --crop 2:7,3:9,1:11 -o "$dir/mc.png" || fail "render m --crop"
"$ropecast" "${render[@]}" "$dir/w.rcast" --crop 13:18,3:9,1:11 -o "$dir/wc.png" || fail "render w --crop"
same "the mirrored store's --crop counts the file's x" "$dir/mc.png" "$dir/wc.png"
"$ropecast" info "$dir/t.rcast" --json > "$dir/info.json" || fail "info t.rcast --json"
python3 - "$dir/info.json" <<'PY' || fail "info --json of the turned store: $(cat "$dir/info.json")"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["orientation"] == "PIR", j["orientation"]
assert j["axes"] == [[0, 1, 0], [0, 0, -1], [-1, 0, 0]], j["axes"]
PY

# extract -o X.nrrd: a NRRD that says where its samples lie; converted again, it is the store it came from.
"$ropecast" extract "$dir/t.rcast" -o "$dir/t0.nrrd" -q || fail "extract t.rcast to NRRD"
"$ropecast" info "$dir/t0.nrrd" > "$dir/info.txt" || fail "info t0.nrrd"
grep -q "^axes       PIR$" "$dir/info.txt" && grep -q "^dims       16 x 12 x 20 samples, spacing 1 x 1 x 1$" "$dir/info.txt" ||
  fail "info of the extracted NRRD: $(cat "$dir/info.txt")"
"$ropecast" convert "$dir/t0.nrrd" -o "$dir/t0.rcast" --brick 8 --quiet || fail "convert the extracted NRRD"
"$ropecast" extract "$dir/t0.rcast" -o "$dir/t0_again.raw" -q && "$ropecast" extract "$dir/t.rcast" -o "$dir/t_level0.raw" -q &&
  cmp -s "$dir/t0_again.raw" "$dir/t_level0.raw" || fail "the extracted NRRD's samples are not the store's"
"$ropecast" "${render[@]}" "$dir/t0.rcast" --orbit 30,20,3 -o "$dir/t0.png" || fail "render t0.rcast"
"$ropecast" "${render[@]}" "$dir/t.rcast" --orbit 30,20,3 -o "$dir/t.png" || fail "render t.rcast"
cmp -s "$dir/t0.png" "$dir/t.png" || fail "the extracted NRRD's store draws otherwise than the store it came from"
# Level 1 of the world-axes volume, a box of it: its first sample's centre and its spacing, 2.
"$ropecast" extract "$dir/w.rcast" --level 1 --crop 1:,2:,: -o "$dir/w1.nrrd" -q || fail "extract --level 1 --crop to NRRD"
grep -qx "sizes: 9 6 6" "$dir/w1.nrrd" --text && grep -qx "space directions: (2,0,0) (0,2,0) (0,0,2)" "$dir/w1.nrrd" --text &&
  grep -qx "space origin: (3,5,1)" "$dir/w1.nrrd" --text ||
  fail "the level-1 NRRD's header: $(head -c 400 "$dir/w1.nrrd" | tr -c '[:print:]\n' '?')"

# A file that places its first sample (P: M's samples, its "space origin" the centre of voxel 0, 0, 0): info
# says where, of the file and of its store (which keeps x reversed: its own first sample is the file's last);
# extract's NRRDs place their samples where the file does, so the extracted volume overlays the original in
# another program; converted again, it is placed the same.
sed 's/^space directions: (-1,0,0) (0,1,0) (0,0,1)$/&\nspace origin: (-100.5,50,-20)/' "$dir/m.nrrd" > "$dir/p.nrrd"
"$ropecast" convert "$dir/p.nrrd" -o "$dir/p.rcast" --brick 8 -q || fail "convert p.nrrd"
for input in p.nrrd p.rcast; do
  "$ropecast" info "$dir/$input" > "$dir/info.txt" || fail "info $input"
  grep -qx "origin     -100.5, 50, -20 (the center of voxel 0, 0, 0, in the axes' frame)" "$dir/info.txt" ||
    fail "info of $input does not place voxel 0, 0, 0: $(cat "$dir/info.txt")"
done
"$ropecast" extract "$dir/p.rcast" -o "$dir/p0.nrrd" -q || fail "extract p.rcast"
grep -qx "space directions: (-1,0,0) (0,1,0) (0,0,1)" "$dir/p0.nrrd" --text &&
  grep -qx "space origin: (-100.5,50,-20)" "$dir/p0.nrrd" --text ||
  fail "the placed store's NRRD: $(head -c 400 "$dir/p0.nrrd" | tr -c '[:print:]\n' '?')"
# Level 1, from the file's voxel 2, 4 on: its first sample's centre is level 0's (2.5, 4.5, 0.5).
"$ropecast" extract "$dir/p.rcast" --level 1 --crop 1:,2:,: -o "$dir/p1.nrrd" -q || fail "extract p.rcast --level 1"
grep -qx "space origin: (-103,54.5,-19.5)" "$dir/p1.nrrd" --text ||
  fail "the placed store's level-1 NRRD: $(head -c 400 "$dir/p1.nrrd" | tr -c '[:print:]\n' '?')"
"$ropecast" convert "$dir/p0.nrrd" -o "$dir/p0.rcast" --brick 8 -q && "$ropecast" info "$dir/p0.rcast" > "$dir/info.txt" &&
  grep -qx "origin     -100.5, 50, -20 (the center of voxel 0, 0, 0, in the axes' frame)" "$dir/info.txt" ||
  fail "the extracted NRRD's store is placed otherwise: $(cat "$dir/info.txt")"
# The same as a NIfTI-1 file (an sform in RAS, which mirrors here): placed as its file, the same samples; a
# compressed name is refused, not filled with uncompressed bytes.
"$ropecast" extract "$dir/p.rcast" -o "$dir/p0.nii" -q && "$ropecast" info "$dir/p0.nii" > "$dir/info.txt" &&
  grep -qx "axes       RPS, mirroring: a store keeps x reversed, as LPS" "$dir/info.txt" &&
  grep -qx "origin     -100.5, 50, -20 (the center of voxel 0, 0, 0, in the axes' frame)" "$dir/info.txt" ||
  fail "the placed store's NIfTI file: $(cat "$dir/info.txt")"
"$ropecast" convert "$dir/p0.nii" -o "$dir/p0n.rcast" --brick 8 -q && "$ropecast" extract "$dir/p0n.rcast" -o "$dir/p0n.raw" -q &&
  tail -c 3840 "$dir/p.nrrd" | cmp -s - "$dir/p0n.raw" || fail "the NIfTI file's samples are not its store's file's"
"$ropecast" extract "$dir/p.rcast" -o "$dir/p0.nii.gz" -q 2> "$dir/err.txt" && fail "extract to .nii.gz accepted"
grep -q "extract writes uncompressed files" "$dir/err.txt" && [ ! -e "$dir/p0.nii.gz" ] ||
  fail "extract to .nii.gz: $(cat "$dir/err.txt")"

# The viewer's probe under the same pixels names the same world point in each volume's file's samples: the
# turned volume's T[i,j,k] = W[19-k, i, 11-j], the mirrored one's M[i,j,k] = W[19-i, j, k], each value W's.
if command -v xvfb-run > /dev/null; then
  echo '[{"event": "probe", "pos": [20, 100]}, {"event": "probe", "pos": [40, 80]},
         {"event": "probe", "pos": [80, 60]}, {"event": "probe", "pos": [100, 60]}]' > "$dir/probe.json"
  for v in w t m p; do
    xvfb-run -a -s "-screen 0 320x240x24" "$ropecast" view "$dir/$v.rcast" --size 160x128 --iso 100 \
      --voxels-per-pixel 16 --orbit 30,20,1.6 --script "$dir/probe.json" > "$dir/probe_$v.txt" 2> "$dir/err.txt" ||
      fail "view $v with probes: $(cat "$dir/err.txt")"
  done
  voxels() { sed -n 's/.*: voxel \([0-9]*\), \([0-9]*\), \([0-9]*\)  value \([^ ]*\)  at .*$/\1 \2 \3 \4/p' "$1"; }
  [ "$(voxels "$dir/probe_w.txt" | wc -l)" = 4 ] || fail "probes of w: $(cat "$dir/probe_w.txt")"
  [ "$(voxels "$dir/probe_t.txt" | awk '{ print 19 - $3, $1, 11 - $2, $4 }')" = "$(voxels "$dir/probe_w.txt")" ] ||
    fail "the turned volume's probes are not the world one's samples: $(paste "$dir/probe_t.txt" "$dir/probe_w.txt")"
  [ "$(voxels "$dir/probe_m.txt" | awk '{ print 19 - $1, $2, $3, $4 }')" = "$(voxels "$dir/probe_w.txt")" ] ||
    fail "the mirrored volume's probes are not the world one's samples: $(paste "$dir/probe_m.txt" "$dir/probe_w.txt")"
  # P is M placed: the same voxels, and each point also in the file's frame, the world's moved by the offset
  # of their placements (store origin (-119.5, 50, -20) less the world's sample 0 at 0.5, 0.5, 0.5).
  [ "$(voxels "$dir/probe_p.txt")" = "$(voxels "$dir/probe_m.txt")" ] ||
    fail "the placed volume's probes are not the mirrored one's: $(paste "$dir/probe_p.txt" "$dir/probe_m.txt")"
  sed -n 's/.*  at \([^,]*\), \([^,]*\), \([^ ]*\)  file \([^,]*\), \([^,]*\), \(.*\)$/\1 \2 \3 \4 \5 \6/p' "$dir/probe_p.txt" |
    awk 'function off(a, b, d) { return (a + d - b) ^ 2 } { n++; if (off($1, $4, -120) + off($2, $5, 49.5) + off($3, $6, -20.5) > 1e-6) bad++ }
         END { exit !(n == 4 && !bad) }' ||
    fail "the placed volume's probes do not give the file's frame: $(cat "$dir/probe_p.txt")"
  grep -q "  file " "$dir/probe_m.txt" && fail "a volume placed nowhere names a point in a file's frame: $(cat "$dir/probe_m.txt")"
else
  echo "skip: the viewer's probe (xvfb-run is not installed)"
fi

echo "$failures failure(s)"
[ "$failures" -eq 0 ]
