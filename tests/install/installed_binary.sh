#!/usr/bin/env bash
# An installed ropecast is relocatable: `cmake --install` into a temporary prefix, the prefix moved elsewhere,
# and the moved binary renders from a folder outside both trees, with ROPECAST_SHADER_DIR unset, the same
# image as the build tree's binary. The binary must not name the source tree's shader folder (it would read
# GLSL from there instead of its embedded copies).
#   tests/install/installed_binary.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
source=$(cd "$2" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
unset ROPECAST_SHADER_DIR

cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
mv "$work/prefix" "$work/moved"
installed=$work/moved/bin/ropecast
[ -x "$installed" ] || { echo "installed_binary: no bin/ropecast in the prefix"; cat "$work/install.log"; exit 1; }
if grep -q "$source/shaders" "$installed"; then
  echo "installed_binary: the binary names the source tree's shader folder $source/shaders"
  exit 1
fi

mkdir "$work/run"
cd "$work/run"
args=(procedural:sphere:48 --size 64x48 --orbit 30,20,3)
"$installed" render "${args[@]}" --mode iso -o iso.png
"$installed" render "${args[@]}" --mode dvr --tf linear -o dvr.png
"$installed" render "${args[@]}" --mode iso --backend compute -o iso_compute.png
"$build/tools/ropecast" render "${args[@]}" --mode iso -o iso_build.png
"$build/tools/ropecast" render "${args[@]}" --mode dvr --tf linear -o dvr_build.png
# Identical images (compare prints inf dB for identical files and exits 1 below --min-psnr).
"$installed" compare iso.png iso_build.png --min-psnr 99
"$installed" compare dvr.png dvr_build.png --min-psnr 99
"$installed" compare iso_compute.png iso_build.png --min-psnr 40
echo "installed_binary: the moved install rendered the build's images"
