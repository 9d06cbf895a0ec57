#!/usr/bin/env bash
# An interrupted convert (SIGINT, SIGTERM) dies of the signal and leaves neither the output nor its temporary.
# Usage: bash store_interrupt.sh /path/to/ropecast
set -uo pipefail
ropecast="$1"
# shellcheck source=tests/cli/lib/interrupt.sh
source "$(dirname "$0")/lib/interrupt.sh"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for signal in INT TERM; do
  expect_interrupted_leaves_nothing "$signal" "$dir" \
    "$ropecast" convert procedural:noise:512 -o "$dir/n.store" --quiet || exit 1
done
echo "store_interrupt: ok"
