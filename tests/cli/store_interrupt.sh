#!/usr/bin/env bash
# An interrupted convert (SIGINT, SIGTERM) dies of the signal and leaves neither the output nor its temporary.
# Usage: bash store_interrupt.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for signal in INT TERM; do
  "$ropecast" convert procedural:noise:512 -o "$dir/n.store" --quiet &
  pid=$!
  for _ in $(seq 1 400); do  # wait (up to 20 s) until the temporary exists, so the signal lands mid-write
    [ -n "$(ls "$dir")" ] && break
    sleep 0.05
  done
  if [ -z "$(ls "$dir")" ]; then echo "FAIL: no temporary appeared"; kill -KILL "$pid"; exit 1; fi
  kill -"$signal" "$pid"
  wait "$pid"
  rc=$?
  if [ "$rc" -lt 129 ]; then echo "FAIL: SIG$signal: convert exited with $rc, expected death by the signal"; exit 1; fi
  if [ -n "$(ls "$dir")" ]; then echo "FAIL: SIG$signal left: $(ls "$dir")"; exit 1; fi
  echo "ok   SIG$signal: exit $rc, nothing left"
done
echo "store_interrupt: ok"
