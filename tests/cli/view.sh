#!/usr/bin/env bash
# `ropecast view` end to end under Xvfb (llvmpipe through GLX): the converged screenshot is the image `render
# --converge` draws with the same camera and settings; a scripted drag lands on the orbit docs/VIEWER.md
# documents, and the camera it saves is one `render --path` reads; a scripted isovalue change and a transfer
# function load draw what `render` draws with them; without a display, or without OpenGL 4.5 on it, the viewer
# refuses cleanly, says which, and names `ropecast render`; --max-frames ends every wait; what the script and the
# panels write never replaces an input; a converged view idles; closing the window before a script's screenshot
# is an error; the probe names the voxel under a pixel and the value extract reads there.
# Usage: bash view.sh /path/to/ropecast
set -uo pipefail
# shellcheck source=tests/cli/lib/nifti_series.sh
source "$(dirname "$0")/lib/nifti_series.sh"
ropecast=$(realpath "$1")  # the panel check runs in its own folder
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
data="$(cd "$(dirname "$0")/../data" && pwd)"
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
run() {  # run NAME COMMAND...: must exit 0
  local name="$1"; shift
  if "$@" > "$dir/out.txt" 2> "$dir/err.txt"; then echo "ok   $name"; else fail "$name: exit $?: $(cat "$dir/err.txt")"; fi
}
same() {  # same NAME A.png B.png: at least 40 dB apart
  if "$ropecast" compare "$2" "$3" --min-psnr 40 > "$dir/cmp.txt" 2>&1; then echo "ok   $1"
  else fail "$1: $(cat "$dir/cmp.txt")"; fi
}
differs() {  # differs NAME A.png B.png: below 40 dB (the event changed the image)
  if "$ropecast" compare "$2" "$3" --min-psnr 40 > "$dir/cmp.txt" 2>&1; then fail "$1: no change: $(cat "$dir/cmp.txt")"
  else echo "ok   $1"; fi
}

vol="procedural:marschner-lobb:48 --brick 16 --size 96x96"

# No display: a clean error that names the headless way, before any window or work.
env -u DISPLAY -u WAYLAND_DISPLAY "$ropecast" view $vol --screenshot "$dir/none.png" > /dev/null 2> "$dir/err.txt"
rc=$?
if [ "$rc" -ge 1 ] && [ "$rc" -le 127 ]; then echo "ok   no display: exit $rc"; else fail "no display: exit $rc"; fi
grep -q "ropecast render" "$dir/err.txt" || fail "no display: the message does not name ropecast render: $(cat "$dir/err.txt")"
grep -qi "display" "$dir/err.txt" || fail "no display: the message does not say so: $(cat "$dir/err.txt")"

# The viewer draws with the octree ray caster: render's brute-force baseline is neither offered nor taken.
help=$("$ropecast" view --help)
grep -q -- "--backend ENUM:{auto,fragment,compute,multipass}" <<< "$help" ||
  fail "view --help offers backends the viewer refuses: $(grep -- --backend <<< "$help")"
env -u DISPLAY "$ropecast" view $vol --backend brute > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" = 2 ] && grep -qF -- "--backend: expected auto, fragment, compute or multipass, got 'brute'" "$dir/err.txt"; } || fail "--backend brute: exit $rc: $(cat "$dir/err.txt")"
[ ! -e "$dir/none.png" ] || fail "no display: a screenshot was written"

# A script's transfer function and camera path files are checked before the window opens (no display here):
# the message names the script and the event.
echo "nonsense" > "$dir/not_tf.json"
echo "[{\"event\": \"set_mode\", \"mode\": \"dvr\"}, {\"event\": \"load_tf\", \"tf\": \"$dir/not_tf.json\"}]" > "$dir/bad_tf.json"
env -u DISPLAY "$ropecast" view $vol --script "$dir/bad_tf.json" > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" = 1 ] && grep -qF "bad_tf.json: event 1 (load_tf)" "$dir/err.txt" && ! grep -qi "display" "$dir/err.txt"; } ||
  fail "load_tf of a file that is no transfer function: exit $rc: $(cat "$dir/err.txt")"
echo "[{\"event\": \"save_camera\", \"file\": \"$data/tf/sphere_shells.json\"}]" > "$dir/bad_cam.json"
env -u DISPLAY "$ropecast" view $vol --script "$dir/bad_cam.json" > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" = 1 ] && grep -qF "bad_cam.json: event 0 (save_camera): $data/tf/sphere_shells.json exists and is not a camera path" "$dir/err.txt"; } ||
  fail "save_camera onto a file that is no camera path: exit $rc: $(cat "$dir/err.txt")"

if ! command -v xvfb-run > /dev/null; then
  echo "skip: xvfb-run is not installed (scripts/bootstrap installs xvfb)"
  exit "$((failures > 0))"
fi
# xvfb-run with an authority file of ours: without one it makes a temporary folder, whose removal has failed under
# load ("problem while cleaning up temporary directory"), turning the viewer's exit status into 5.
xrun() { xvfb-run -a -f "$dir/Xauthority" "$@"; }
xview() { xrun -s "-screen 0 320x240x24" "$ropecast" view "$@"; }

# A display whose OpenGL is older than 4.5 (Mesa made to report 3.3 to the viewer): the message says that, not
# "no display".
xview_old_gl() { xrun -s "-screen 0 320x240x24" env MESA_GL_VERSION_OVERRIDE=3.3 "$ropecast" view "$@"; }
xview_old_gl $vol --screenshot "$dir/old_gl.png" > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" = 1 ] && grep -q "OpenGL 4.5" "$dir/err.txt" && ! grep -q "X11 display" "$dir/err.txt" &&
  grep -q "ropecast render" "$dir/err.txt" && [ ! -e "$dir/old_gl.png" ]; } ||
  fail "a display without OpenGL 4.5: exit $rc: $(cat "$dir/err.txt")"

# --screenshot alone: the converged view, as render --converge draws it at the default orbit.
run "view --screenshot" xview $vol --screenshot "$dir/v0.png"
run "render --converge" "$ropecast" render $vol --converge -o "$dir/r0.png"
same "converged view = render" "$dir/v0.png" "$dir/r0.png"

# A slow disk: the screenshot waits for the reads as render --converge does (the frames that could only show the
# same cut used to spend --max-frames in a second), and is render's image.
slow="procedural:sphere:32 --brick 8 --size 48x40 --io-delay-ms 100"
xview $slow --screenshot "$dir/vslow.png" > /dev/null 2> "$dir/err.txt" || fail "view from a slow disk: $(cat "$dir/err.txt")"
! grep -q "not converged" "$dir/err.txt" || fail "view from a slow disk gave up: $(cat "$dir/err.txt")"
run "render from a slow disk" "$ropecast" render $slow --converge -o "$dir/rslow.png"
grep -q '"max_abs":0' <<< "$("$ropecast" compare "$dir/vslow.png" "$dir/rslow.png")" ||
  fail "view from a slow disk is not render's image: $("$ropecast" compare "$dir/vslow.png" "$dir/rslow.png")"
# A pool too small for the view: the screenshot says so, as render does.
xview procedural:menger:81 --size 160x120 --gpu-budget 300K --screenshot "$dir/vpool.png" > /dev/null \
  2> "$dir/err.txt" || fail "view with a small pool: $(cat "$dir/err.txt")"
grep -q "ropecast view: warning: .* leaves stay coarser" "$dir/err.txt" ||
  fail "a pool-limited screenshot did not warn: $(cat "$dir/err.txt")"

# --backend multipass: the viewer draws with it (the panel's backend list has it), the image render's.
run "view --backend multipass" xview $vol --backend multipass --screenshot "$dir/vm.png" --stats "$dir/vm.jsonl"
grep -q '"backend":"multipass"' <<< "$(tail -n 1 "$dir/vm.jsonl")" ||
  fail "--backend multipass: the last frame was drawn with another backend: $(tail -n 1 "$dir/vm.jsonl")"
same "multipass view = render" "$dir/vm.png" "$dir/r0.png"

# A drag of (+40, +20) pixels: azimuth 30 - 40 * 0.25, elevation 20 + 20 * 0.25; the saved camera is that orbit.
cat > "$dir/drag.json" << JSON
[{"event": "drag", "from": [48, 48], "to": [88, 68], "steps": 4, "seconds": 0.2},
 {"event": "screenshot", "file": "$dir/v1.png"},
 {"event": "save_camera", "file": "$dir/cameras.json"}]
JSON
run "view --script drag" xview $vol --script "$dir/drag.json"
run "render --orbit 20,25,3" "$ropecast" render $vol --converge --orbit 20,25,3 -o "$dir/r1.png"
same "dragged view = render at the documented orbit" "$dir/v1.png" "$dir/r1.png"
differs "the drag turned the view" "$dir/v1.png" "$dir/v0.png"
grep -q '"orbit"' "$dir/cameras.json" 2> /dev/null || fail "save_camera wrote no orbit keyframe: $(cat "$dir/cameras.json")"
run "render --path the saved camera" "$ropecast" render $vol --converge --path "$dir/cameras.json" -o "$dir/r1p.png"
same "saved camera = the dragged view" "$dir/v1.png" "$dir/r1p.png"

# Two wheel clicks: the distance 3 * 0.9^2; then a middle-button pan, saved as an eye/target keyframe; then a
# slice, its plane (the axial one through the center, z = 24) moved three voxels toward the eye (above it) by
# three clicks with shift; then a MIP of the slab 6 thick about it, set by a script.
cat > "$dir/zoom_pan.json" << JSON
[{"event": "wheel", "clicks": 2}, {"event": "screenshot", "file": "$dir/v4.png"},
 {"event": "drag", "button": "middle", "from": [48, 48], "to": [60, 40], "steps": 3},
 {"event": "screenshot", "file": "$dir/v5.png"}, {"event": "save_camera", "file": "$dir/panned.json"},
 {"event": "set_mode", "mode": "slice"}, {"event": "wheel", "clicks": 3, "shift": true},
 {"event": "screenshot", "file": "$dir/v7.png"}, {"event": "set_mode", "mode": "mip"},
 {"event": "set_clip_plane", "plane": [24, 24, 27, 0, 0, 1], "slab": 6},
 {"event": "screenshot", "file": "$dir/v8.png"}]
JSON
run "view --script wheel, pan" xview $vol --script "$dir/zoom_pan.json"
run "render --orbit 30,20,2.43" "$ropecast" render $vol --converge --orbit 30,20,2.43 -o "$dir/r4.png"
same "zoomed view = render at the documented distance" "$dir/v4.png" "$dir/r4.png"
grep -q '"eye"' "$dir/panned.json" 2> /dev/null || fail "a panned camera saves eye and target: $(cat "$dir/panned.json")"
run "render --path the panned camera" "$ropecast" render $vol --converge --path "$dir/panned.json" -o "$dir/r5.png"
same "saved panned camera = the panned view" "$dir/v5.png" "$dir/r5.png"
differs "the pan moved the view" "$dir/v5.png" "$dir/v4.png"
run "render a slice at z = 27" "$ropecast" render $vol --converge --path "$dir/panned.json" --mode slice \
  --clip-plane 24,24,27,0,0,1 -o "$dir/r7.png"
same "a slice moved by shift + wheel = render --clip-plane there" "$dir/v7.png" "$dir/r7.png"
run "render a slab's MIP" "$ropecast" render $vol --converge --path "$dir/panned.json" --mode mip \
  --clip-plane 24,24,27,0,0,1 --slab 6 -o "$dir/r8.png"
same "a scripted slab = render --slab" "$dir/v8.png" "$dir/r8.png"

# Holding W for 0.5 s of the script's clock flies 0.25 bounding-sphere radii forward, whatever the frame times;
# the saved eye/target camera draws the same.
cat > "$dir/fly.json" << JSON
[{"event": "key", "key": "w", "seconds": 0.5}, {"event": "screenshot", "file": "$dir/v6.png"},
 {"event": "save_camera", "file": "$dir/flown.json"}]
JSON
run "view --script key w" xview $vol --script "$dir/fly.json"
differs "flying moved the view" "$dir/v6.png" "$dir/v0.png"
run "render --path the flown camera" "$ropecast" render $vol --converge --path "$dir/flown.json" -o "$dir/r6.png"
same "saved flown camera = the flown view" "$dir/v6.png" "$dir/r6.png"
python3 -c 'import json, math, sys
k = json.load(open(sys.argv[1]))[0]
radius = 0.5 * math.sqrt(3 * 48 ** 2)
kept = math.dist(k["eye"], k["target"]) / radius            # eye and center move together
flown = math.dist(k["target"], [24, 24, 24]) / radius       # the center left the volume center by 0.5 * 0.5
sys.exit(abs(kept - 3.0) > 1e-9 or abs(flown - 0.25) > 1e-9)' "$dir/flown.json" ||
  fail "0.5 s of W: expected the center 0.25 radii forward, 3 radii from the eye: $(cat "$dir/flown.json")"

# --target-frame-ms: frames while the camera moves sample coarser (a target no frame meets: the largest step), and
# the still camera refines to the full-quality image of the same orbit.
run "view --target-frame-ms while dragging" xview $vol --script "$dir/drag.json" --target-frame-ms 0.001 \
  --stats "$dir/drag.jsonl"
same "coarse while moving, full quality once still" "$dir/v1.png" "$dir/r1.png"
steps=$(python3 -c 'import json, sys; print(" ".join(str(json.loads(l)["step_voxels"]) for l in open(sys.argv[1])))' \
  "$dir/drag.jsonl")
grep -qE "(^| )2\.0( |$)" <<< "$steps" || fail "--target-frame-ms: no frame sampled at 4x --step while moving: $steps"
last=$(tail -n 1 "$dir/drag.jsonl")
grep -q '"step_voxels":0.5' <<< "$last" && grep -q '"converged":true' <<< "$last" ||
  fail "--target-frame-ms: the last frame is not a converged full-step one: $last"
# From a converged view, a long drag: once the step is at its largest, the cut coarsens (half
# --voxels-per-pixel), and the still camera refines again (the drag turned it: its own cut).
cat > "$dir/long_drag.json" << JSON
[{"event": "wait_converged"},
 {"event": "drag", "from": [48, 48], "to": [58, 53], "steps": 12, "seconds": 1.5},
 {"event": "wait_converged"}]
JSON
# (A volume whose full-detail cut at 96x96 is level 0: 41 bricks, 17 at half the target.)
run "view --target-frame-ms, a long drag" xview procedural:marschner-lobb:64 --brick 16 --size 96x96 --script "$dir/long_drag.json" --target-frame-ms 0.001 \
  --stats "$dir/long_drag.jsonl"
python3 - "$dir/long_drag.jsonl" << 'PY' || fail "--target-frame-ms: the cut did not coarsen while moving"
import json, sys
frames = [json.loads(line) for line in open(sys.argv[1])]
first = next(i for i, f in enumerate(frames) if f["converged"])
still = frames[first]["working_set_bricks"]
moving = [f["working_set_bricks"] for f in frames[first + 1:] if f["step_voxels"] == 2.0]
print("converged", still, "moving", moving, "last", frames[-1]["working_set_bricks"])
sys.exit(0 if moving and min(moving) < min(still, frames[-1]["working_set_bricks"]) else 1)
PY

# set_iso, then a screenshot: render with --iso.
cat > "$dir/iso.json" << JSON
[{"event": "set_iso", "value": 60}, {"event": "screenshot", "file": "$dir/v2.png"}]
JSON
run "view --script set_iso" xview $vol --script "$dir/iso.json"
run "render --iso 60" "$ropecast" render $vol --converge --iso 60 -o "$dir/r2.png"
same "isovalue change = render --iso" "$dir/v2.png" "$dir/r2.png"
differs "the isovalue changed the view" "$dir/v2.png" "$dir/v0.png"
# set_crop, then a screenshot: render with --crop; --crop at start gives the same view.
cat > "$dir/crop.json" << JSON
[{"event": "set_crop", "crop": "10:,:30,4:40"}, {"event": "screenshot", "file": "$dir/v3.png"}]
JSON
run "view --script set_crop" xview $vol --script "$dir/crop.json"
run "render --crop" "$ropecast" render $vol --converge --crop 10:,:30,4:40 -o "$dir/r3.png"
same "crop change = render --crop" "$dir/v3.png" "$dir/r3.png"
differs "the crop changed the view" "$dir/v3.png" "$dir/v0.png"
run "view --crop" xview $vol --crop 10:,:30,4:40 --screenshot "$dir/v4.png"
same "view --crop = render --crop" "$dir/v4.png" "$dir/r3.png"

# set_lighting: the isosurface's color and material, and DVR unlit, as render's options draw them.
cat > "$dir/lighting.json" << JSON
[{"event": "set_lighting", "iso_color": [1, 0.2, 0.1], "material": [0.4, 0.5, 0.1, 8]},
 {"event": "screenshot", "file": "$dir/vlit.png"},
 {"event": "set_mode", "mode": "dvr"}, {"event": "set_lighting", "shading": false},
 {"event": "screenshot", "file": "$dir/vunlit.png"}]
JSON
run "view --script set_lighting" xview $vol --script "$dir/lighting.json"
run "render --iso-color --material" "$ropecast" render $vol --converge --iso-color 1,0.2,0.1 --material 0.4,0.5,0.1,8 \
  -o "$dir/rlit.png"
run "render --mode dvr --shading off" "$ropecast" render $vol --converge --mode dvr --shading off --material 0.4,0.5,0.1,8 \
  -o "$dir/runlit.png"
same "set_lighting = render --iso-color --material" "$dir/vlit.png" "$dir/rlit.png"
differs "the lighting changed the view" "$dir/vlit.png" "$dir/v0.png"
same "DVR unlit = render --shading off" "$dir/vunlit.png" "$dir/runlit.png"

# A time series (a NIfTI file of two volumes, spheres of two sizes): set_time_point shows the other, as render
# --time draws it, and back; --time picks the one shown first; a time point past the series, or one of an input
# of one, fails the script, naming it.
write_nifti_series "$dir/series.nii" || exit 1
series="$dir/series.nii --size 96x96 --iso 1500"
cat > "$dir/time.json" << JSON
[{"event": "screenshot", "file": "$dir/t0.png"},
 {"event": "set_time_point", "time_point": 1}, {"event": "screenshot", "file": "$dir/t1.png"},
 {"event": "set_time_point", "time_point": 0}, {"event": "screenshot", "file": "$dir/t0b.png"}]
JSON
run "view --script set_time_point" xview $series --script "$dir/time.json"
run "render --time 0" "$ropecast" render $series --converge -o "$dir/rt0.png"
run "render --time 1" "$ropecast" render $series --converge --time 1 -o "$dir/rt1.png"
same "time point 0 = render" "$dir/t0.png" "$dir/rt0.png"
same "time point 1 = render --time 1" "$dir/t1.png" "$dir/rt1.png"
same "back to time point 0" "$dir/t0b.png" "$dir/rt0.png"
differs "the time point changed the view" "$dir/t1.png" "$dir/t0.png"
run "view --time 1" xview $series --time 1 --screenshot "$dir/t1s.png"
same "view --time 1 = render --time 1" "$dir/t1s.png" "$dir/rt1.png"
# Playing: the stats say which time point each frame drew; it comes back to the first after the last.
echo '[{"event": "play", "playing": true, "seconds_each": 0.1}, {"event": "quit", "at": 3}]' > "$dir/play.json"
run "view --script play" xview $series --script "$dir/play.json" --stats "$dir/play.jsonl"
python3 - "$dir/play.jsonl" <<'PY' || fail "playing did not go 0, 1, 0: $(cut -c1-60 "$dir/play.jsonl" | head -5)"
import json, sys
shown = [json.loads(line)["time_point"] for line in open(sys.argv[1])]
changes = [t for i, t in enumerate(shown) if i == 0 or t != shown[i - 1]]
sys.exit(0 if changes[:3] == [0, 1, 0] else 1)
PY
# A file of two channels: set_channel shows the other, as render --channel draws it; the stats say which.
write_nifti_series "$dir/channels.nii" channels || exit 1
channels="$dir/channels.nii --size 96x96 --iso 1500"
cat > "$dir/channel.json" << JSON
[{"event": "screenshot", "file": "$dir/c0.png"},
 {"event": "set_channel", "channel": 1}, {"event": "screenshot", "file": "$dir/c1.png"}]
JSON
run "view --script set_channel" xview $channels --script "$dir/channel.json" --stats "$dir/channel.jsonl"
run "render --channel 1" "$ropecast" render $channels --converge --channel 1 -o "$dir/rc1.png"
same "channel 0 = render" "$dir/c0.png" "$dir/rt0.png"
same "channel 1 = render --channel 1" "$dir/c1.png" "$dir/rc1.png"
grep -q '"channel":1' <<< "$(tail -n 1 "$dir/channel.jsonl")" || fail "the stats do not say channel 1: $(tail -n 1 "$dir/channel.jsonl")"
echo '[{"event": "set_time_point", "time_point": 2}, {"event": "screenshot", "file": "'"$dir"'/x.png"}]' > "$dir/time2.json"
xview $series --script "$dir/time2.json" > /dev/null 2> "$dir/err.txt" && fail "set_time_point 2 of 2"
grep -qF "event 0 (set_time_point): view: time point 2: the input $dir/series.nii holds 2 (0 to 1)" "$dir/err.txt" ||
  fail "no refusal of time point 2: $(cat "$dir/err.txt")"
xview $vol --script "$dir/time2.json" > /dev/null 2> "$dir/err.txt" && fail "set_time_point of a procedural input"
grep -qF "holds one time point" "$dir/err.txt" || fail "no refusal of a time point of one: $(cat "$dir/err.txt")"
echo '[{"event": "play", "playing": true}]' > "$dir/play1.json"
xview $vol --script "$dir/play1.json" > /dev/null 2> "$dir/err.txt" && fail "play of a procedural input"
grep -qF "holds one time point; there is nothing to play" "$dir/err.txt" || fail "no refusal of play: $(cat "$dir/err.txt")"
echo '[{"event": "set_channel", "channel": 1}]' > "$dir/channel1.json"
xview $series --script "$dir/channel1.json" > /dev/null 2> "$dir/err.txt" && fail "set_channel of a time series"
grep -qF "holds one channel; channel 1 does not exist" "$dir/err.txt" || fail "no refusal of a channel of one: $(cat "$dir/err.txt")"
[ ! -e "$dir/x.png" ] || fail "a refused time point left a screenshot"
# set_clip_plane, then a screenshot: render with --clip-plane; then without caps: render --caps off.
cat > "$dir/plane.json" << JSON
[{"event": "set_clip_plane", "plane": [24, 24, 24, -1, -0.5, 0.2]}, {"event": "screenshot", "file": "$dir/v5.png"},
 {"event": "set_caps", "caps": false}, {"event": "screenshot", "file": "$dir/v5o.png"}]
JSON
run "view --script set_clip_plane, set_caps" xview $vol --script "$dir/plane.json"
run "render --clip-plane" "$ropecast" render $vol --converge --clip-plane 24,24,24,-1,-0.5,0.2 -o "$dir/r5.png"
same "clip plane = render --clip-plane" "$dir/v5.png" "$dir/r5.png"
differs "the clip plane changed the view" "$dir/v5.png" "$dir/v0.png"
run "render --clip-plane --caps off" "$ropecast" render $vol --converge --clip-plane 24,24,24,-1,-0.5,0.2 --caps off \
  -o "$dir/r5o.png"
same "set_caps false = render --caps off" "$dir/v5o.png" "$dir/r5o.png"
differs "the caps changed the view" "$dir/v5o.png" "$dir/v5.png"
# set_view: the named side of the patient at the current distance, as render --view draws it; reset_camera
# returns to the starting view.
cat > "$dir/named.json" << JSON
[{"event": "set_view", "view": "superior"}, {"event": "screenshot", "file": "$dir/v8.png"},
 {"event": "reset_camera"}, {"event": "screenshot", "file": "$dir/v9.png"}]
JSON
run "view --script set_view" xview $vol --script "$dir/named.json"
run "render --view superior" "$ropecast" render $vol --converge --view superior -o "$dir/r8.png"
same "set_view superior = render --view superior" "$dir/v8.png" "$dir/r8.png"
differs "the named view changed the view" "$dir/v8.png" "$dir/v0.png"
same "reset_camera after set_view = the starting view" "$dir/v9.png" "$dir/v0.png"
run "view --view left" xview $vol --view left --screenshot "$dir/v10.png"
run "render --view left" "$ropecast" render $vol --converge --view left -o "$dir/r10.png"
same "view --view left = render --view left" "$dir/v10.png" "$dir/r10.png"
# probe: the voxel under a pixel of the converged view and its value. A ball (64 voxels) seen from +x, above the
# middle of a 96x96 view (40 degrees; the camera looks below its center, so that a pixel's depth read from
# another row would miss it): the voxels where the rays through two pixels meet its surface, each within a voxel
# of that pixel's ray and at the surface's distance from the center; the value what extract reads there and the
# point in the world within the voxel; with MIP a larger value on the same ray; in a corner nothing, and past the window's edge no pixel. center_at (a double
# click) on the second pixel brings its voxel to the middle of the view, and a drag turns the view about it; on
# nothing it warns and the camera stays. measure (two right clicks) between the two pixels: the ruler ends on
# their voxels, its length their distance; to nothing it warns.
"$ropecast" convert procedural:sphere:64 --brick 16 -q -o "$dir/ball.rcast" || fail "convert the ball"
cat > "$dir/probe.json" << JSON
[{"event": "probe", "pos": [48, 30]}, {"event": "probe", "pos": [40, 22]}, {"event": "probe", "pos": [2, 2]},
 {"event": "probe", "pos": [500, 3]}, {"event": "set_mode", "mode": "mip"}, {"event": "probe", "pos": [48, 30]},
 {"event": "set_mode", "mode": "iso"}, {"event": "measure", "from": [48, 30], "to": [40, 22]},
 {"event": "measure", "from": [48, 30], "to": [2, 2]},
 {"event": "center_at", "pos": [40, 22]}, {"event": "probe", "pos": [47, 47]},
 {"event": "drag", "from": [48, 48], "to": [68, 58], "steps": 4}, {"event": "probe", "pos": [47, 47]},
 {"event": "center_at", "pos": [2, 2]}]
JSON
run "view --script probe" xview "$dir/ball.rcast" --size 96x96 --eye 182,32,32 --target 32,32,12 --up 0,0,1 \
  --script "$dir/probe.json"
mapfile -t probes < <(grep "^ropecast view: probe at" "$dir/out.txt")
probe_voxel() { sed -n 's/.*: voxel \([0-9]*\), \([0-9]*\), \([0-9]*\)  value \([^ ]*\)  at .*$/\1 \2 \3 \4/p' <<< "$1"; }
on_pixel_ray() {  # on_pixel_ray PX PY X Y Z: the voxel's center within a voxel of the ray through pixel PX, PY
  awk -v px="$1" -v py="$2" -v x="$3" -v y="$4" -v z="$5" 'BEGIN {
    t = sin(atan2(0, -1) / 9) / cos(atan2(0, -1) / 9)                        # tan(20 degrees)
    ex = 182; ey = 32; ez = 32; fx = -150; fy = 0; fz = -20                   # forward: the target 32,32,12
    n = sqrt(fx * fx + fy * fy + fz * fz); fx /= n; fy /= n; fz /= n
    rx = fy; ry = -fx; n = sqrt(rx * rx + ry * ry); rx /= n; ry /= n          # right = forward x z
    ux = ry * fz; uy = -rx * fz; uz = rx * fy - ry * fx                       # up = right x forward
    sx = (2 * (px + 0.5) / 96 - 1) * t; sy = (1 - 2 * (py + 0.5) / 96) * t
    dx = fx + sx * rx + sy * ux; dy = fy + sx * ry + sy * uy; dz = fz + sy * uz
    n = sqrt(dx * dx + dy * dy + dz * dz); dx /= n; dy /= n; dz /= n
    vx = x + 0.5 - ex; vy = y + 0.5 - ey; vz = z + 0.5 - ez; along = vx * dx + vy * dy + vz * dz
    ox = vx - along * dx; oy = vy - along * dy; oz = vz - along * dz
    cx = x + 0.5 - 32; cy = y + 0.5 - 32; cz = z + 0.5 - 32; r = sqrt(cx * cx + cy * cy + cz * cz)
    exit !(sqrt(ox * ox + oy * oy + oz * oz) < 1 && r > 16 && r < 30) }'
}
for k in 0 1; do
  pixel=$(sed -n 's/.*probe at \([0-9]*\), \([0-9]*\):.*/\1 \2/p' <<< "${probes[$k]:-}")
  read -r px py pz pvalue <<< "$(probe_voxel "${probes[$k]:-}")"
  if [ -z "${pvalue:-}" ] || [ -z "$pixel" ]; then fail "probe: no voxel on the ball: ${probes[$k]:-none}"; continue; fi
  # shellcheck disable=SC2086
  on_pixel_ray $pixel "$px" "$py" "$pz" || fail "probe: ${probes[$k]} is not on the ball's surface under that pixel"
  # The point in the world (the volume's own axes here): within the voxel.
  at=$(sed -n 's/.*  at \(.*\)$/\1/p' <<< "${probes[$k]}" | tr -d ',')
  awk -v p="$at" -v v="$px $py $pz" 'BEGIN { split(p, a, " "); split(v, b, " ")
    for (i = 1; i <= 3; ++i) if (!(a[i] >= b[i] - 0.001 && a[i] <= b[i] + 1.001)) exit 1 }' ||
    fail "probe: the point ${at:-none} is not in voxel $px, $py, $pz"
  "$ropecast" extract "$dir/ball.rcast" --crop "$px:$((px + 1)),$py:$((py + 1)),$pz:$((pz + 1))" -o "$dir/voxel.raw" > /dev/null
  [ "$(od -An -tu1 "$dir/voxel.raw" | tr -d ' ')" = "$pvalue" ] ||
    fail "probe: value $pvalue, extract reads $(od -An -tu1 "$dir/voxel.raw") at $px, $py, $pz"
done
read -r _ _ _ surface <<< "$(probe_voxel "${probes[0]:-}")"
read -r _ _ _ largest <<< "$(probe_voxel "${probes[4]:-}")"
[ "${largest:-0}" -gt "${surface:-255}" ] || fail "probe: the MIP's value ${largest:-none} is not above the surface's"
grep -q "probe at 2, 2: nothing under the pointer" <<< "${probes[2]:-}" || fail "probe in a corner: ${probes[2]:-none}"
grep -q "probe at 500, 3: outside the 3D view" <<< "${probes[3]:-}" || fail "probe past the edge: ${probes[3]:-none}"
read -r cx cy cz _ <<< "$(probe_voxel "${probes[1]:-}")"
for k in 5 6; do
  read -r x y z _ <<< "$(probe_voxel "${probes[$k]:-}")"
  awk -v a="${cx:-0} ${cy:-0} ${cz:-0}" -v b="${x:--9} ${y:--9} ${z:--9}" 'BEGIN { split(a, p); split(b, q)
    for (i = 1; i <= 3; ++i) if ((p[i] - q[i]) ^ 2 > 1) exit 1 }' ||
    fail "center_at: the middle of the view shows ${probes[$k]:-none}, not the voxel centered on (${probes[1]:-none})"
done
read -r ax ay az _ <<< "$(probe_voxel "${probes[0]:-}")"
expected="from voxel ${ax:-}, ${ay:-}, ${az:-} to voxel ${cx:-}, ${cy:-}, ${cz:-}"
ruler=$(grep "^ropecast view: ruler: " "$dir/out.txt")
length=$(sed -n "s/^ropecast view: ruler: length \([0-9.]*\) $expected\$/\1/p" <<< "$ruler")
if [ -z "$length" ]; then
  fail "measure: the ruler is not $expected: ${ruler:-none}"
else
  awk -v l="$length" -v a="$ax $ay $az" -v b="$cx $cy $cz" 'BEGIN { split(a, p); split(b, q)
    d = sqrt((p[1] - q[1]) ^ 2 + (p[2] - q[2]) ^ 2 + (p[3] - q[3]) ^ 2); exit !(l > d - 1.8 && l < d + 1.8) }' ||
    fail "measure: length $length, the voxels lie $ax,$ay,$az and $cx,$cy,$cz"
fi
grep -q "event 8 (measure): nothing under the pointer for an end of the ruler; no ruler" "$dir/err.txt" ||
  fail "measure to nothing: no warning naming the event: $(cat "$dir/err.txt")"
grep -q "event 13 (center_at): nothing under the pointer to center on; the camera stays" "$dir/err.txt" ||
  fail "center_at on nothing: no warning naming the event: $(cat "$dir/err.txt")"
printf '[{"event": "set_crop", "crop": "0:60,:,:"}, {"event": "quit"}]' > "$dir/crop_out.json"
xview $vol --script "$dir/crop_out.json" > /dev/null 2> "$dir/err.txt" && fail "set_crop past the volume: exit 0"
grep -q "event 0 (set_crop): --crop: the x range 0:60 does not lie" "$dir/err.txt" ||
  fail "set_crop past the volume: no message naming the event: $(cat "$dir/err.txt")"
# An isovalue outside the data is taken, with a warning that names the event (render --iso warns alike).
printf '[{"event": "set_iso", "value": 100000}, {"event": "quit"}]' > "$dir/iso_out.json"
run "view set_iso outside the data" xview $vol --script "$dir/iso_out.json"
grep -q "event 0 (set_iso): isovalue 100000 lies outside" "$dir/err.txt" ||
  fail "set_iso outside the data: no warning naming the event: $(cat "$dir/err.txt")"

# Back to an isovalue seen before: what it needs is still resident, so nothing is read or uploaded again (the
# round trip reads and uploads what the one-way change does).
cat > "$dir/iso_there.json" << JSON
[{"event": "wait_converged"}, {"event": "set_iso", "value": 60}, {"event": "wait_converged"}]
JSON
cat > "$dir/iso_back.json" << JSON
[{"event": "wait_converged"}, {"event": "set_iso", "value": 60}, {"event": "wait_converged"},
 {"event": "set_iso", "value": 127.5}, {"event": "wait_converged"}]
JSON
run "view set_iso there" xview $vol --script "$dir/iso_there.json" --stats "$dir/there.jsonl"
run "view set_iso there and back" xview $vol --script "$dir/iso_back.json" --stats "$dir/back.jsonl"
sums() { python3 -c 'import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
print(sum(r["bytes_read"] for r in rows), sum(r["bricks_uploaded"] for r in rows))' "$1"; }
there=$(sums "$dir/there.jsonl"); back=$(sums "$dir/back.jsonl")
[ "$there" = "$back" ] || fail "returning to an isovalue read or uploaded again: bytes, uploads $there one way, $back there and back"
[ "$(tail -n 1 "$dir/back.jsonl" | grep -c '"converged":true')" = 1 ] || fail "set_iso round trip did not converge"

# DVR: load a transfer function file; --screenshot after the script.
cat > "$dir/tf.json" << JSON
[{"event": "set_mode", "mode": "dvr"}, {"event": "load_tf", "tf": "$data/tf/sphere_shells.json"}]
JSON
run "view --script set_mode load_tf" xview $vol --script "$dir/tf.json" --screenshot "$dir/v3.png"
run "render --mode dvr --tf" "$ropecast" render $vol --converge --mode dvr --tf "$data/tf/sphere_shells.json" \
  -o "$dir/r3.png"
same "DVR with a loaded TF = render --tf" "$dir/v3.png" "$dir/r3.png"
# MIP: a switch to it shows its default transfer function (gray), as render --mode mip does.
# Then a window: the gray preset stretched over it, as render --tf-range draws it.
printf '[{"event": "set_mode", "mode": "mip"}, {"event": "screenshot", "file": "%s"}, {"event": "set_tf_range", "range": [60, 200]}, {"event": "screenshot", "file": "%s"}]' \
  "$dir/v6.png" "$dir/v7.png" > "$dir/mip.json"
run "view --script set_mode mip, set_tf_range" xview $vol --script "$dir/mip.json"
run "render --mode mip" "$ropecast" render $vol --converge --mode mip -o "$dir/r6.png"
same "MIP switch = render --mode mip" "$dir/v6.png" "$dir/r6.png"
differs "the MIP switch changed the view" "$dir/v6.png" "$dir/v0.png"
run "render --mode mip --tf-range" "$ropecast" render $vol --converge --mode mip --tf-range 60,200 -o "$dir/r7.png"
same "set_tf_range = render --tf-range" "$dir/v7.png" "$dir/r7.png"
differs "the window changed the view" "$dir/v7.png" "$dir/v6.png"
# A switch to DVR whose stored gradients no longer fit one brick in --gpu-budget goes on with computed ones (and
# says so), and --stats numbers the frames of the session on, across the renderer the switch makes anew.
cat > "$dir/tight.json" << JSON
[{"event": "wait_converged"}, {"event": "set_mode", "mode": "dvr"}, {"event": "load_tf", "tf": "$data/tf/sphere_shells.json"}]
JSON
run "view: DVR in a pool too small for stored gradients" xview procedural:marschner-lobb:48 --brick 8 --size 96x96 \
  --gpu-budget 8K --script "$dir/tight.json" --screenshot "$dir/v3t.png" --stats "$dir/tight.jsonl"
grep -q "computing them per sample instead" "$dir/err.txt" || fail "the gradients' fallback was not said: $(cat "$dir/err.txt")"
run "render --gradients computed in that pool" "$ropecast" render procedural:marschner-lobb:48 --brick 8 --size 96x96 \
  --gpu-budget 8K --converge --mode dvr --tf "$data/tf/sphere_shells.json" --gradients computed -o "$dir/r3t.png"
same "DVR with computed gradients = render --gradients computed" "$dir/v3t.png" "$dir/r3t.png"
python3 -c 'import json, sys; f = [json.loads(l)["frame"] for l in open(sys.argv[1])]; sys.exit(f != list(range(len(f))))' \
  "$dir/tight.jsonl" || fail "--stats frames are not 0, 1, 2, ...: $(cut -c1-20 "$dir/tight.jsonl" | tr '\n' ' ')"

# A bad script is refused with its name and the event, before any window opens.
echo '[{"event": "spin"}]' > "$dir/bad.json"
"$ropecast" view $vol --script "$dir/bad.json" > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" -ge 1 ] && [ "$rc" -le 127 ] && grep -q "bad.json: event 0 (spin)" "$dir/err.txt"; } ||
  fail "bad script: exit $rc: $(cat "$dir/err.txt")"

# An output that is an input is refused before anything is read or written.
"$ropecast" view $vol --script "$dir/bad.json" --stats "$dir/bad.json" > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" -ge 1 ] && [ "$rc" -le 127 ] && grep -q -- "--stats" "$dir/err.txt" && grep -q -- "--script" "$dir/err.txt"; } ||
  fail "--stats onto --script: exit $rc: $(cat "$dir/err.txt")"
grep -q spin "$dir/bad.json" || fail "--stats onto --script overwrote the script"

# The files a script's events name are outputs and inputs too: a screenshot onto the input store, --stats onto
# a transfer function an event loads, and a screenshot into a missing folder are refused before the window.
"$ropecast" convert procedural:sphere:16 -o "$dir/in.png" --quiet || fail "convert for the setup"
cp "$dir/in.png" "$dir/in_copy.rcast"
echo "[{\"event\": \"screenshot\", \"file\": \"$dir/in.png\"}]" > "$dir/onto_input.json"
"$ropecast" view "$dir/in.png" --script "$dir/onto_input.json" > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" = 1 ] && grep -qF "a screenshot event of --script $dir/onto_input.json: $dir/in.png: the same file as the input" "$dir/err.txt"; } ||
  fail "a script's screenshot onto the input: exit $rc: $(cat "$dir/err.txt")"
cmp -s "$dir/in.png" "$dir/in_copy.rcast" || fail "a script's screenshot overwrote the input store"
echo "[{\"event\": \"load_tf\", \"tf\": \"$data/tf/sphere_shells.json\"}]" > "$dir/loads_tf.json"
cp "$data/tf/sphere_shells.json" "$dir/shells.json"
echo "[{\"event\": \"load_tf\", \"tf\": \"$dir/shells.json\"}]" > "$dir/loads_tf.json"
"$ropecast" view $vol --script "$dir/loads_tf.json" --stats "$dir/shells.json" > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" = 1 ] && grep -qF "the same file as a load_tf event of --script" "$dir/err.txt"; } ||
  fail "--stats onto a script's transfer function: exit $rc: $(cat "$dir/err.txt")"
cmp -s "$dir/shells.json" "$data/tf/sphere_shells.json" || fail "--stats overwrote a script's transfer function"
echo "[{\"event\": \"screenshot\", \"file\": \"$dir/nodir/x.png\"}]" > "$dir/nodir.json"
"$ropecast" view $vol --script "$dir/nodir.json" > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" = 1 ] && grep -qF "$dir/nodir/x.png: its folder" "$dir/err.txt"; } ||
  fail "a script's screenshot into a missing folder: exit $rc: $(cat "$dir/err.txt")"

# A screenshot with the panels, then quit: the screenshot is taken (after the frame's panels) before quitting.
cat > "$dir/panels.json" << JSON
[{"event": "screenshot", "file": "$dir/vp.png", "panels": true}, {"event": "quit"}]
JSON
run "view --script screenshot with panels, quit" xview $vol --script "$dir/panels.json"
[ -s "$dir/vp.png" ] || fail "a screenshot with panels followed by quit was not written"

# --max-frames bounds every wait: with W held the camera never stops, so neither the script's waits nor the
# --screenshot after it can converge; each runs after --max-frames frames, with a warning naming it.
cat > "$dir/held.json" << JSON
[{"event": "key_down", "key": "w"}, {"event": "wait_converged"}, {"event": "screenshot", "file": "$dir/held.png"}]
JSON
timeout 300 xvfb-run -a -f "$dir/Xauthority" -s "-screen 0 320x240x24" "$ropecast" view $vol --script "$dir/held.json" --max-frames 20 \
  --screenshot "$dir/held_end.png" > /dev/null 2> "$dir/err.txt"
rc=$?
{ [ "$rc" = 0 ] && [ -s "$dir/held.png" ] && [ -s "$dir/held_end.png" ]; } ||
  fail "a held key with --max-frames 20: exit $rc (124: still running after 300 s): $(cat "$dir/err.txt")"
for what in "held.json: event 1 (wait_converged): not converged after 20 frames" \
  "held.json: event 2 (screenshot): not converged after 20 frames" "--screenshot: not converged after 20 frames"; do
  grep -qF -- "$what" "$dir/err.txt" || fail "a held key: no warning \"$what\": $(cat "$dir/err.txt")"
done

# --screenshot with a script that quits: quit ends the script, and the screenshot is taken (one wheel click: the
# distance 3 * 0.9).
cat > "$dir/quits.json" << JSON
[{"event": "wheel", "clicks": 1}, {"event": "quit"}, {"event": "set_iso", "value": 60}]
JSON
run "view --script ... quit --screenshot" xview $vol --script "$dir/quits.json" --screenshot "$dir/vq.png"
run "render --orbit 30,20,2.7" "$ropecast" render $vol --converge --orbit 30,20,2.7 -o "$dir/rq.png"
same "--screenshot after a quit = render at the documented distance" "$dir/vq.png" "$dir/rq.png"

# Two screenshots with panels in a row each write their file, and a wheel right after the second does not reach
# it: it shows the state at its event, as a lone one does (the stats' fps text differs from run to run: 30 dB
# at 1024x768; the wheel's zoom would be under 10).
cat > "$dir/panels2.json" << JSON
[{"event": "screenshot", "file": "$dir/pa.png", "panels": true},
 {"event": "screenshot", "file": "$dir/pb.png", "panels": true}, {"event": "wheel", "clicks": 8}]
JSON
cat > "$dir/panels1.json" << JSON
[{"event": "screenshot", "file": "$dir/p1.png", "panels": true}]
JSON
big="procedural:marschner-lobb:48 --brick 16 --size 1024x768"
run "view two screenshots with panels" xrun -s "-screen 0 1100x800x24" "$ropecast" view $big --script "$dir/panels2.json"
run "view one screenshot with panels" xrun -s "-screen 0 1100x800x24" "$ropecast" view $big --script "$dir/panels1.json"
[ -s "$dir/pa.png" ] || fail "the first of two screenshots with panels was not written"
for shot in pa pb; do
  "$ropecast" compare "$dir/p1.png" "$dir/$shot.png" --min-psnr 30 > "$dir/cmp.txt" 2>&1 ||
    fail "$shot.png with panels is not the state at its event: $(cat "$dir/cmp.txt")"
done

# While the crop controls are open (a script's set_crop opens them), the crop box is outlined over the view,
# in the window's panel screenshot, never in the 3D view's.
printf '[{"event": "set_crop", "crop": "2:40,:,3:"}, {"event": "screenshot", "file": "%s", "panels": true}, {"event": "screenshot", "file": "%s"}]' \
  "$dir/outline.png" "$dir/outline_view.png" > "$dir/outline.json"
run "view a crop box's outline" xrun -s "-screen 0 800x600x24" "$ropecast" view procedural:marschner-lobb:48 --brick 16 \
  --size 700x500 --script "$dir/outline.json"
outline_pixels() {  # pixels of the outline's amber (255, 200, 60 at 86 %) in a PNG
  oiiotool "$1" --ch R,G,B -d uint8 -o "$dir/outline.ppm" 2> /dev/null || { echo -1; return; }
  python3 - "$dir/outline.ppm" <<'PY'
import sys
data = open(sys.argv[1], "rb").read()
fields, pos = [], 0
while len(fields) < 4:  # P6, width, height, maxval, each after whitespace
    while data[pos:pos + 1].isspace(): pos += 1
    start = pos
    while not data[pos:pos + 1].isspace(): pos += 1
    fields.append(data[start:pos])
pixels = data[pos + 1:]
print(sum(1 for i in range(0, len(pixels), 3)
          if pixels[i] > 200 and 150 < pixels[i + 1] < 215 and pixels[i + 2] < 110))
PY
}
n=$(outline_pixels "$dir/outline.png"); m=$(outline_pixels "$dir/outline_view.png")
{ [ "$n" -ge 50 ] && [ "$m" = 0 ]; } && echo "ok   the crop box outlined: $n pixels with panels, $m in the view" ||
  fail "the crop box's outline: $n pixels with panels (at least 50), $m in the 3D view (none)"

# save_camera appends to a path with timed keyframes a timed one (a second after the last): render reads it.
echo '[{"orbit": [30, 20, 3], "time": 0}, {"orbit": [60, 20, 3], "time": 0.5}]' > "$dir/timed.json"
echo "[{\"event\": \"save_camera\", \"file\": \"$dir/timed.json\"}]" > "$dir/save_timed.json"
run "view save_camera onto a timed path" xview $vol --script "$dir/save_timed.json"
run "render --path the timed path" "$ropecast" render $vol --path "$dir/timed.json" --frames 3 -o "$dir/timed.png"
python3 -c 'import json, sys; sys.exit(json.load(open(sys.argv[1]))[-1].get("time") != 1.5)' "$dir/timed.json" ||
  fail "save_camera onto a timed path: the new keyframe is not at 1.5 s: $(cat "$dir/timed.json")"

# A converged view sleeps until something happens: the three seconds of waiting for the script's quit draw no
# frame (a viewer that went on rendering would write a stats line per frame, tens of them at least).
echo '[{"event": "wait_converged"}, {"event": "quit", "at": 3}]' > "$dir/idle.json"
run "view idles once converged" xview $vol --script "$dir/idle.json" --stats "$dir/idle.jsonl"
after=$(python3 -c 'import json, sys
frames = [json.loads(line) for line in open(sys.argv[1])]
first = next((i for i, f in enumerate(frames) if f["converged"]), len(frames))
print(len(frames) - first - 1)' "$dir/idle.jsonl")
[ "$after" -le 2 ] || fail "a converged view went on rendering: $after frames after it converged"

# The window closed by the user (the window manager's close button: WM_DELETE_WINDOW) before a script's
# screenshot is written: exit 1, the message names the event and its file, and no file appears.
cat > "$dir/xclose.py" << 'PY'
import ctypes
X = ctypes.cdll.LoadLibrary("libX11.so.6")
X.XOpenDisplay.restype = ctypes.c_void_p
X.XDefaultRootWindow.argtypes = [ctypes.c_void_p]
X.XDefaultRootWindow.restype = ctypes.c_ulong
X.XInternAtom.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int]
X.XInternAtom.restype = ctypes.c_ulong
X.XQueryTree.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.POINTER(ctypes.c_ulong),
                         ctypes.POINTER(ctypes.c_ulong), ctypes.POINTER(ctypes.POINTER(ctypes.c_ulong)),
                         ctypes.POINTER(ctypes.c_uint)]
X.XSendEvent.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_long, ctypes.c_void_p]
X.XSync.argtypes = [ctypes.c_void_p, ctypes.c_int]
class ClientMessage(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("serial", ctypes.c_ulong), ("send_event", ctypes.c_int),
                ("display", ctypes.c_void_p), ("window", ctypes.c_ulong), ("message_type", ctypes.c_ulong),
                ("format", ctypes.c_int), ("data", ctypes.c_long * 5)]
class XEvent(ctypes.Union):
    _fields_ = [("xclient", ClientMessage), ("pad", ctypes.c_long * 24)]
d = X.XOpenDisplay(None)
root = X.XDefaultRootWindow(d)
protocols = X.XInternAtom(d, b"WM_PROTOCOLS", 0)
delete = X.XInternAtom(d, b"WM_DELETE_WINDOW", 0)
r, p, n = ctypes.c_ulong(), ctypes.c_ulong(), ctypes.c_uint()
children = ctypes.POINTER(ctypes.c_ulong)()
X.XQueryTree(d, root, ctypes.byref(r), ctypes.byref(p), ctypes.byref(children), ctypes.byref(n))
for i in range(n.value):  # no window manager under Xvfb: the viewer's window is a child of the root
    e = XEvent()
    e.xclient.type = 33  # ClientMessage
    e.xclient.window = children[i]
    e.xclient.message_type = protocols
    e.xclient.format = 32
    e.xclient.data[0] = delete
    X.XSendEvent(d, children[i], 0, 0, ctypes.byref(e))
X.XSync(d, 0)
PY
echo "[{\"event\": \"screenshot\", \"file\": \"$dir/up.png\"},
 {\"event\": \"screenshot\", \"file\": \"$dir/late.png\", \"at\": 60}]" > "$dir/late.json"
xrun -s "-screen 0 320x240x24" bash -c '
  "$1" view $4 --script "$2/late.json" 2> "$2/err.txt" & viewer=$!
  for i in $(seq 200); do [ -e "$2/up.png" ] && break; sleep 0.3; done
  python3 "$3"
  wait $viewer' _ "$ropecast" "$dir" "$dir/xclose.py" "$vol" > /dev/null 2>&1
rc=$?
if [ "$rc" = 1 ] && [ -e "$dir/up.png" ] && [ ! -e "$dir/late.png" ] &&
  grep -qF "event 1 (screenshot): the window was closed before it wrote $dir/late.png" "$dir/err.txt"; then
  echo "ok   window closed before the script's screenshot"
else
  fail "window closed before the script's screenshot: exit $rc, up.png $([ -e "$dir/up.png" ] && echo written ||
    echo missing): $(cat "$dir/err.txt")"
fi

# The panels' buttons pass the guard the command line's outputs do. Run where the panels' default file names
# are inputs (the store view.png, --tf tf.json, --script cameras.json), click "save" (transfer function), "save
# camera" and "screenshot" (their places at 760x560), and nothing is overwritten.
cat > "$dir/xclick.py" << 'PY'
import ctypes, sys, time
X = ctypes.cdll.LoadLibrary("libX11.so.6"); T = ctypes.cdll.LoadLibrary("libXtst.so.6")
X.XOpenDisplay.restype = ctypes.c_void_p
X.XSync.argtypes = [ctypes.c_void_p, ctypes.c_int]
T.XTestFakeMotionEvent.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_ulong]
T.XTestFakeButtonEvent.argtypes = [ctypes.c_void_p, ctypes.c_uint, ctypes.c_int, ctypes.c_ulong]
d = X.XOpenDisplay(None)
for point in sys.argv[1:]:  # click X,Y with the left button
    x, y = map(int, point.split(","))
    T.XTestFakeMotionEvent(d, -1, x, y, 0); X.XSync(d, 0); time.sleep(0.2)
    T.XTestFakeButtonEvent(d, 1, 1, 0); X.XSync(d, 0); time.sleep(0.15)
    T.XTestFakeButtonEvent(d, 1, 0, 0); X.XSync(d, 0); time.sleep(0.2)
PY
if python3 -c 'import ctypes; ctypes.cdll.LoadLibrary("libXtst.so.6")' 2> /dev/null; then
  mkdir "$dir/panel" && cd "$dir/panel" || exit 1
  "$ropecast" convert procedural:sphere:16 -o view.png --quiet || fail "convert for the setup"
  cp "$data/tf/sphere_shells.json" tf.json
  # Up once ready.png is written; the wait keeps the window open for the clicks.
  echo '[{"event": "screenshot", "file": "ready.png"}, {"event": "wait_converged", "at": 6}]' > cameras.json
  cp view.png view.bak; cp tf.json tf.bak; cp cameras.json cameras.bak
  xrun -s "-screen 0 800x600x24" bash -c '
    "$1" view view.png --tf tf.json --mode dvr --size 760x560 --script cameras.json 2> err.txt & viewer=$!
    for i in $(seq 200); do [ -e ready.png ] && break; sleep 0.3; done
    python3 "$2" 77,404 470,274 468,320
    wait $viewer' _ "$ropecast" "$dir/xclick.py" > /dev/null 2>&1
  rc=$?
  [ "$rc" = 0 ] || fail "the panel's buttons: exit $rc: $(cat err.txt)"
  cmp -s view.png view.bak || fail "the panel's screenshot overwrote the input store"
  cmp -s tf.json tf.bak || fail "the panel's transfer function save overwrote --tf"
  cmp -s cameras.json cameras.bak || fail "the panel's save camera overwrote --script"
  for what in "the panel's transfer function tf.json: the same file as --tf tf.json" \
    "the panel's camera path cameras.json: the same file as --script cameras.json" \
    "the panel's screenshot view.png: the same file as the input view.png"; do
    grep -qF "$what" err.txt || fail "the panel's buttons: no \"$what\": $(cat err.txt)"
  done
  cd - > /dev/null || exit 1
else
  echo "skip: the panel's buttons (no libXtst to click them)"
fi

echo "$failures failure(s)"
[ "$failures" -eq 0 ]
