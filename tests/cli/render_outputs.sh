#!/usr/bin/env bash
# `ropecast render` end to end: every output it promises (PNG, EXR, depth EXR, --stats lines with their fields),
# stores and procedural inputs, the backends (brute force in both shader stages), --reference, the progressive
# modes (--frames, --converge, --path, --every), and the progress line on a terminal.
# Usage: bash render_outputs.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
run() {  # run NAME COMMAND...: must exit 0
  local name="$1"; shift
  if "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then echo "ok   $name"; else fail "$name: exit $?: $(cat "$dir/err.txt")"; fi
}
# Mean of a channel over the image, from oiiotool --stats ("Stats Avg: r g b a (float)").
channel_avg() { oiiotool --stats "$1" 2>/dev/null | awk -v c="$2" '/Stats Avg/ {print $(3 + c); exit}'; }
# psnr A B: PSNR of two images of the same size, from oiiotool --diff ("Peak SNR = X"; absent when identical).
psnr() { oiiotool "$1" "$2" --diff 2>/dev/null | awk '/Peak SNR/ {print $4; exit}'; }
at_least() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a >= b) }'; }

small="procedural:sphere:48 --size 64x64 --brick 16"

# --slice AXIS:INDEX: the plane through that slice of voxel centers, --mode slice implied.
run "--slice z:30" "$ropecast" render procedural:marschner-lobb:48 --size 64x64 --slice z:30 -o "$dir/slice_z.png"
run "the same plane by --clip-plane" "$ropecast" render procedural:marschner-lobb:48 --size 64x64 --mode slice \
  --clip-plane 24,24,30.5,0,0,1 -o "$dir/slice_plane.png"
d=$("$ropecast" compare "$dir/slice_z.png" "$dir/slice_plane.png") && grep -q '"max_abs":0.0,' <<< "$d" ||
  fail "--slice z:30 is not the plane z = 30.5: $d"
# --slab: a MIP of the slab of slices 27 to 33 about slice 30 is the MIP of the same slab cropped.
run "--mode mip --slice z:30 --slab 7" "$ropecast" render procedural:marschner-lobb:48 --size 64x64 --mode mip \
  --slice z:30 --slab 7 --view superior -o "$dir/slab.png"
run "the same slab by --crop" "$ropecast" render procedural:marschner-lobb:48 --size 64x64 --mode mip \
  --crop :,:,27:34 --view superior -o "$dir/slab_crop.png"
d=$("$ropecast" compare "$dir/slab.png" "$dir/slab_crop.png" --min-psnr 60) ||
  fail "a slab of 7 about slice 30 is not the crop of slices 27 to 33: $d"
run "png+exr+depth+stats" "$ropecast" render $small -o "$dir/a.png" --exr "$dir/a.exr" --depth "$dir/a_depth.exr" \
  --stats "$dir/a.jsonl"
for f in a.png a.exr a_depth.exr a.jsonl; do [ -s "$dir/$f" ] || fail "missing output $f"; done
! grep -q "warning" "$dir/err.txt" || fail "a view the default pool holds warned: $(cat "$dir/err.txt")"
oiiotool --info -v "$dir/a.exr" 2>/dev/null | grep -q "4 channel" || fail "a.exr is not float RGBA"
oiiotool --info -v "$dir/a.exr" 2>/dev/null | grep -q "float" || fail "a.exr is not float"
# compare takes two depth images (one channel) as they are, and asks for --channels when the counts differ.
d=$("$ropecast" compare "$dir/a_depth.exr" "$dir/a_depth.exr") || fail "compare of two depth images: $d"
grep -q '"channels":1' <<< "$d" && grep -q '"max_abs":0' <<< "$d" || fail "compare of two depth images: $d"
d=$("$ropecast" compare "$dir/a_depth.exr" "$dir/a.exr" 2>&1) && fail "compare of a depth and an RGBA image: exit 0"
grep -q -- "--channels" <<< "$d" || fail "compare of a depth and an RGBA image should ask for --channels: $d"
# Two gray-and-alpha images: the default compares the gray, as it compares RGB, not the alpha.
oiiotool --no-autopremult --pattern constant:color=0.5,1 8x8 2 --attrib oiio:UnassociatedAlpha 1 -d uint8 \
  -o "$dir/ga1.png" && oiiotool --no-autopremult --pattern constant:color=0.5,0.3 8x8 2 \
  --attrib oiio:UnassociatedAlpha 1 -d uint8 -o "$dir/ga2.png" || fail "oiiotool for the gray-and-alpha images"
d=$("$ropecast" compare "$dir/ga1.png" "$dir/ga2.png") || fail "compare of two gray-and-alpha images: $d"
grep -q '"channels":1' <<< "$d" && grep -q '"max_abs":0' <<< "$d" || fail "compare of gray-and-alpha images: $d"
# The sphere covers the middle of the image: coverage (EXR alpha) strictly between 0 and 1 on average.
alpha=$(channel_avg "$dir/a.exr" 3)
at_least "$alpha" 0.05 && ! at_least "$alpha" 0.95 || fail "a.exr mean alpha $alpha: expected a partly covered image"
[ "$(wc -l < "$dir/a.jsonl")" -eq 1 ] || fail "one frame should give one stats line"
for field in frame frame_ms raycast_ms index_ms leaves bricks_resident bricks_uploaded bytes_uploaded refine_ms \
    requests_pending cache_hits cache_misses cpu_cache_bytes gpu_pool_used leaves_pool_full leaves_solid converged step_voxels backend; do
  grep -q "\"$field\":" "$dir/a.jsonl" || fail "stats line lacks $field: $(cat "$dir/a.jsonl")"
done
grep -q '"converged":true' "$dir/a.jsonl" || fail "a synchronous frame should be converged"
# --backend auto (the default) names the backend it chose (which one: tests/render/backend_choice_test.cpp).
grep -qE '"backend":"(fragment|compute)"' "$dir/a.jsonl" || fail "auto backend not reported: $(cat "$dir/a.jsonl")"

# --target-frame-ms: a target no frame can meet makes the step grow after the first frame, up to 4x.
run "target frame time" "$ropecast" render $small --mode dvr --tf ct-soft --frames 3 --target-frame-ms 0.001 \
  --step 0.5 -o "$dir/t.png" --stats "$dir/t.jsonl"
steps=$(python3 -c 'import json, sys; print(" ".join(str(json.loads(l)["step_voxels"]) for l in open(sys.argv[1])))' \
  "$dir/t.jsonl")
[ "$steps" = "0.5 2.0 2.0" ] || fail "--target-frame-ms 0.001: steps $steps, expected 0.5 2.0 2.0"
# Once a still view has converged, the step stays and so does the cut: its frames cost less (no queries), and
# a step they shortened made a new view whose queries refined and collapsed nodes again.
run "target frame time, still view" "$ropecast" render procedural:menger:81 --brick 8 --size 96x96 --frames 40 \
  --target-frame-ms 6 -o "$dir/ts.png" --stats "$dir/ts.jsonl"
python3 - "$dir/ts.jsonl" <<'PY' || fail "--target-frame-ms on a still view: the cut or the step changed after converging"
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
first = next((i for i, r in enumerate(rows) if r["converged"]), None)
assert first is not None, "never converged"
after = rows[first:]
changed = [(r["frame"], r["leaves"], r["step_voxels"], r["bricks_uploaded"]) for r in after
           if not r["converged"] or r["leaves"] != after[0]["leaves"] or r["step_voxels"] != after[0]["step_voxels"]
           or r["bricks_uploaded"] > 0]
assert not changed, f"converged at frame {first}, then {changed[:5]}"
PY
# DVR with computed gradients renders the stored-gradient image (same gradients up to storage precision).
run "dvr computed gradients" "$ropecast" render $small --mode dvr --tf ct-soft -o "$dir/g1.png" --gradients computed
run "dvr stored gradients" "$ropecast" render $small --mode dvr --tf ct-soft -o "$dir/g2.png"
p=$(psnr "$dir/g1.png" "$dir/g2.png")
[ -z "$p" ] || [ "$p" = "inf" ] || at_least "$p" 35 || fail "computed vs stored gradients PSNR $p dB < 35"

# The compute backend gives the fragment backend's image; --stats names each.
run "fragment backend" "$ropecast" render $small -o "$dir/fr.png" --backend fragment --stats "$dir/fr.jsonl"
grep -q '"backend":"fragment"' "$dir/fr.jsonl" || fail "--backend fragment: stats say $(cat "$dir/fr.jsonl")"
run "compute backend" "$ropecast" render $small -o "$dir/c.png" --backend compute --stats "$dir/c.jsonl"
grep -q '"backend":"compute"' "$dir/c.jsonl" || fail "--backend compute: stats say $(cat "$dir/c.jsonl")"
run "brute backend" "$ropecast" render $small -o "$dir/b.png" --backend brute --stats "$dir/b.jsonl"
grep -q '"backend":"brute"' "$dir/b.jsonl" || fail "--backend brute: stats say $(cat "$dir/b.jsonl")"
p=$(psnr "$dir/fr.png" "$dir/c.png")
[ -z "$p" ] || [ "$p" = "inf" ] || at_least "$p" 50 || fail "fragment vs compute PSNR $p dB < 50"
# Brute force in either shader stage (--brute-stage), named by --stats as "stage"; by default in the stage the
# octree ray caster resolves --backend auto to, and the two stages give one image.
stage_of() { python3 -c 'import json, sys; print(json.loads(open(sys.argv[1]).readline())["stage"])' "$1"; }
[ "$(stage_of "$dir/b.jsonl")" = "$(stage_of "$dir/a.jsonl")" ] ||
  fail "--backend brute runs in stage $(stage_of "$dir/b.jsonl"), the auto ray caster in $(stage_of "$dir/a.jsonl")"
run "brute backend, compute stage" "$ropecast" render $small -o "$dir/bc.png" --backend brute --brute-stage compute \
  --stats "$dir/bc.jsonl"
grep -q '"backend":"brute"' "$dir/bc.jsonl" && grep -q '"stage":"compute"' "$dir/bc.jsonl" ||
  fail "--backend brute --brute-stage compute: stats say $(cat "$dir/bc.jsonl")"
run "brute backend, fragment stage" "$ropecast" render $small -o "$dir/bf.png" --backend brute --brute-stage fragment \
  --stats "$dir/bf.jsonl"
grep -q '"stage":"fragment"' "$dir/bf.jsonl" || fail "--brute-stage fragment: stats say $(cat "$dir/bf.jsonl")"
p=$(psnr "$dir/bf.png" "$dir/bc.png")
[ -z "$p" ] || [ "$p" = "inf" ] || at_least "$p" 50 || fail "brute force fragment vs compute PSNR $p dB < 50"

# A converted store renders, and --reference (CPU brute force) agrees with the octree image.
run "convert" "$ropecast" convert procedural:sphere:48 --brick 16 -o "$dir/s.rcast" --quiet
run "render store" "$ropecast" render "$dir/s.rcast" --size 64x64 -o "$dir/s.png"
run "reference" "$ropecast" render "$dir/s.rcast" --size 64x64 -o "$dir/s_ref.png" --reference
p=$(psnr "$dir/s.png" "$dir/s_ref.png")
[ -z "$p" ] || at_least "$p" 30 || fail "store image vs --reference PSNR '$p' dB < 30"
echo "     store vs reference: ${p:-identical} dB"

# DVR with a preset and with a transfer-function file.
run "dvr preset" "$ropecast" render $small --mode dvr --tf ct-soft -o "$dir/d.png"
cat > "$dir/tf.json" <<'TF'
{"points": [[0, 0, 0, 0, 0], [100, 0, 0, 0, 0], [255, 1, 0.5, 0.2, 0.1]]}
TF
if "$ropecast" render $small --mode dvr --tf "$dir/tf.json" -o "$dir/d2.png" 2> "$dir/err.txt"; then
  echo "ok   dvr tf file"
else
  fail "dvr tf file: $(cat "$dir/err.txt")"
fi

# Progressive: N frames give N lines; --converge ends converged; --every writes intermediate frames.
run "frames" "$ropecast" render $small -o "$dir/f.png" --frames 3 --stats "$dir/f.jsonl"
[ "$(wc -l < "$dir/f.jsonl")" -eq 3 ] || fail "--frames 3 gave $(wc -l < "$dir/f.jsonl") stats lines"
run "converge" "$ropecast" render $small -o "$dir/v.png" --converge --io-delay-ms 5 --upload-budget 64K \
  --stats "$dir/v.jsonl" --every 1
tail -n 1 "$dir/v.jsonl" | grep -q '"converged":true' || fail "--converge: last frame not converged"
! grep -q "warning" "$dir/err.txt" || fail "--converge on a view the pool holds warned: $(cat "$dir/err.txt")"
# --every 1 writes each frame, the last included: as many files as stats lines, the last one the -o image.
[ "$(ls "$dir"/v_*.png 2>/dev/null | wc -l)" -eq "$(wc -l < "$dir/v.jsonl")" ] ||
  fail "--every 1 wrote $(ls "$dir"/v_*.png 2>/dev/null | wc -l) frames for $(wc -l < "$dir/v.jsonl") stats lines"
cmp -s "$(ls "$dir"/v_*.png | tail -n 1)" "$dir/v.png" || fail "--every 1: the last numbered frame is not the -o image"
# The loader's thread count changes when bricks arrive, not the converged image.
for threads in 1 7; do
  run "converge with --io-threads $threads" "$ropecast" render $small -o "$dir/t$threads.png" --converge \
    --io-delay-ms 5 --upload-budget 64K --io-threads "$threads"
  cmp -s "$dir/t$threads.png" "$dir/v.png" || fail "--io-threads $threads: another converged image"
done
# Brute force's frames along a path are written alike (every second one, and the last).
run "brute every" "$ropecast" render $small -o "$dir/b.png" --backend brute --frames 3 --every 2
[ "$(ls "$dir"/b_*.png 2>/dev/null | tr '\n' ' ')" = "$dir/b_0000.png $dir/b_0002.png " ] ||
  fail "--backend brute --every 2 wrote: $(ls "$dir"/b_*.png 2>/dev/null)"
# A render that fails leaves none of its outputs: not its --every frames, not its --stats. A file-size limit
# stands for a full disk (the EXR, or a frame, cannot be written); a folder with a frame's name is refused
# before anything renders. --converge, so that the last image is the loaded one: frames drawn before the bricks
# arrive are nearly empty, and their EXR fitted the limit on a busy machine.
mkdir "$dir/fail" && (ulimit -f 12; "$ropecast" render procedural:noise:64 -o "$dir/fail/o.png" --size 128x128 \
  --mode dvr --converge --every 1 --stats "$dir/fail/s.jsonl" --exr "$dir/fail/o.exr") >/dev/null 2>&1 &&
  fail "a render past the file-size limit exited 0"
[ -z "$(ls -A "$dir/fail")" ] || fail "a render that failed left: $(ls -A "$dir/fail" | tr '\n' ' ')"
mkdir "$dir/fail/g_0002.png"
"$ropecast" render $small -o "$dir/fail/g.png" --frames 3 --every 1 --stats "$dir/fail/g.jsonl" \
  >/dev/null 2>"$dir/err.txt" && fail "--every with a folder named like a frame exited 0"
grep -q "g_0002.png: a folder" "$dir/err.txt" || fail "--every, a folder named like a frame: $(cat "$dir/err.txt")"
[ "$(ls -A "$dir/fail")" = "g_0002.png" ] || fail "a refused render left: $(ls -A "$dir/fail" | tr '\n' ' ')"
# From a slow disk (35 reads of 150 ms on 2 workers: 2.6 s), --converge waits for reads, up to 0.1 s, between
# frames that would draw the same cut: 100 frames converge, where frames of 2 ms spent them on the first reads.
run "converge from a slow disk" "$ropecast" render $small -o "$dir/slow.png" --converge --io-delay-ms 150 \
  --max-frames 100 --stats "$dir/slow.jsonl"
tail -n 1 "$dir/slow.jsonl" | grep -q '"converged":true' ||
  fail "--converge --io-delay-ms 150: not converged in $(wc -l < "$dir/slow.jsonl") frames"
p=$(psnr "$dir/a.png" "$dir/v.png")
[ -z "$p" ] || [ "$p" = "inf" ] || at_least "$p" 50 || fail "converged image differs from the synchronous one ($p dB)"
# A pool smaller than the view and one upload a frame: a still view settles (it swapped two trees forever,
# the rays' requests and the budgeted uploads displacing each other).
run "converge, full pool, one upload a frame" "$ropecast" render procedural:noise:128 --brick 8 --size 128x128 \
  --orbit 30,20,1.2 -o "$dir/tight.png" --converge --max-frames 600 --gpu-budget 400K --upload-budget 1728 \
  --stats "$dir/tight.jsonl"
tail -n 1 "$dir/tight.jsonl" | grep -q '"converged":true' ||
  fail "full pool, one upload a frame: not converged in $(wc -l < "$dir/tight.jsonl") frames"
# Pacing the uploads changes the order the cut grows in, not the cut it converges to.
"$ropecast" render procedural:noise:128 --brick 8 --size 128x128 --orbit 30,20,1.2 -o "$dir/tight_free.png" \
  --converge --gpu-budget 400K 2> "$dir/err.txt" || fail "full pool, no upload budget: $(cat "$dir/err.txt")"
# A view the pool cannot hold renders, and says it is coarser than asked and what to raise.
grep -q "leaves stay coarser than --voxels-per-pixel 1 asks.*raise --gpu-budget" "$dir/err.txt" &&
  echo "ok   full pool: warned" || fail "full pool: no warning naming --gpu-budget: $(cat "$dir/err.txt")"
d=$("$ropecast" compare "$dir/tight.png" "$dir/tight_free.png")
if grep -q '"max_abs":0.0,' <<< "$d"; then echo "ok   full pool: the same cut with and without an upload budget"
else fail "full pool: the cut converged with one upload a frame differs from the one without a budget: $d"; fi
cat > "$dir/path.json" <<'PATH'
[{"orbit": [0, 20, 3]}, {"orbit": [90, 20, 2.5]}]
PATH
if "$ropecast" render $small -o "$dir/p.png" --path "$dir/path.json" --frames 4 --stats "$dir/p.jsonl" 2> "$dir/err.txt"; then
  [ "$(wc -l < "$dir/p.jsonl")" -eq 4 ] && echo "ok   path" || fail "--path --frames 4 gave $(wc -l < "$dir/p.jsonl") lines"
else
  fail "path: $(cat "$dir/err.txt")"
fi
# A path of one frame (--frames 1, the default) is its first camera, rendered as that camera alone: loaded
# before it is drawn, not a first progressive frame with nothing loaded yet.
"$ropecast" render $small -o "$dir/p1.png" --path "$dir/path.json" 2> "$dir/err.txt" || fail "path, one frame: $(cat "$dir/err.txt")"
"$ropecast" render $small -o "$dir/o1.png" --orbit 0,20,3 2> "$dir/err.txt" || fail "orbit 0,20,3: $(cat "$dir/err.txt")"
p=$(psnr "$dir/p1.png" "$dir/o1.png")
if [ -z "$p" ] || [ "$p" = "inf" ] || at_least "$p" 50; then echo "ok   path of one frame = its first camera"
else fail "path of one frame differs from its first camera ($p dB)"; fi

# A progress line on a terminal (script(1), from bsdutils, gives the render one): the load's bricks, or each
# frame of a progressive render; -q, or stderr not a terminal, silences it.
on_terminal() {  # on_terminal LOG ARGS...: `ropecast render ARGS` with a terminal; what it showed into LOG
  local log="$1"; shift
  script -qec "$(printf '%q ' "$ropecast" render "$@")" "$log" > /dev/null || fail "on a terminal: render $*: exit $?"
}
on_terminal "$dir/t1.log" $small -o "$dir/t1.png"
grep -q "render: loading, [0-9]* bricks read, 0 pending" "$dir/t1.log" && echo "ok   progress of the load" ||
  fail "no load progress on a terminal: $(cat -v "$dir/t1.log")"
on_terminal "$dir/t2.log" $small -o "$dir/t2.png" --converge
grep -q "render: frame [0-9]*, working set [0-9]* bricks" "$dir/t2.log" && echo "ok   progress of the frames" ||
  fail "no frame progress on a terminal: $(cat -v "$dir/t2.log")"
on_terminal "$dir/t3.log" $small -o "$dir/t3.png" --converge -q
! grep -q "render:" "$dir/t3.log" && echo "ok   -q: no progress" || fail "-q showed progress: $(cat -v "$dir/t3.log")"
"$ropecast" render $small -o "$dir/t4.png" --converge 2> "$dir/t4.err"
[ ! -s "$dir/t4.err" ] && echo "ok   no terminal: no progress" || fail "progress without a terminal: $(cat "$dir/t4.err")"

# --tf-range: the gray preset of a MIP over 50..150 is the function of those points (its fractions 0, 0.1,
# 0.2 and 1 of the range); with --mode iso it has no effect, and says so.
printf '{"points": [[50,0,0,0,0],[60,0,0,0,0],[70,0.111,0.111,0.111,1],[150,1,1,1,1]]}' > "$dir/window.json"
run "--tf-range" "$ropecast" render $small --mode mip --tf-range 50,150 -o "$dir/range.png"
run "--tf of the window's points" "$ropecast" render $small --mode mip --tf "$dir/window.json" -o "$dir/window.png"
run "--mode mip" "$ropecast" render $small --mode mip -o "$dir/mip.png"
d=$("$ropecast" compare "$dir/range.png" "$dir/window.png" --min-psnr 60) || fail "--tf-range 50,150 is not the window's function: $d"
"$ropecast" compare "$dir/range.png" "$dir/mip.png" --min-psnr 40 > /dev/null && fail "--tf-range changed nothing"
run "--tf-range with --mode iso" "$ropecast" render $small --tf-range 50,150 -o "$dir/iso_range.png"
grep -qF "warning: --tf-range: no effect with --mode iso" "$dir/err.txt" || fail "--tf-range with --mode iso: $(cat "$dir/err.txt")"

# Lighting: --shading off is DVR lit by ambient light of weight 1 alone (--material 1,0,0,1), and unlike the
# shaded default; --iso-color and --material change an isosurface; options a mode does not read are said.
run "--shading off" "$ropecast" render $small --mode dvr --shading off -o "$dir/unlit.png"
run "--material 1,0,0,1" "$ropecast" render $small --mode dvr --material 1,0,0,1 -o "$dir/ambient.png"
run "--mode dvr" "$ropecast" render $small --mode dvr -o "$dir/dvr.png"
grep -q '"max_abs":0' <<< "$("$ropecast" compare "$dir/unlit.png" "$dir/ambient.png")" ||
  fail "--shading off is not ambient light alone: $("$ropecast" compare "$dir/unlit.png" "$dir/ambient.png")"
"$ropecast" compare "$dir/unlit.png" "$dir/dvr.png" --min-psnr 40 > /dev/null && fail "--shading off changed nothing"
run "--iso-color" "$ropecast" render $small --iso-color 1,0,0 -o "$dir/red.png"
at_least "$(channel_avg "$dir/red.png" 0)" "$(awk -v g="$(channel_avg "$dir/red.png" 1)" 'BEGIN { print 3 * g }')" ||
  fail "--iso-color 1,0,0 is not red: $(channel_avg "$dir/red.png" 0) red, $(channel_avg "$dir/red.png" 1) green"
run "--material" "$ropecast" render $small --material 0.5,0.2,0,1 -o "$dir/matte.png"
"$ropecast" compare "$dir/matte.png" "$dir/a.png" --min-psnr 40 > /dev/null && fail "--material changed nothing"
run "--shading with --mode iso" "$ropecast" render $small --shading off -o "$dir/iso_shading.png"
grep -qF "warning: --shading: no effect with --mode iso" "$dir/err.txt" || fail "--shading with --mode iso: $(cat "$dir/err.txt")"
run "--gradients with --shading off" "$ropecast" render $small --mode dvr --shading off --gradients computed -o "$dir/unlit2.png"
grep -qF "warning: --gradients: no effect with --shading off" "$dir/err.txt" || fail "--gradients with --shading off: $(cat "$dir/err.txt")"
grep -q '"max_abs":0' <<< "$("$ropecast" compare "$dir/unlit.png" "$dir/unlit2.png")" || fail "unlit DVR depends on --gradients"
run "--iso-color with --mode mip" "$ropecast" render $small --mode mip --iso-color 1,0,0 -o "$dir/mip_color.png"
grep -qF "warning: --iso-color: no effect with --mode mip" "$dir/err.txt" || fail "--iso-color with --mode mip: $(cat "$dir/err.txt")"

[ "$failures" -eq 0 ] && echo "all ok" || echo "$failures failure(s)"
[ "$failures" -eq 0 ]
