#!/usr/bin/env bash
# Bad input for `ropecast render`: an exit code in 1..127, a message naming the file or option, no output left.
# Usage: bash render_errors.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
failures=0

# expect_failure NAME PATTERN ARGS...: `ropecast render ARGS -o $dir/x.png` must fail with 1..127, print PATTERN
# on stderr and leave no x.png, no x_NNNN.png of --every, nor a temporary of either.
expect_failure() {
  local name="$1" pattern="$2"
  shift 2
  # Bad input must never hang (a ray caster fed rays that are not finite can spin forever).
  timeout 120 "$ropecast" render "$@" -o "$dir/x.png" > "$dir/out.txt" 2> "$dir/err.txt"
  rc=$?
  if [ "$rc" = 124 ]; then
    echo "FAIL $name: still running after 120 s"; failures=$((failures + 1)); return
  fi
  if [ "$rc" -lt 1 ] || [ "$rc" -gt 127 ]; then
    echo "FAIL $name: exit code $rc"; failures=$((failures + 1)); return
  fi
  if ! grep -qF -- "$pattern" "$dir/err.txt"; then
    echo "FAIL $name: stderr does not name '$pattern':"; cat "$dir/err.txt"; failures=$((failures + 1)); return
  fi
  if [ -n "$(find "$dir" -name 'x*.png*')" ]; then
    echo "FAIL $name: left $(find "$dir" -name 'x*.png*')"; failures=$((failures + 1)); return
  fi
  echo "ok   $name (exit $rc): $(head -c 160 "$dir/err.txt" | tr '\n' ' ')"
}
# expect_usage NAME PATTERN ARGS...: as expect_failure, and the exit status is 2 (a usage error: README.md).
expect_usage() {
  local before=$failures
  expect_failure "$@"
  [ "$failures" != "$before" ] || [ "$rc" = 2 ] || { echo "FAIL $1: exit $rc, a usage error exits 2"; failures=$((failures + 1)); }
}

vol="procedural:sphere:32"
printf 'not a store at all' > "$dir/bogus.rcast"
printf '{"points": [[0, 0, 0, 0]]}' > "$dir/short_point.json"
printf '{"points": ' > "$dir/truncated.json"
printf '[{"eye": [1, 2]}]' > "$dir/bad_path.json"
printf '[{"eye": [0, 0, 0], "target": [1, 1, 1], "up": [2, 2, 2]}]' > "$dir/parallel_up_path.json"
# Eye and target trade places: they meet halfway, at frame 1 of 3.
printf '[{"eye": [0, -50, 16], "target": [0, 50, 16]}, {"eye": [0, 50, 16], "target": [0, -50, 16]}]' \
  > "$dir/crossing_path.json"

expect_failure "missing store" "$dir/none.rcast" "$dir/none.rcast"
expect_failure "not a store" "$dir/bogus.rcast" "$dir/bogus.rcast"
expect_usage "unknown procedural" "bogus" procedural:bogus:32
expect_usage "procedural size out of range" "bad SIZE '0'" procedural:sphere:0
expect_usage "bad size" "--size" "$vol" --size 0x4
expect_usage "--tf-range LO = HI" "--tf-range 100,100: expected LO,HI with LO < HI" "$vol" --mode mip --tf-range 100,100
expect_usage "--tf-range of one number" "--tf-range" "$vol" --mode mip --tf-range 100
expect_usage "size not WxH" "--size" "$vol" --size 512
expect_usage "bad mode" "--mode" "$vol" --mode foo
expect_usage "bad backend" "--backend: expected auto, fragment, compute, brute or multipass, got 'vulkan'" "$vol" --backend vulkan
expect_failure "backend by number" "--backend: expected auto, fragment, compute, brute or multipass, got '1'" "$vol" --backend 1
expect_usage "bad brute stage" "--brute-stage: expected auto, fragment or compute, got 'vertex'" "$vol" --backend brute \
  --brute-stage vertex
expect_usage "brute stage without brute force" "--brute-stage compute applies to --backend brute" "$vol" \
  --brute-stage compute
expect_usage "brute stage with the octree ray caster" "--brute-stage fragment applies to --backend brute" "$vol" \
  --backend compute --brute-stage fragment
expect_usage "bad gradients" "--gradients" "$vol" --gradients sobel
expect_usage "no I/O thread" "--io-threads: expected an integer in [1, 256], got '0'" "$vol" --io-threads 0
expect_usage "I/O threads not a number" "--io-threads: expected an integer in [1, 256], got 'many'" "$vol" --io-threads many
expect_usage "negative target frame time" "--target-frame-ms" "$vol" --target-frame-ms -5
expect_usage "no frame for --converge" "--max-frames" "$vol" --converge --max-frames 0
# Options that would be ignored are refused: one camera, a frame cap and frame files only where they apply.
expect_usage "orbit and eye" "--orbit excludes --eye" "$vol" --orbit 10,10,3 --eye 0,0,200 --target 1,1,1
expect_usage "orbit and up" "--orbit excludes --up" "$vol" --orbit 10,10,3 --up 0,1,0
expect_usage "path and orbit" "excludes --path" "$vol" --path "$dir/bad_path.json" --orbit 10,10,3
for option in --exr --depth --stats --tf --path; do
  expect_usage "empty $option" "$option: expected a" "$vol" "$option" ""
done
expect_usage "path and fov" "excludes --path" "$vol" --path "$dir/bad_path.json" --fov 10
expect_usage "frame cap without --converge" "--max-frames requires --converge" "$vol" --max-frames 3
expect_usage "empty input" "the input: expected a store file (.rcast), a volume or procedural:NAME:SIZE, got ''" ""
expect_usage "crop not three ranges" "--crop" "$vol" --crop 0:8,0:8
expect_usage "crop range without a colon" "--crop: expected a range of voxels A:B with A < B" "$vol" --crop 8,:,:
expect_usage "crop range reversed" "got '9:3'" "$vol" --crop :,9:3,:
expect_usage "crop range empty" "got '4:4'" "$vol" --crop 4:4,:,:
expect_usage "crop range negative" "got '-2:8'" "$vol" --crop -2:8,:,:
expect_usage "crop past the volume" "--crop: the z range 10:33 does not lie in the volume's voxels 0:32 along z (32x32x32)" \
  "$vol" --crop :,:,10:33
expect_usage "clip plane of five numbers" "--clip-plane" "$vol" --clip-plane 1,2,3,0,1
expect_usage "clip plane not numbers" "--clip-plane" "$vol" --clip-plane 1,2,3,0,1,x
expect_usage "clip plane too far out" "--clip-plane: expected six numbers within +-1e15, got 1e+300,0,0,1,-1,0" "$vol" --clip-plane 1e300,0,0,1,-1,0
expect_usage "clip plane without a normal" "--clip-plane: the normal 0,0,0 has no direction" "$vol" --clip-plane 16,16,16,0,0,0
expect_usage "--slice of no axis" "--slice w:3: expected AXIS:INDEX, AXIS x, y or z" "$vol" --slice w:3
expect_usage "--slice without an index" "--slice z: expected AXIS:INDEX" "$vol" --slice z
expect_usage "--slice between voxels" "--slice z:1.5: expected AXIS:INDEX" "$vol" --slice z:1.5
expect_usage "--slice past the volume" "--slice z:32: the volume has 32 voxels along z, 0 to 31" "$vol" --slice z:32
expect_usage "--slice outside --crop" "--slice y:3 lies outside --crop, which keeps voxels 10 to 19 along y" "$vol" \
  --slice y:3 --crop :,10:20,:
expect_usage "--slice with another mode" "--slice z:3 shows a slice, and --mode dvr draws something else" "$vol" \
  --slice z:3 --mode dvr
expect_usage "--slab without a plane" "--slab 4 is about a plane: give --clip-plane or --slice" "$vol" --mode mip \
  --slab 4
expect_usage "--slab of a slice" "--slab 4: a slice has no thickness" "$vol" --slice z:3 --slab 4
expect_usage "--slab of zero" "--slab" "$vol" --mode mip --slice z:3 --slab 0
expect_usage "--slice and --clip-plane" "--slice and --clip-plane both give the slice's plane" "$vol" --slice z:3 \
  --clip-plane 1,1,1,0,0,1
expect_usage "crop starting past the volume" "--crop: the x range 32: does not lie" "$vol" --crop 32:,:,:
expect_usage "background out of range" "--background: expected a finite number in [0, 1]" "$vol" --background -1,5,0.5
expect_usage "iso color out of range" "--iso-color: expected a finite number in [0, 1], got '2'" "$vol" --iso-color 1,2,0
expect_usage "material of three numbers" "--material" "$vol" --material 0.1,0.5,0.5
expect_usage "material weight past 1" "--material: KD must lie in [0, 1], got 1.5" "$vol" --material 0.1,1.5,0.5,8
expect_usage "material shininess below 1" "--material: SHININESS must lie in [1, 1024], got 0.5" "$vol" --material 0.1,0.5,0.5,0.5
expect_usage "shading neither on nor off" "--shading" "$vol" --shading maybe
expect_usage "every zero" "--every" "$vol" --every 0 --frames 3
expect_usage "every with the reference" "--every has nothing to do with --reference" "$vol" --reference --every 1 --frames 3
expect_usage "frame files of one frame" "--every 2 writes frames of a progressive render" "$vol" --every 2
expect_usage "CPU reference and a GPU backend" "excludes --reference" "$vol" --reference --backend compute
"$ropecast" convert procedural:sphere:16 -o "$dir/s16.rcast" --quiet || { echo "FAIL convert for the setup"; failures=$((failures + 1)); }
expect_usage "brick size of a store" "--brick 8 applies to procedural inputs" "$dir/s16.rcast" --brick 8
expect_usage "stats of the CPU reference" "--stats has nothing to record with --reference" "$vol" --reference \
  --stats "$dir/ref.jsonl"
expect_usage "eye without target" "--eye and --target go together" "$vol" --eye 0,0,200
expect_usage "orbit of no distance" "--orbit: the distance must be positive" "$vol" --orbit 10,10,0
[ ! -e "$dir/ref.jsonl" ] || { echo "FAIL stats of the CPU reference: wrote ref.jsonl"; failures=$((failures + 1)); }
# CLI11's own range check lets NaN through; a NaN opacity or isovalue must not reach the renderer.
expect_failure "NaN early termination" "--ert: expected a finite number in (0, 1], got 'nan'" "$vol" --ert nan
expect_failure "early termination at opacity 0" "--ert: expected a finite number in (0, 1], got '0'" "$vol" --ert 0
expect_failure "NaN isovalue" "--iso: expected a finite number, got 'nan'" "$vol" --iso nan
expect_failure "NaN field of view" "--fov: expected a finite number in [1, 179]" "$vol" --fov nan
expect_failure "unknown tf preset" "--tf" "$vol" --mode dvr --tf nopreset
expect_failure "tf point not 5 numbers" "short_point.json" "$vol" --mode dvr --tf "$dir/short_point.json"
expect_failure "tf not JSON" "truncated.json" "$vol" --mode dvr --tf "$dir/truncated.json"
expect_failure "tf typo in iso mode" "--tf" "$vol" --mode iso --tf "$dir/none.json"
expect_failure "orbit needs 3 numbers" "--orbit" "$vol" --orbit 1,2
expect_failure "eye equals target" "--eye" "$vol" --eye 1,1,1 --target 1,1,1
expect_failure "up parallel to the view" "--up 1,1,1: up is parallel" "$vol" --eye 0,0,0 --target 1,1,1 --up 1,1,1
expect_failure "zero up" "--up 0,0,0: up is the zero vector" "$vol" --eye 1,2,3 --target 0,0,0 --up 0,0,0
expect_failure "view direction overflows" "not finite" "$vol" --eye 1e308,0,0 --target -1e308,0,0
expect_usage "visibility threshold beyond the image" \
  "--visibility-threshold 1025 is more than the 1024 pixels of the image (--size 32x32)" \
  "$vol" --size 32x32 --visibility-threshold 1025 --converge
expect_usage "gpu budget too small" "--gpu-budget 1024 bytes holds no brick slot" "$vol" --gpu-budget 1K
# With stored DVR gradients a slot takes 9 bytes a texel; the message says what computed ones would take.
expect_usage "gpu budget too small for stored gradients" \
  "holds no brick slot of 419904 bytes (373248 of them for stored DVR gradients; with --gradients computed a slot takes 46656)" \
  "$vol" --mode dvr --gpu-budget 100K
expect_usage "cpu cache too small" "--cpu-cache 1024 bytes is below 16 bricks" "$vol" --cpu-cache 1K
expect_usage "upload budget too small" "--upload-budget 1024 bytes cannot carry one brick" "$vol" --upload-budget 1K
expect_failure "bad byte size" "--cpu-cache" "$vol" --cpu-cache lots
expect_failure "missing camera path" "nofile.json" "$vol" --path "$dir/nofile.json"
expect_failure "malformed camera path" "bad_path.json" "$vol" --path "$dir/bad_path.json"
expect_failure "camera path keyframe up parallel" "parallel_up_path.json, keyframe 0: up is parallel" "$vol" \
  --path "$dir/parallel_up_path.json"
expect_failure "camera path eye meets target" "crossing_path.json, frame 1 of 3: eye and target" "$vol" \
  --path "$dir/crossing_path.json" --frames 3 --every 1
expect_failure "unwritable stats" "$dir/nodir/s.jsonl" "$vol" --stats "$dir/nodir/s.jsonl"
expect_failure "float output not EXR" "--exr $dir/x_float.png: expected a file name ending in .exr" "$vol" \
  --exr "$dir/x_float.png"
expect_failure "depth output not EXR" "--depth $dir/x_depth.tif: expected a file name ending in .exr" "$vol" \
  --depth "$dir/x_depth.tif"
expect_failure "unwritable depth" "--depth $dir/nodir/d.exr: its folder" "$vol" --depth "$dir/nodir/d.exr"
# A folder that exists but takes no new file: refused before rendering, and -o is not written without --exr.
expect_failure "EXR in a folder that takes no file" "cannot create output '/sys/x.exr'" "$vol" --exr /sys/x.exr

# An image name without a known extension is refused before rendering ('.png' alone is a name without one).
for name in noextension .png x.unknownext; do
  "$ropecast" render "$vol" -o "$dir/$name" > /dev/null 2> "$dir/err.txt"
  rc=$?
  case $name in
    x.*) want="-o $dir/$name: no image writer" ;;
    *) want="-o $dir/$name: expected a name and an extension such as .png, got '$name'" ;;
  esac
  if [ "$rc" -ge 1 ] && [ "$rc" -le 127 ] && grep -qF -- "$want" "$dir/err.txt" &&
    [ -z "$(find "$dir" -name "$name*")" ]; then
    echo "ok   output $name (exit $rc)"
  else
    echo "FAIL output $name: exit $rc: $(cat "$dir/err.txt")"; failures=$((failures + 1))
  fi
done

# An unwritable image path fails the same way (it is not x.png, so check it by hand).
"$ropecast" render "$vol" -o "$dir/nodir/y.png" > /dev/null 2> "$dir/err.txt"
rc=$?
if [ "$rc" -ge 1 ] && [ "$rc" -le 127 ] && grep -qF "$dir/nodir/y.png" "$dir/err.txt"; then
  echo "ok   unwritable output (exit $rc)"
else
  echo "FAIL unwritable output: exit $rc: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi

"$ropecast" render "$vol" -o /sys/y.png > /dev/null 2> "$dir/err.txt"
rc=$?
if [ "$rc" -ge 1 ] && [ "$rc" -le 127 ] && grep -qF "render: -o: cannot create output '/sys/y.png'" "$dir/err.txt"; then
  echo "ok   output in a folder that takes no file (exit $rc)"
else
  echo "FAIL output in a folder that takes no file: exit $rc: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi

# An isovalue outside the data's range is not an error (the image is the background), but it is said.
if "$ropecast" render "$vol" --iso 1e6 -o "$dir/far.png" > /dev/null 2> "$dir/err.txt" &&
  grep -qF -- "--iso 1e+06 lies outside" "$dir/err.txt" && [ -f "$dir/far.png" ]; then
  echo "ok   isovalue outside the data range: warned, image written"
else
  echo "FAIL isovalue outside the data range: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi
if "$ropecast" render "$vol" --iso 100 -o "$dir/in.png" > /dev/null 2> "$dir/err.txt" && [ ! -s "$dir/err.txt" ]; then
  echo "ok   isovalue inside the data range: no warning"
else
  echo "FAIL isovalue inside the data range: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi

# Options the mode or renderer does not read are not errors (scripts share option sets), but they are said.
warned() {  # NAME EXPECTED_STDERR ARGS...: the render succeeds and warns with EXPECTED_STDERR
  local name=$1 expected=$2
  shift 2
  if "$ropecast" render "$@" -o "$dir/unused.png" > /dev/null 2> "$dir/err.txt" &&
    grep -qF -- "$expected" "$dir/err.txt" && [ -f "$dir/unused.png" ]; then
    echo "ok   $name: warned, image written"
  else
    echo "FAIL $name: $(cat "$dir/err.txt")"; failures=$((failures + 1))
  fi
}
# Images smaller than the default visibility threshold render where nothing queries: one synchronous frame,
# --reference, brute force.
for tiny in "--size 1x1" "--size 2x1 --reference" "--size 3x1 --backend brute"; do
  # shellcheck disable=SC2086  # the options are words
  if "$ropecast" render "$vol" $tiny -o "$dir/tiny.png" > /dev/null 2> "$dir/err.txt"; then echo "ok   $tiny"
  else echo "FAIL $tiny: $(cat "$dir/err.txt")"; failures=$((failures + 1)); fi
done
warned "--iso with --mode dvr" "warning: --iso: no effect with --mode dvr" "$vol" --mode dvr --iso 100
warned "DVR options with --mode iso" "warning: --tf, --ert: no effect with --mode iso" "$vol" --tf ct-bone --ert 0.5
warned "--frames with --reference" "warning: --frames: no effect with --reference" "$vol" --reference --frames 3 --size 8x8
warned "iso and DVR options with --mode mip" "warning: --iso, --ert: no effect with --mode mip" "$vol" --mode mip \
  --iso 100 --ert 0.5
warned "occlusion options with --mode mip" "warning: --occlusion: no effect with --mode mip" "$vol" --mode mip \
  --occlusion on
warned "iso and occlusion options with --mode aip" "warning: --iso, --caps: no effect with --mode aip" "$vol" \
  --mode aip --iso 100 --caps off
warned "occlusion options with --mode slice" "--occlusion: no effect with --mode slice (nothing behind the plane" \
  "$vol" --mode slice --occlusion on
warned "--step with --mode slice" "warning: --step: no effect with --mode slice (one sample per ray" "$vol" \
  --mode slice --step 2
# With --path, --frames says which camera is the last frame's, the one --reference renders: no warning.
printf '[{"orbit": [0, 20, 2.5]}, {"orbit": [90, 20, 2.5]}]' > "$dir/turn.json"
printf '[{"orbit": [90, 20, 2.5]}]' > "$dir/last.json"
if "$ropecast" render "$vol" --reference --path "$dir/turn.json" --frames 3 --size 16x16 -o "$dir/ref3.png" \
    2> "$dir/err.txt" && ! grep -q warning "$dir/err.txt" &&
  "$ropecast" render "$vol" --reference --path "$dir/last.json" --size 16x16 -o "$dir/reflast.png" &&
  "$ropecast" compare "$dir/ref3.png" "$dir/reflast.png" | grep -q '"max_abs":0'; then
  echo "ok   --reference --path --frames 3: the last frame's camera"
else
  echo "FAIL --reference --path --frames 3: not the last frame's camera, or warned: $(cat "$dir/err.txt")"
  failures=$((failures + 1))
fi
warned "octree options with brute force" "warning: --gpu-budget, --occlusion: no effect with --backend brute" \
  "$vol" --backend brute --gpu-budget 64M --occlusion off

# compare: a threshold that is not a number is refused; a PSNR below a threshold exits 3, above it 0.
if "$ropecast" compare "$dir/far.png" "$dir/in.png" --min-psnr nan > /dev/null 2> "$dir/err.txt"; then
  echo "FAIL compare --min-psnr nan: accepted"; failures=$((failures + 1))
elif grep -qF -- "--min-psnr" "$dir/err.txt"; then
  echo "ok   compare --min-psnr nan refused"
else
  echo "FAIL compare --min-psnr nan: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi
"$ropecast" compare "$dir/far.png" "$dir/in.png" --min-psnr 1000 > /dev/null 2>&1
below=$?
"$ropecast" compare "$dir/in.png" "$dir/in.png" --min-psnr 1000 > /dev/null 2>&1
same=$?
if [ "$below" = 3 ] && [ "$same" = 0 ]; then
  echo "ok   compare --min-psnr: 3 below, 0 for identical images"
else
  echo "FAIL compare --min-psnr: $below below, $same for identical images"; failures=$((failures + 1))
fi

# compare: more channels than an image has names the image and the option.
"$ropecast" compare "$dir/far.png" "$dir/in.png" --channels 4 > /dev/null 2> "$dir/err.txt"
rc=$?
if [ "$rc" = 2 ] && grep -qF -- "--channels 4: $dir/far.png has 3 channel(s)" "$dir/err.txt"; then
  echo "ok   compare --channels 4 of RGB images refused (exit 2)"
else
  echo "FAIL compare --channels 4 of RGB images: exit $rc: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi
# A bound that is infinite is not shown as one the option takes.
if "$ropecast" compare --help | grep -qF -- "FLOAT >= 0"; then
  echo "ok   compare --help: --min-psnr FLOAT >= 0, not [0, inf]"
else
  echo "FAIL compare --help: $("$ropecast" compare --help | grep -F -- --min-psnr)"; failures=$((failures + 1))
fi

# compare: a PNG whose header claims 60000x60000 pixels is refused before anything is allocated for it.
python3 - "$dir/in.png" "$dir/huge.png" <<'PY'
import struct, sys, zlib
data = bytearray(open(sys.argv[1], 'rb').read())
assert data[12:16] == b'IHDR'
struct.pack_into('>II', data, 16, 60000, 60000)
struct.pack_into('>I', data, 29, zlib.crc32(bytes(data[12:29])))
open(sys.argv[2], 'wb').write(data)
PY
(ulimit -v 4000000 && "$ropecast" compare "$dir/huge.png" "$dir/in.png") > /dev/null 2> "$dir/err.txt"
rc=$?
if [ "$rc" = 1 ] && grep -qF "huge.png' claims 60000x60000 pixels" "$dir/err.txt"; then
  echo "ok   compare refuses an image that claims 60000x60000 pixels"
else
  echo "FAIL compare of an image claiming 60000x60000: exit $rc: $(cat "$dir/err.txt")"; failures=$((failures + 1))
fi

[ "$failures" -eq 0 ] && echo "all ok" || echo "$failures failure(s)"
[ "$failures" -eq 0 ]
