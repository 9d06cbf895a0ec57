#!/usr/bin/env bash
# `ropecast bench modes` on a small procedural input: bench.json has every configuration and every frame in
# the documented schema, frame_times.png is a real PNG of some size, images/ holds each configuration's last
# frame and the difference images (--no-plot: no frame_times.png); bad options fail with an exit code in
# 1..127 and a message naming them.
# Usage: bash bench_modes.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

# A run: 3 frames x 2 repetitions of the three default configurations, DVR.
if ! timeout 300 "$ropecast" bench modes procedural:sphere:32 --brick 8 --mode dvr --size 48x40 --frames 3 \
    --reps 2 --out "$dir/run" > "$dir/out.txt" 2> "$dir/err.txt"; then
  fail "bench modes run: exit $?"; cat "$dir/out.txt" "$dir/err.txt"
else
  cat "$dir/out.txt"
  /usr/bin/python3 - "$dir/run/bench.json" <<'PY' || fail "bench.json"
import json, sys
bench = json.load(open(sys.argv[1]))
assert set(bench) == {"settings", "gl_renderer", "configs"}, sorted(bench)
assert bench["gl_renderer"], "gl_renderer empty"
names = [c["name"] for c in bench["configs"]]
assert len(names) == 3 and len(set(names)) == 3, names
assert any("multipass" in n for n in names), names
keys = {"frame_ms", "raycast_ms", "draw_calls", "leaves", "bricks_resident", "bytes_uploaded"}
for c in bench["configs"]:
    assert len(c["frames"]) == 6, (c["name"], len(c["frames"]))
    for f in c["frames"]:
        assert set(f) == keys, sorted(f)
        assert f["frame_ms"] > 0 and f["raycast_ms"] > 0 and f["leaves"] > 0, f
        assert f["draw_calls"] == 1 if "multipass" not in c["name"] else f["draw_calls"] > 1, f
    # cold start per repetition: both repetitions upload in their first frame
    assert c["frames"][0]["bytes_uploaded"] > 0 and c["frames"][3]["bytes_uploaded"] > 0, c["name"]
print("ok   bench.json:", names)
PY
  png="$dir/run/frame_times.png"
  if [ "$(head -c 8 "$png" 2> /dev/null | od -An -tx1 | tr -d ' \n')" != "89504e470d0a1a0a" ]; then
    fail "frame_times.png is not a PNG"
  elif [ "$(stat -c %s "$png")" -lt 10000 ]; then
    fail "frame_times.png has only $(stat -c %s "$png") bytes"
  else
    echo "ok   frame_times.png ($(stat -c %s "$png") bytes)"
  fi
  for f in single-fragment.png single-compute.png multipass.png diff_multipass_vs_single-fragment.png; do
    [ -s "$dir/run/images/$f" ] && [ -z "$(find "$dir/run/images/$f" -size -20c)" ] || fail "images/$f missing"
  done
  grep -q "multipass" "$dir/out.txt" && grep -q "PSNR" "$dir/out.txt" || fail "no table printed"
fi

# --no-plot: the table, bench.json and images/, no frame_times.png (a machine without matplotlib); a maximum
# intensity projection, through its default transfer function.
if ! timeout 300 "$ropecast" bench modes procedural:sphere:32 --brick 8 --size 32x32 --frames 1 --reps 1 \
    --mode mip --configs single-fragment --out "$dir/noplot" --no-plot > "$dir/out.txt" 2> "$dir/err.txt"; then
  fail "bench modes --no-plot: exit $?"; cat "$dir/err.txt"
elif [ -e "$dir/noplot/frame_times.png" ] || [ ! -s "$dir/noplot/bench.json" ] ||
    [ ! -s "$dir/noplot/images/single-fragment.png" ] || ! grep -q "PSNR" "$dir/out.txt"; then
  fail "bench modes --no-plot wrote: $(ls "$dir/noplot")"
else
  echo "ok   --no-plot: $(ls "$dir/noplot" | tr '\n' ' ')"
  /usr/bin/python3 -c '
import json, sys
s = json.load(open(sys.argv[1]))["settings"]
assert (s["mode"], s["tf"]) == ("mip", "gray"), s' "$dir/noplot/bench.json" && echo "ok   mip settings" ||
    fail "bench.json of --mode mip"
fi

# --tf-range: recorded, and the windowed MIP is another image than the plain one.
if timeout 300 "$ropecast" bench modes procedural:sphere:32 --brick 8 --mode mip --tf-range 80,200 --size 32x32 \
    --frames 1 --reps 1 --configs single-fragment --out "$dir/window" --no-plot > "$dir/out.txt" 2> "$dir/err.txt"; then
  /usr/bin/python3 -c '
import json, sys
s = json.load(open(sys.argv[1]))["settings"]
assert s["tf_range"] == [80, 200], s' "$dir/window/bench.json" || fail "bench.json of --tf-range"
  d=$("$ropecast" compare "$dir/window/images/single-fragment.png" "$dir/noplot/images/single-fragment.png") ||
    fail "compare of the windowed and the plain MIP: $d"
  /usr/bin/python3 -c 'import json, sys; p = json.loads(sys.argv[1])["psnr_db"]; sys.exit(p == "inf" or p >= 40)' "$d" &&
    echo "ok   --tf-range" || fail "--tf-range changed nothing: $d"
else
  fail "bench modes --tf-range: exit $?"; cat "$dir/err.txt"
fi

# Into a folder of an earlier run: images/ shows this run's configurations alone, an earlier plot goes (it
# would pass for this run's); other files stay.
mkdir -p "$dir/noplot/images" && echo stale > "$dir/noplot/frame_times.png" && touch "$dir/noplot/images/multipass.png" "$dir/noplot/images/diff_multipass_vs_single-fragment.png" "$dir/noplot/images/notes.txt"
if timeout 300 "$ropecast" bench modes procedural:sphere:32 --brick 8 --size 32x32 --frames 1 --reps 1 \
    --configs single-fragment --out "$dir/noplot" --no-plot > "$dir/out.txt" 2> "$dir/err.txt"; then
  left=$(ls "$dir/noplot/images" | tr '\n' ' ')
  [ "$left" = "notes.txt single-fragment.png " ] && echo "ok   a second run: images/ holds $left" ||
    fail "a second run left images/ with: $left"
  [ ! -e "$dir/noplot/frame_times.png" ] || fail "a second run with --no-plot left the earlier frame_times.png"
else
  fail "bench modes, a second run: exit $?"; cat "$dir/err.txt"
fi

# expect_failure NAME PATTERN ARGS...
expect_failure() {
  local name="$1" pattern="$2"
  shift 2
  timeout 120 "$ropecast" bench modes "$@" > "$dir/out.txt" 2> "$dir/err.txt"
  local rc=$?
  if [ "$rc" -lt 1 ] || [ "$rc" -gt 127 ]; then fail "$name: exit code $rc"; return; fi
  if ! grep -qF -- "$pattern" "$dir/err.txt"; then
    fail "$name: stderr does not name '$pattern':"; cat "$dir/err.txt"; return
  fi
  echo "ok   $name (exit $rc): $(head -c 160 "$dir/err.txt" | tr '\n' ' ')"
}
vol="procedural:sphere:32"
expect_failure "an empty --out" "--out: expected a folder name" $vol --out ""
expect_failure "unknown config" "--configs: unknown configuration 'single-vulkan'" $vol --configs single-fragment,single-vulkan --out "$dir/e1"
expect_failure "config twice" "listed twice" $vol --configs multipass,multipass --out "$dir/e2"
expect_failure "no config named" "--configs: expected at least one of" $vol --configs "" --out "$dir/e2"
expect_failure "bad size" "--size" $vol --size 0x10 --out "$dir/e3"
expect_failure "zero reps" "--reps" $vol --reps 0 --out "$dir/e4"
expect_failure "bad mode" "--mode" $vol --mode average --out "$dir/e5"
expect_failure "missing store" "no such store file" "$dir/none.rcast" --out "$dir/e6"
expect_failure "path and orbit" "--path and --orbit" $vol --path x.json --orbit 1,2,3 --out "$dir/e7"
expect_failure "path and turn" "--path excludes --turn" $vol --path x.json --turn 45 --out "$dir/e7"
expect_failure "missing path" "nope.json" $vol --path "$dir/nope.json" --out "$dir/e8"
expect_failure "bad tf" "--tf" $vol --mode dvr --tf no-such-preset --out "$dir/e9"
expect_failure "empty --tf-range" "--tf-range 5,5: expected LO,HI with LO < HI" $vol --mode mip --tf-range 5,5 --out "$dir/e9"
printf 'x' > "$dir/file"
expect_failure "out is a file" "--out" $vol --out "$dir/file"
# Failures found after the folder is made (a pool with no slot; a damaged store is alike) take it away again.
expect_failure "pool without a slot" "--gpu-budget 1 bytes holds no brick slot" $vol --gpu-budget 1 --out "$dir/e10/deeper"
for e in e1 e2 e6 e7 e10; do [ -e "$dir/$e" ] && fail "a failed run ($e) left its --out folder"; done

if [ "$failures" -ne 0 ]; then echo "$failures failure(s)"; exit 1; fi
echo "all passed"
