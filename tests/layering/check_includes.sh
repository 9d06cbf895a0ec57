#!/usr/bin/env bash
# The library layering of docs/ARCHITECTURE.md, checked on every #include of the tree:
#   core <- store <- loader;  core <- index;  core <- shaders;  core, store, index <- reference;
#   core, store <- occlusion;  core, store, loader, index, occlusion, shaders <- render;  everything <- tools.
# A library may include its own headers and those of the libraries below it, never one above it; GL headers
# (epoxy, EGL, GL, GLFW) belong to render/ and the GL tools and tests; tools/ is reached by nothing but
# tools/ and its tests; CPU tests (*_test.cpp) outside tests/render/ include no render/ header.
#
#   tests/layering/check_includes.sh [ROOT]     prints each forbidden include as FILE:LINE: why; exit 1 if any
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$root"

declare -A allowed=(
  [core]="core"
  [store]="core store"
  [loader]="core store loader"
  [index]="core index"
  [shaders]="core shaders"
  [reference]="core store index reference"
  [occlusion]="core store occlusion"
  [render]="core store loader index occlusion shaders render"
  [fuzz]="core store fuzz"
)
gl_headers='^(epoxy|EGL|GL|GLES[0-9]*|GLFW)/'

status=0
report() {
  echo "$1: $2"
  status=1
}

# One grep over every source (a process per file costs seconds); its lines read "FILE:LINE:TEXT".
while IFS=: read -r file line text; do
  top=${file%%/*}
  [[ $text =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*[\"\<]([^\"\>]+)[\"\>] ]] || continue
  target=${BASH_REMATCH[1]}
  lib=${target%%/*}
  if [[ $target =~ $gl_headers ]]; then
    case $file in
      render/* | tools/gl_* | tests/*_gltest.cpp | tests/render/testutil_gl.*) ;;
      *) report "$file:$line" "includes the GL header <$target> outside render/ and the GL tools and tests" ;;
    esac
    continue
  fi
  [[ $target == */* ]] || continue  # a system header, or a file next to the includer
  if [ "$lib" = tools ]; then
    case $file in
      tools/* | tests/tools/*) ;;
      *) report "$file:$line" "includes \"$target\": nothing but tools/ and its tests may reach tools/" ;;
    esac
    continue
  fi
  if [ -n "${allowed[$top]:-}" ] && [ -d "$lib" ] && [[ " ${allowed[$top]} " != *" $lib "* ]]; then
    report "$file:$line" "includes \"$target\": $top/ may include only ${allowed[$top]// /, }"
  fi
  if [[ $file == tests/*_test.cpp && $file != tests/render/* && $lib == render ]]; then
    report "$file:$line" "includes \"$target\": a CPU test (*_test.cpp) outside tests/render/ needs no GL"
  fi
done < <(git ls-files --cached --others --exclude-standard -z -- '*.h' '*.cpp' '*.c' | grep -zv '^build' |
  xargs -0r grep -Hn '#[[:space:]]*include' || true)

if [ "$status" = 0 ]; then echo "check_includes: the layering holds"; fi
exit "$status"
