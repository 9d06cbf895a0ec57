#!/usr/bin/env bash
# The image module (tools/image_module.h): ropecast links no OpenImageIO and loads ropecast_images.so the first
# time a command needs an image other than a PNG (reference/png_codec.h); without the module, or with a wrong one,
# the commands that need none still work (render to PNG, compare and regress of PNGs among them) and those that do fail
# with a message that names it, leaving nothing behind.
# Usage: bash image_module.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
module="$(dirname "$ropecast")/ropecast_images.so"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

# expect_failure NAME PATTERN COMMAND...: the command must fail with 1..127 and print PATTERN on stderr.
expect_failure() {
  local name="$1" pattern="$2"
  shift 2
  "$@" > "$dir/out.txt" 2> "$dir/err.txt"
  local rc=$?
  if [ "$rc" -lt 1 ] || [ "$rc" -gt 127 ]; then fail "$name: exit code $rc"; return; fi
  if ! grep -qF -- "$pattern" "$dir/err.txt"; then
    fail "$name: stderr does not name '$pattern':"; cat "$dir/err.txt"; return
  fi
  echo "ok   $name (exit $rc): $(head -c 240 "$dir/err.txt")"
}

[ -f "$module" ] || { echo "FAIL: no $module beside $ropecast"; exit 1; }
if readelf -d "$ropecast" | grep NEEDED | grep -qi openimageio; then
  fail "ropecast needs OpenImageIO at start:"; readelf -d "$ropecast" | grep -i openimageio
else
  echo "ok   ropecast's needed libraries name no OpenImageIO"
fi
if nm -C "$module" | grep -q "TemporaryFile"; then
  fail "the module holds TemporaryFile code (its signal cleanup would be the module's, not the executable's)"
else
  echo "ok   the module makes no TemporaryFile"
fi

# Inputs, made with the full build: a raw volume and a folder of two PNG slices (color: read only here).
mkdir "$dir/slices" "$dir/alone" "$dir/wrong" "$dir/out"
head -c $((16 * 16 * 16)) /dev/urandom > "$dir/v_16x16x16_uint8.raw"
"$ropecast" render procedural:sphere:16 --size 16x16 -o "$dir/slices/s0.png" -q || exit 1
cp "$dir/slices/s0.png" "$dir/slices/s1.png"
"$ropecast" convert "$dir/v_16x16x16_uint8.raw" -o "$dir/v.rcast" -q || exit 1

# ropecast alone: what needs no image works.
cp "$ropecast" "$dir/alone/ropecast"
alone="$dir/alone/ropecast"
"$alone" info "$dir/v.rcast" > /dev/null && echo "ok   info without the module" || fail "info without the module"
"$alone" convert "$dir/v_16x16x16_uint8.raw" -o "$dir/out/raw.rcast" -q && echo "ok   convert raw without the module" ||
  fail "convert raw without the module"
rm -f "$dir/out/raw.rcast"
"$alone" render "$dir/v.rcast" --size 16x16 -o "$dir/out/x.png" -q && [ -s "$dir/out/x.png" ] &&
  echo "ok   render to PNG without the module" || fail "render to PNG without the module"
rm -f "$dir/out/x.png"
expect_failure "render with an EXR without the module" "ropecast_images.so, which is neither at $dir/alone/ropecast_images.so" \
  "$alone" render "$dir/v.rcast" --size 16x16 -o "$dir/out/x.png" --exr "$dir/out/x.exr"
expect_failure "render to JPEG without the module" "ropecast_images.so" \
  "$alone" render "$dir/v.rcast" --size 16x16 -o "$dir/out/x.jpg"
expect_failure "convert a PNG stack without the module" "ropecast_images.so" \
  "$alone" convert "$dir/slices" -o "$dir/out/s.rcast"
"$alone" compare "$dir/slices/s0.png" "$dir/slices/s1.png" > "$dir/cmp.txt" && grep -q '"psnr_db":"inf"' "$dir/cmp.txt" &&
  echo "ok   compare of PNGs without the module" || fail "compare of PNGs without the module: $(cat "$dir/cmp.txt")"
# regress of PNG goldens, its report's images included (the golden: s0.png, rendered as the case renders).
printf '{"cases": [{"name": "s", "input": "procedural:sphere:16", "options": ["--size", "16x16"], "golden": "slices/s0.png"}]}' > "$dir/suite.json"
"$alone" regress "$dir/suite.json" --report "$dir/report" > "$dir/reg.txt" 2>&1 && grep -q "1 cases, 0 failed" "$dir/reg.txt" &&
  [ -s "$dir/report/s.difference.png" ] && echo "ok   regress of PNG goldens without the module" ||
  fail "regress of PNG goldens without the module: $(cat "$dir/reg.txt")"
"$ropecast" render procedural:sphere:16 --size 16x16 -o "$dir/s.png" --exr "$dir/s.exr" -q || exit 1
expect_failure "compare of an EXR without the module" "ropecast_images.so" \
  "$alone" compare "$dir/s.exr" "$dir/slices/s0.png"
[ -z "$(ls -A "$dir/out")" ] && echo "ok   nothing written" || { fail "left behind:"; ls -A "$dir/out"; }

# A file of that name that is no module of this build.
cp "$ropecast" "$dir/wrong/ropecast"
echo "not a shared library" > "$dir/wrong/ropecast_images.so"
expect_failure "a module that does not load" "$dir/wrong/ropecast_images.so, which does not load" \
  "$dir/wrong/ropecast" render "$dir/v.rcast" -o "$dir/out/x.jpg"
other=$(ldd "$ropecast" | awk '/libzstd/ {print $3; exit}')
cp "$other" "$dir/wrong/ropecast_images.so"
expect_failure "another library under the module's name" "which is from another build of ropecast" \
  "$dir/wrong/ropecast" render "$dir/v.rcast" -o "$dir/out/x.jpg"
[ -z "$(ls -A "$dir/out")" ] && echo "ok   nothing written" || { fail "left behind:"; ls -A "$dir/out"; }

# With the module: an error raised inside it reaches the command line whole.
expect_failure "an error from inside the module" "readImage: cannot open '$dir/v_16x16x16_uint8.raw'" \
  "$ropecast" compare "$dir/v_16x16x16_uint8.raw" "$dir/slices/s0.png"
# (Images and image stacks through the module: render_outputs.sh, store_roundtrip.sh, regress.sh and the rest.)

[ "$failures" = 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "image_module: all checks passed"
