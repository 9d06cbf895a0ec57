# shellcheck shell=bash
# Sourced by tests/cli/*.sh (this folder is not globbed as tests).
#
# write_nifti_series PATH [channels]: a NIfTI-1 file of two uint16 volumes of 24 x 20 x 16 voxels, each a ball
# whose values fall from 4000 at the center, the second falling twice as fast (a smaller ball at any
# isovalue): two time points, or with "channels" two channels (5th dimension's components). Returns python's
# status.
write_nifti_series() {
  python3 - "$1" "${2:-time}" <<'PY'
import struct, sys
header = bytearray(348)
struct.pack_into("<i", header, 0, 348)
dims = (4, 24, 20, 16, 2, 1, 1, 1) if sys.argv[2] != "channels" else (5, 24, 20, 16, 1, 2, 1, 1)
struct.pack_into("<8h", header, 40, *dims)
struct.pack_into("<hh", header, 70, 512, 16)
struct.pack_into("<8f", header, 76, 1, 1, 1, 1, 1, 1, 1, 1)
struct.pack_into("<f", header, 108, 352)
header[344:348] = b"n+1\0"
volumes = []
for slope in (300, 600):
    volumes += [max(0, int(4000 - slope * ((x - 12) ** 2 + (y - 10) ** 2 + (z - 8) ** 2) ** 0.5))
                for z in range(16) for y in range(20) for x in range(24)]
open(sys.argv[1], "wb").write(bytes(header) + bytes(4) + struct.pack("<%dH" % len(volumes), *volumes))
PY
}
