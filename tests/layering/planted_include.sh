#!/usr/bin/env bash
# The layering check can fail: in a copy of the tree, a header of loader/ that includes render/ (and one of
# index/ that includes GL) must be reported, by file and line, with a non-zero exit.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
git -C "$root" ls-files --cached --others --exclude-standard -z | (cd "$root" && xargs -0 cp --parents -t "$work")
git -C "$work" init -q && git -C "$work" add -A
bash "$work/tests/layering/check_includes.sh" "$work" > /dev/null || { echo "the tree itself fails"; exit 1; }
printf '#include "render/gl_context.h"\n' >> "$work/loader/working_set.h"
printf '#include <epoxy/gl.h>\n' >> "$work/index/cut.h"
git -C "$work" add -A
if out=$(bash "$work/tests/layering/check_includes.sh" "$work"); then
  echo "planted forbidden includes were not reported"; exit 1
fi
echo "$out"
grep -q '^loader/working_set.h:[0-9]*: includes "render/gl_context.h"' <<< "$out"
grep -q '^index/cut.h:[0-9]*: includes the GL header <epoxy/gl.h>' <<< "$out"
echo "planted_include: both reported"
