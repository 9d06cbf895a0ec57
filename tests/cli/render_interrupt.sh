#!/usr/bin/env bash
# An interrupted render (SIGINT, SIGTERM) dies of the signal and leaves no temporary: neither the --stats file
# being written nor an image half-written.
# Usage: bash render_interrupt.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless}
for signal in INT TERM; do
  "$ropecast" render procedural:sphere:64 --size 64x64 --frames 1000000 --stats "$dir/s.jsonl" \
    --exr "$dir/o.exr" -o "$dir/o.png" > /dev/null 2>&1 &
  pid=$!
  for _ in $(seq 1 400); do  # wait (up to 20 s) until the stats temporary exists: the render is under way
    [ -n "$(ls "$dir")" ] && break
    sleep 0.05
  done
  if [ -z "$(ls "$dir")" ]; then echo "FAIL: no stats temporary appeared"; kill -KILL "$pid"; exit 1; fi
  sleep 0.5  # into the frame loop
  kill -"$signal" "$pid"
  for _ in $(seq 1 400); do  # a render that ignores the signal must fail here, not run its million frames
    kill -0 "$pid" 2> /dev/null || break
    sleep 0.05
  done
  if kill -0 "$pid" 2> /dev/null; then
    echo "FAIL: SIG$signal: still running 20 s later"; kill -KILL "$pid"; wait "$pid"; exit 1
  fi
  wait "$pid"
  rc=$?
  if [ "$rc" -lt 129 ]; then echo "FAIL: SIG$signal: render exited with $rc, expected death by the signal"; exit 1; fi
  if [ -n "$(ls "$dir")" ]; then echo "FAIL: SIG$signal left: $(ls "$dir")"; exit 1; fi
  echo "ok   SIG$signal: exit $rc, nothing left"
done
echo "render_interrupt: ok"
