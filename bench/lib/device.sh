# shellcheck shell=bash
# Shared by the bench/device_*.sh scripts, sourced from the repository root: on a lent NVIDIA device machine
# (the device tool's README, its headless rendering paragraph), the GL loader packages carried in .gl are
# unpacked (nothing can be installed there otherwise), NVIDIA's EGL vendor file is named and EGL_PLATFORM=device
# set; the GPU's name and clocks go to $OUT/gpu.txt. Then device_ropecast_build makes a folder whose
# tools/ropecast runs the carried OpenImageIO-free build (build/vg) with the carried libraries (.devlibs), the
# BUILD_DIR argument the bench scripts take. scripts/device_prepare makes everything carried. Off the device
# (no NVIDIA driver) nothing is unpacked and the same runs against whatever GL the machine has.

# device_gl_setup: unpacks the loaders and selects NVIDIA's EGL when the driver is there.
device_gl_setup() {
  if ls .gl/*.deb >/dev/null 2>&1 && command -v nvidia-smi >/dev/null; then
    for f in .gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
    local vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
    [ -f "$vendor" ] && export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
    export EGL_PLATFORM=device # not surfaceless, which the bench scripts would otherwise ask for
  fi
  if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem --format=csv | tee "$OUT/gpu.txt"
  fi
  DEVICE_LIBS=$PWD/.devlibs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
}

# device_ropecast_build: prints a folder whose tools/ropecast runs build/vg/tools/ropecast with the carried
# libraries.
device_ropecast_build() {
  [ -x build/vg/tools/ropecast ] || {
    echo "$0: build/vg/tools/ropecast not carried (scripts/device_prepare builds it)" >&2
    return 1
  }
  local wrapper
  wrapper=$(mktemp -d /tmp/ropecast_build.XXXXXX)
  mkdir -p "$wrapper/tools"
  cat >"$wrapper/tools/ropecast" <<WRAP
#!/bin/sh
LD_LIBRARY_PATH=$DEVICE_LIBS exec $PWD/build/vg/tools/ropecast "\$@"
WRAP
  chmod +x "$wrapper/tools/ropecast"
  echo "$wrapper"
}
