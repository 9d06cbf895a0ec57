#!/usr/bin/env bash
# Renders every case of tests/regression/cases.txt and compares it with its golden image (idiff from
# OpenImageIO), or with `update` rewrites the golden images.
# Usage: tests/regression/run.sh check|update /path/to/ropecast
# A check fails when more than 0.5% of the pixels differ by more than 2/255 or any pixel by more than 0.25;
# the differing renders and difference images are kept under $ROPECAST_REGRESSION_OUT (default: a temp dir).
set -uo pipefail
mode="$1"
ropecast="$2"
here="$(cd "$(dirname "$0")" && pwd)"
out="${ROPECAST_REGRESSION_OUT:-$(mktemp -d)}"
mkdir -p "$out"
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
case "$mode" in check|update) ;; *) echo "usage: $0 check|update ROPECAST" >&2; exit 2 ;; esac

failures=0
cases=0
while IFS= read -r line; do
  case "$line" in ''|'#'*) continue ;; esac
  name="${line%%:*}"
  read -r -a args <<< "${line#*:}"
  cases=$((cases + 1))
  if ! "$ropecast" render "${args[@]}" -o "$out/$name.png" 2> "$out/$name.log"; then
    echo "FAIL $name: render failed: $(cat "$out/$name.log")"; failures=$((failures + 1)); continue
  fi
  golden="$here/golden/$name.png"
  if [ "$mode" = update ]; then
    cp "$out/$name.png" "$golden" && echo "updated $golden"
    continue
  fi
  if [ ! -f "$golden" ]; then
    echo "FAIL $name: no golden image $golden (run scripts/update-goldens)"; failures=$((failures + 1)); continue
  fi
  if idiff -fail 0.008 -failpercent 0.5 -hardfail 0.25 -warn 0.004 -warnpercent 100 -abs -scale 4 \
      -od -o "$out/$name.diff.png" "$golden" "$out/$name.png" > "$out/$name.idiff" 2>&1; then
    echo "ok   $name"
  else
    echo "FAIL $name: differs from $golden; render $out/$name.png, difference $out/$name.diff.png"
    sed 's/^/     /' "$out/$name.idiff"
    failures=$((failures + 1))
  fi
done < "$here/cases.txt"

[ "$cases" -gt 0 ] || { echo "FAIL: no cases in $here/cases.txt"; exit 1; }
if [ "$mode" = check ] && [ "$failures" -eq 0 ] && [ -z "${ROPECAST_REGRESSION_OUT:-}" ]; then rm -rf "$out"; fi
echo "$cases cases, $failures failed"
[ "$failures" -eq 0 ]
