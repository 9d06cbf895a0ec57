#!/usr/bin/python3
# Writes the .vti files of this folder with VTK's own writer (python3-vtk9, `scripts/bootstrap --bench`), one
# for each of its compressors, so that tests/store/source_vti_test.cpp reads what VTK writes, not only what the
# test's own writer makes of the format. Each holds a 9x7x5 volume "density" whose value at (x, y, z) is
# x + 10 y + 100 z. Run from this folder: /usr/bin/python3 write_fixtures.py
import vtk


def volume(scalar_type):
    image = vtk.vtkImageData()
    image.SetDimensions(9, 7, 5)
    image.AllocateScalars(scalar_type, 1)
    scalars = image.GetPointData().GetScalars()
    scalars.SetName("density")
    for i in range(9 * 7 * 5):
        x, y, z = i % 9, i // 9 % 7, i // 63
        scalars.SetValue(i, x + 10 * y + 100 * z)
    return image


def write(path, image, compressor, base64, block_bytes=None):
    writer = vtk.vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    {"zlib": writer.SetCompressorTypeToZLib, "lz4": writer.SetCompressorTypeToLZ4,
     "lzma": writer.SetCompressorTypeToLZMA}[compressor]()
    if block_bytes:
        writer.SetBlockSize(block_bytes)
    writer.SetDataModeToAppended()
    writer.SetEncodeAppendedData(base64)
    if not writer.Write():
        raise SystemExit("could not write " + path)


write("vtk_zlib_uint16.vti", volume(vtk.VTK_UNSIGNED_SHORT), "zlib", True)
write("vtk_lz4_uint16_blocks.vti", volume(vtk.VTK_UNSIGNED_SHORT), "lz4", False, 128)
write("vtk_lzma_float32.vti", volume(vtk.VTK_FLOAT), "lzma", True)
