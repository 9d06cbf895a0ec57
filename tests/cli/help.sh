#!/usr/bin/env bash
# `ropecast --help` and README.md agree: README lists every command with the description --help gives it,
# and every option README shows for a command is in that command's --help.
# Usage: bash help.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
readme="$(cd "$(dirname "$0")/../.." && pwd)/README.md"
failures=0
dir_err=$(mktemp)
trap 'rm -f "$dir_err"' EXIT
fail() { echo "FAIL $*"; failures=$((failures + 1)); }

help=$("$ropecast" --help) || fail "ropecast --help exited non-zero"
# The subcommands of --help: the lines after "Subcommands:", "  NAME  description".
commands=$(awk '/^Subcommands:/ {on = 1; next} on && NF {print $1}' <<< "$help")
[ -n "$commands" ] || fail "ropecast --help lists no subcommands: $help"
for cmd in $commands; do
  description=$(awk -v c="$cmd" '/^Subcommands:/ {on = 1; next} on && $1 == c {$1 = ""; sub(/^ +/, ""); print}' <<< "$help")
  row=$(grep -E "^\| \`$cmd\` +\|" "$readme" | head -n 1)
  if [ -z "$row" ]; then fail "README.md has no table row for \`$cmd\`"; continue; fi
  grep -qF -- "| $description" <<< "$row" || fail "README.md row of $cmd ($row) is not its --help description '$description'"
  grep -qE "^ropecast $cmd( |\$)" "$readme" || fail "README.md shows no 'ropecast $cmd' usage line"
  # The options on the command's usage lines (the line and its indented continuations).
  options=$(awk -v c="$cmd" '$1 == "ropecast" {on = ($2 == c)} $1 != "ropecast" && !/^    / {on = 0} on' "$readme" |
    grep -oE -- '--[a-z][a-z0-9-]*' | sort -u)
  cmd_help=$("$ropecast" "$cmd" --help) || fail "ropecast $cmd --help exited non-zero"
  [ "$cmd" = bench ] && cmd_help=$("$ropecast" bench index --help; "$ropecast" bench modes --help)
  for option in $options; do
    grep -qE -- "(^|[ ,])$option([ ,=]|\$)" <<< "$cmd_help" || fail "README.md shows $option for $cmd, its --help does not"
  done
  echo "ok   $cmd: $(wc -w <<< "$options") README options in --help"
done
# And README lists no command that --help lacks.
for cmd in $(grep -oE '^\| `[a-z]+`' "$readme" | tr -d '|` '); do
  grep -qx "$cmd" <<< "$commands" || fail "README.md lists $cmd, ropecast --help does not"
done

# Usage errors exit 2 (README.md "Exit status"); a mistyped command is named, with the commands there are.
"$ropecast" rendr x.rcast -o x.png > /dev/null 2> "$dir_err"
rc=$?
if [ "$rc" = 2 ] && grep -qF "unknown command 'rendr'; the commands are convert," "$dir_err"; then
  echo "ok   a mistyped command is named (exit 2)"
else
  fail "ropecast rendr: exit $rc: $(cat "$dir_err")"
fi
"$ropecast" bench indx > /dev/null 2> "$dir_err"
rc=$?
if [ "$rc" = 2 ] && grep -qF "unknown subcommand 'indx'; they are index, modes" "$dir_err"; then
  echo "ok   a mistyped benchmark is named (exit 2)"
else
  fail "ropecast bench indx: exit $rc: $(cat "$dir_err")"
fi
"$ropecast" render procedural:sphere:16 --size 0x1 -o x.png > /dev/null 2> "$dir_err"
rc=$?
if [ "$rc" = 2 ] && grep -qF -- "--size" "$dir_err"; then echo "ok   a bad option value exits 2"
else fail "render --size 0x1: exit $rc: $(cat "$dir_err")"; fi
# A parse error reads like every other error, says what was expected, and names the --help to read.
"$ropecast" render procedural:sphere:16 -o x.png --voxel-per-pixel 2 > /dev/null 2> "$dir_err"
rc=$?
if [ "$rc" = 2 ] && grep -qxF "ropecast: error: unknown option --voxel-per-pixel (did you mean --voxels-per-pixel?)" "$dir_err" &&
  grep -qxF "(ropecast render --help lists the options)" "$dir_err"; then
  echo "ok   a mistyped option is named with the one meant (exit 2)"
else
  fail "render --voxel-per-pixel: exit $rc: $(cat "$dir_err")"
fi
"$ropecast" render procedural:sphere:16 -o x.png --orbit 30,20 > /dev/null 2> "$dir_err"
rc=$?
if [ "$rc" = 2 ] && grep -qxF "ropecast: error: --orbit: expected 3 values separated by ',', got 2" "$dir_err"; then
  echo "ok   a short list says how many values it takes (exit 2)"
else
  fail "render --orbit 30,20: exit $rc: $(cat "$dir_err")"
fi
"$ropecast" --version > /dev/null || fail "ropecast --version exited non-zero"

[ "$failures" -eq 0 ] && echo "all ok" || echo "$failures failure(s)"
[ "$failures" -eq 0 ]
