#!/usr/bin/env bash
# `ropecast regress` end to end: a missing golden fails and says how to create it, --update writes the failing
# and missing goldens only, --update-all all of them, a golden that is not RGB fails, renders repeat exactly, a changed image fails with its
# figures, --report writes the page with failing cases first, --jobs renders the same images, bad suites exit
# 2, and no golden or report file may be an input.
# Usage: bash regress.sh /path/to/ropecast
set -uo pipefail
ropecast="$(realpath "$1")"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
# expect RC NAME PATTERN ARGS...: `ropecast regress ARGS` exits RC and prints PATTERN (stdout or stderr).
expect() {
  local want="$1" name="$2" pattern="$3"
  shift 3
  "$ropecast" regress "$@" > "$dir/out.txt" 2>&1
  local rc=$?
  if [ "$rc" != "$want" ]; then fail "$name: exit $rc, expected $want: $(cat "$dir/out.txt")"; return; fi
  if ! grep -qF -- "$pattern" "$dir/out.txt"; then fail "$name: output lacks '$pattern': $(cat "$dir/out.txt")"; return; fi
  echo "ok   $name (exit $rc)"
}
inode() { stat -c %i "$1"; }

cd "$dir" || exit 1
mkdir -p suite/data suite/golden
"$ropecast" convert procedural:sphere:32 --brick 8 -o suite/data/s.rcast --quiet || fail "convert for the setup"
cat > suite/suite.json <<'JSON'
{
  "tolerances": {"min_psnr_db": 40},
  "cases": [
    {"name": "a", "input": "procedural:sphere:32", "options": ["--size", "48x48", "--brick", "8"],
     "golden": "golden/a.png", "tolerances": {"max_pixel_error": 0, "max_failing_share": 0}},
    {"name": "b", "input": "procedural:noise:24", "options": ["--size", "48x48", "--mode", "dvr", "--tf", "linear", "--max-frames", "200"],
     "golden": "golden/b.png"},
    {"name": "store", "input": "data/s.rcast", "options": ["--size", "40x32", "--orbit", "60,10,2.5"],
     "golden": "golden/store.png"}
  ]
}
JSON

expect 1 "missing goldens fail" "run \`ropecast regress suite/suite.json --update\` to create it" suite/suite.json
expect 0 "--update creates them" "3 goldens updated" suite/suite.json --update
for f in a b store; do [ -s "suite/golden/$f.png" ] || fail "--update wrote no golden/$f.png"; done
# Case a allows no difference at all: the same options give the same pixels run after run.
expect 0 "a second run passes exactly" "3 cases, 0 failed" suite/suite.json
expect 0 "--jobs 2 renders the same images" "3 cases, 0 failed" suite/suite.json --jobs 2

# A golden that no longer matches: the case fails with its figures, the others pass.
cp suite/golden/b.png b_saved.png
oiiotool suite/golden/b.png --addc 0.2,0,0 -o suite/golden/b.png 2> /dev/null || fail "oiiotool for the setup"
expect 1 "a changed image fails" "FAIL b" suite/suite.json --report report
grep -q "^ok   a" "$dir/out.txt" || fail "case a should still pass: $(cat "$dir/out.txt")"
grep -q "max error 0.2" "$dir/out.txt" || fail "the figures of b: $(cat "$dir/out.txt")"
for f in index.html b.render.png b.golden.png b.difference.png a.render.png; do
  [ -s "report/$f" ] || fail "--report wrote no $f"
done
first=$(grep -o '<h2>[^<]*' report/index.html | head -1)
[ "$first" = "<h2>FAIL b" ] || fail "the report should list the failing case first, got '$first'"
grep -q 'class=scale' report/index.html || fail "the difference image has no scale"
# Each case's command is the one that renders what was compared: the converged frame.
commands=$(grep -F '<code>ropecast render' report/index.html)
[ "$(grep -c . <<<"$commands")" = 3 ] && [ "$(grep -c -- '--converge' <<<"$commands")" = 3 ] ||
  fail "the report's commands should be 3, each with --converge: $commands"
if grep -qE '(src|href)="(/|https?:)' report/index.html; then fail "the report refers outside its folder"; fi

# --update rewrites the failing golden only; --update-all all of them.
a_inode=$(inode suite/golden/a.png)
expect 0 "--update rewrites the failing golden" "1 goldens updated" suite/suite.json --update
[ "$(inode suite/golden/a.png)" = "$a_inode" ] || fail "--update rewrote the passing golden a.png"
cmp -s suite/golden/b.png b_saved.png || fail "--update did not restore b.png from the render"
expect 0 "--update-all rewrites all" "3 goldens updated" suite/suite.json --update-all
[ "$(inode suite/golden/a.png)" != "$a_inode" ] || fail "--update-all left a.png"
[ -z "$(find suite report -name '*.tmp*')" ] || fail "temporaries left: $(find suite report -name '*.tmp*')"

# A one-channel golden is not compared on its one channel (a render differing in green and blue would pass).
oiiotool suite/golden/a.png --ch R -o suite/golden/a.png 2> /dev/null || fail "oiiotool for the setup"
expect 1 "a one-channel golden fails" "expected an RGB or RGBA image" suite/suite.json
expect 0 "--update replaces it" "1 goldens updated" suite/suite.json --update
expect 0 "then it passes" "3 cases, 0 failed" suite/suite.json

# A render that fails is a failing case, not a bad suite: here a pool too small for one of the input's bricks,
# which only the render finds.
cat > bad_render.json <<'JSON'
{"cases": [{"name": "r", "input": "procedural:sphere:32", "options": ["--gpu-budget", "1K"], "golden": "r.png"}]}
JSON
expect 1 "a failing render fails its case" "render failed" bad_render.json

# Bad suites: exit 2 with what was expected.
bad() {  # bad NAME PATTERN JSON
  printf '%s' "$3" > bad.json
  expect 2 "bad suite: $1" "$2" bad.json
}
bad "not JSON" "not valid JSON" '{"cases": ['
bad "no cases" 'expected "cases"' '{"tolerances": {}}'
bad "unknown key" "unknown key 'golde'" '{"cases": [{"name": "x", "input": "procedural:sphere:16", "golde": "x.png"}]}'
bad "malformed procedural input" "unknown name 'nothing'" '{"cases": [{"name": "x", "input": "procedural:nothing:32", "golden": "x.png"}]}'
bad "missing golden" 'missing "golden"' '{"cases": [{"name": "x", "input": "procedural:sphere:16"}]}'
bad "bad option" "--mode" '{"cases": [{"name": "x", "input": "procedural:sphere:16", "options": ["--mode", "foo"], "golden": "x.png"}]}'
bad "option writing a file" "--stats writes a file" \
  '{"cases": [{"name": "x", "input": "procedural:sphere:16", "options": ["--stats", "s.jsonl"], "golden": "x.png"}]}'
bad "--help in options" "--help asks for help" '{"cases": [{"name": "x", "input": "procedural:sphere:16", "options": ["--help"], "golden": "x.png"}]}'
bad "-o in options" "-o writes a file" '{"cases": [{"name": "x", "input": "procedural:sphere:16", "options": ["-o", "y.png"], "golden": "x.png"}]}'
bad "a step that follows frame times" "--target-frame-ms adapts the step" \
  '{"cases": [{"name": "x", "input": "procedural:sphere:16", "options": ["--target-frame-ms", "50"], "golden": "x.png"}]}'
bad "two cases one name" "names two cases" \
  '{"cases": [{"name": "x", "input": "procedural:sphere:16", "golden": "x.png"}, {"name": "x", "input": "procedural:sphere:16", "golden": "y.png"}]}'
bad "a camera that cannot be" "case 'x': options: --eye and --target go together" \
  '{"cases": [{"name": "x", "input": "procedural:sphere:16", "options": ["--eye", "0,0,90"], "golden": "x.png"}]}'
bad "missing store" "no such store file" '{"cases": [{"name": "x", "input": "nowhere.rcast", "golden": "x.png"}]}'
bad "unknown tolerance" "unknown tolerance 'min_psnr'" '{"tolerances": {"min_psnr": 3}, "cases": [{"name": "x", "input": "procedural:sphere:16", "golden": "x.png"}]}'
bad "tolerance out of range" "expected a number in [0, 1]" \
  '{"cases": [{"name": "x", "input": "procedural:sphere:16", "golden": "x.png", "tolerances": {"max_failing_share": 2}}]}'

# Outputs never replace inputs: a golden written by --update that is the store (by a hard link) or the suite
# (by a symlink), a report file that is the suite, and two updated cases with one golden.
ln suite/data/s.rcast suite/golden/hard.png
ln -s ../guard2.json suite/golden/link.png
one_case() { printf '{"cases": [{"name": "%s", "input": "data/s.rcast", "options": ["--size", "16x16"], "golden": "%s"}]}' "$1" "$2"; }
one_case x golden/hard.png > suite/guard1.json
expect 2 "--update onto the store" "the same file as the input of case 'x'" suite/guard1.json --update
one_case x golden/link.png > suite/guard2.json
expect 2 "--update-all onto the suite" "the golden of case 'x' suite/golden/link.png: the same file as the suite suite/guard2.json" \
  suite/guard2.json --update-all
cmp -s suite/data/s.rcast suite/golden/hard.png || fail "the store changed"
mkdir -p rep2
ln suite/suite.json rep2/index.html
expect 2 "--report onto the suite" "--report rep2/index.html: the same file as the suite" suite/suite.json --report rep2
printf '{"cases": [{"name": "x", "input": "procedural:sphere:16", "golden": "g.png"}, {"name": "y", "input": "procedural:sphere:16", "golden": "g.png"}]}' > twice.json
expect 2 "two updated cases, one golden" "are the same file" twice.json --update
[ ! -e g.png ] || fail "g.png was written"
expect 1 "one golden shared by cases that are only checked" "no golden image" twice.json
# A golden of another size fails its case, and the report still shows it beside the render.
cp suite/golden/a.png suite/golden/sized.png
one_case sized golden/sized.png > suite/sized.json
expect 1 "a golden of another size" "is 48x48, the render 16x16" suite/sized.json --report rep3
[ -s rep3/sized.golden.png ] || fail "the report lacks the golden of another size: $(ls rep3)"
expect 2 "a report folder that cannot be made" "--report /sys/rep: cannot create the folder" suite/suite.json \
  --report /sys/rep

# --reference cases render their one image in a child (--jobs) as in this process; with --converge too they
# are refused as render refuses them.
printf '{"cases": [{"name": "r", "input": "procedural:sphere:16", "options": ["--size", "24x24", "--reference"], "golden": "r.png"}, {"name": "q", "input": "procedural:sphere:16", "options": ["--size", "24x24"], "golden": "q.png"}]}' > ref.json
expect 0 "--reference cases (--jobs 1)" "2 goldens updated" ref.json --jobs 1 --update
expect 0 "--reference cases (--jobs 2)" "2 cases, 0 failed" ref.json --jobs 2 --report rep4
grep -q "reference --converge" rep4/index.html && fail "the report's command for a --reference case carries --converge"
printf '{"cases": [{"name": "r", "input": "procedural:sphere:16", "options": ["--reference", "--converge"], "golden": "r.png"}]}' > refconv.json
expect 2 "--reference with --converge" "--converge has nothing to do with --reference" refconv.json
# A golden that is a FIFO fails its case at once (opening it would wait for a writer), with or without a report.
mkfifo fifo.png
printf '{"cases": [{"name": "f", "input": "procedural:sphere:16", "options": ["--size", "24x24"], "golden": "fifo.png"}]}' > fifo.json
for report in "" "--report rep5"; do
  # shellcheck disable=SC2086  # the report option is two words or none
  timeout 60 "$ropecast" regress fifo.json $report > "$dir/out.txt" 2>&1
  rc=$?
  if [ "$rc" = 1 ] && grep -q "not a regular file" "$dir/out.txt"; then echo "ok   a golden that is a FIFO ($report)"
  else fail "a golden that is a FIFO ($report): exit $rc: $(cat "$dir/out.txt")"; fi
done
# A golden with a straight alpha is compared on its stored color, as compare reads it.
oiiotool --no-autopremult q.png --ch R,G,B,A=0.5 --attrib oiio:UnassociatedAlpha 1 -o qa.png 2>/dev/null || fail "oiiotool for the setup"
printf '{"cases": [{"name": "q", "input": "procedural:sphere:16", "options": ["--size", "24x24"], "golden": "qa.png", "tolerances": {"max_pixel_error": 0}}]}' > alpha.json
expect 0 "an RGBA golden with the render's color" "1 cases, 0 failed" alpha.json

# A render's warning reaches the user with its case, rendered in this process or in a child (--jobs).
printf '{"cases": [{"name": "capped", "input": "procedural:sphere:48", "options": ["--size", "32x32", "--max-frames", "1"], "golden": "capped.png"}]}' > capped.json
expect 0 "a case's warning (--jobs 2)" "case 'capped': ropecast render: not converged after 1 frames" capped.json --jobs 2 --update
expect 0 "a case's warning (--jobs 1)" "case 'capped': ropecast render: not converged after 1 frames" capped.json --jobs 1 --update-all

# Ctrl-C: the temporary folder of the renders goes with the run (the process group gets the signal, as from a
# terminal). Slow cases (every read 1 s: a render to PNG starts in a quarter second) are still rendering when
# the signal comes.
mkdir -p tmp
printf '{"cases": [{"name": "s1", "input": "procedural:sphere:48", "options": ["--size", "32x32", "--io-delay-ms", "1000"], "golden": "s1.png"}, {"name": "s2", "input": "procedural:sphere:48", "options": ["--size", "32x32", "--io-delay-ms", "1000"], "golden": "s2.png"}]}' > slow.json
for jobs in 1 2; do
  TMPDIR="$dir/tmp" setsid bash -c 'exec "$0" regress slow.json --jobs "$1" > /dev/null 2>&1' "$ropecast" "$jobs" &
  leader=$!
  sleep 1.5
  kill -INT -- "-$leader" 2> /dev/null
  wait "$leader"
  rc=$?
  if [ "$rc" = 130 ] && [ -z "$(ls -A tmp)" ]; then echo "ok   Ctrl-C with --jobs $jobs: exit 130, no folder left"
  else fail "Ctrl-C with --jobs $jobs: exit $rc, left: $(ls -A tmp)"; fi
  rm -rf tmp/*
done
# The signal sent to regress alone (`kill PID`, `timeout`): it passes it on to the renders it started.
TMPDIR="$dir/tmp" setsid bash -c 'exec "$0" regress slow.json --jobs 2 > /dev/null 2>&1' "$ropecast" &
leader=$!
sleep 1.5
kill -INT "$leader" 2> /dev/null
wait "$leader"
rc=$?
left=$(pgrep -s "$leader" || true)
if [ "$rc" = 130 ] && [ -z "$left" ] && [ -z "$(ls -A tmp)" ]; then echo "ok   SIGINT to regress alone: exit 130, no render running, no folder left"
else fail "SIGINT to regress alone: exit $rc, still running: ${left:-none}, left: $(ls -A tmp)"; fi
rm -rf tmp/*
# With --report the renders' logs are not left in the report folder either.
TMPDIR="$dir/tmp" setsid bash -c 'exec "$0" regress slow.json --jobs 2 --report "$1" > /dev/null 2>&1' "$ropecast" \
  "$dir/rep_int" &
leader=$!
sleep 1.5
kill -INT -- "-$leader" 2> /dev/null
wait "$leader"
rc=$?
logs=$(find "$dir/rep_int" -name '*.log' 2> /dev/null)
if [ "$rc" = 130 ] && [ -z "$logs" ] && [ -z "$(ls -A tmp)" ]; then echo "ok   Ctrl-C with --report: exit 130, no log left"
else fail "Ctrl-C with --report: exit $rc, logs: ${logs:-none}, left: $(ls -A tmp)"; fi
rm -rf tmp/*

[ "$failures" -eq 0 ] && echo "all ok" || echo "$failures failure(s)"
[ "$failures" -eq 0 ]
