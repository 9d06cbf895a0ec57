#!/usr/bin/python3
# Writes the N5 container of this folder with zarr-python's N5 store (Debian's python3-zarr and
# python3-numcodecs), so that tests/store/source_n5_test.cpp reads N5 as another implementation writes it,
# not only what the test's own writer makes of the format. zarr.n5 holds one dataset per compression, each a
# 5x7x9 (z, y, x) uint16 array in blocks of 3x4x5 (edge blocks stored whole, as zarr-python stores them) whose
# value at (x, y, z) is x + 10 y + 100 z. Its lz4 is numcodecs' framing (a size, then an LZ4 block), not
# lz4-java's block stream that N5's Java implementation writes. Run from this folder:
# /usr/bin/python3 write_fixtures.py
import shutil
import warnings

import numcodecs
import numpy
import zarr
from zarr.n5 import N5Store

z, y, x = numpy.mgrid[0:5, 0:7, 0:9]
values = (x + 10 * y + 100 * z).astype("<u2")
compressors = {
    "raw": None,
    "gzip": numcodecs.GZip(level=5),
    "zlib": numcodecs.Zlib(level=5),
    "bzip2": numcodecs.BZ2(),
    "xz": numcodecs.LZMA(),
    "blosc": numcodecs.Blosc(cname="zstd", shuffle=numcodecs.Blosc.SHUFFLE),
    "zstd": numcodecs.Zstd(level=3),
    "lz4": numcodecs.LZ4(),
}
shutil.rmtree("zarr.n5", ignore_errors=True)
store = N5Store("zarr.n5")
warnings.simplefilter("ignore", RuntimeWarning)  # blosc and zstd "not supported by all N5 implementations"
for name, compressor in compressors.items():
    array = zarr.zeros(values.shape, chunks=(3, 4, 5), dtype="<u2", store=store, path=name, compressor=compressor)
    array[:] = values
