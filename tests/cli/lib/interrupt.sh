# shellcheck shell=bash
# Sourced by tests/cli/*_interrupt.sh (this folder is not globbed as tests).
#
# expect_interrupted_leaves_nothing SIGNAL DIR COMMAND...: starts COMMAND in the background, waits (up to 20 s)
# until something stays in DIR (its temporary: the work is under way) and SETTLE seconds more (default 0),
# sends SIGNAL, and requires the command to die of the signal within 20 s and leave DIR empty. Prints an ok or
# FAIL line; returns 0 or 1.
expect_interrupted_leaves_nothing() {
  local signal="$1" dir="$2"
  shift 2
  "$@" > /dev/null 2>&1 &
  local pid=$!
  # Seen twice, 50 ms apart: render checks each image output's folder with a temporary it removes at once
  # (checkImageOutputs), which one look may catch and the next not find.
  local seen=0
  for _ in $(seq 1 400); do
    if [ -n "$(ls -A "$dir")" ]; then
      seen=$((seen + 1))
      [ "$seen" -ge 2 ] && break
    else
      seen=0
    fi
    sleep 0.05
  done
  if [ -z "$(ls -A "$dir")" ]; then
    echo "FAIL: SIG$signal: nothing appeared in $dir"; kill -KILL "$pid"; wait "$pid"; return 1
  fi
  sleep "${SETTLE:-0}"
  kill -"$signal" "$pid"
  for _ in $(seq 1 400); do  # a command that ignores the signal fails here instead of running on
    kill -0 "$pid" 2> /dev/null || break
    sleep 0.05
  done
  if kill -0 "$pid" 2> /dev/null; then
    echo "FAIL: SIG$signal: still running 20 s later"; kill -KILL "$pid"; wait "$pid"; return 1
  fi
  wait "$pid"
  local rc=$?
  if [ "$rc" -lt 129 ]; then echo "FAIL: SIG$signal: exited with $rc, expected death by the signal"; return 1; fi
  if [ -n "$(ls -A "$dir")" ]; then echo "FAIL: SIG$signal left: $(ls -A "$dir")"; return 1; fi
  echo "ok   SIG$signal: exit $rc, nothing left"
}
