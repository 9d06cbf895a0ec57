#!/usr/bin/python3
# Writes the Zarr v2 arrays of this folder with zarr-python and numcodecs (Debian's python3-zarr and
# python3-numcodecs), one for each numcodecs compressor that ropecast reads through its own decoder rather
# than blosc's, so that tests/store/source_zarr_test.cpp reads what numcodecs writes, not only what the
# test's own writer makes of the formats. Each holds a 5x7x9 (z, y, x) uint16 array in chunks of 3x4x5
# whose value at (x, y, z) is x + 10 y + 100 z. Run from this folder: /usr/bin/python3 write_fixtures.py
import lzma
import shutil

import numcodecs
import numpy
import zarr

z, y, x = numpy.mgrid[0:5, 0:7, 0:9]
values = (x + 10 * y + 100 * z).astype("<u2")
compressors = {
    "lz4": numcodecs.LZ4(),
    "lzma": numcodecs.LZMA(),  # an .xz stream
    "lzma_alone": numcodecs.LZMA(format=lzma.FORMAT_ALONE),  # a legacy .lzma stream
    "bz2": numcodecs.BZ2(),
}
for name, compressor in compressors.items():
    path = "numcodecs_" + name + ".zarr"
    shutil.rmtree(path, ignore_errors=True)
    array = zarr.open(path, mode="w", shape=values.shape, chunks=(3, 4, 5), dtype="<u2", compressor=compressor)
    array[:] = values
