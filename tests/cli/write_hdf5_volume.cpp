// Writes a small HDF5 file for tests/cli/hdf5.sh: /scan/ct, int16 big-endian, z, y, x = 10, 12, 16, chunked
// 4 x 6 x 8 with shuffle and deflate, values x + 16 y - 7 z - 500, element_size_um 2.5, 0.75, 0.5 (z, y, x);
// and /scan/mask, uint8 of the same size, so that the file holds two volumes.
// Usage: write_hdf5_volume FILE
#include <cstdint>
#include <exception>
#include <iostream>
#include <vector>

#include "tests/store/testutil_hdf5.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: write_hdf5_volume FILE\n";
    return 2;
  }
  try {
    std::vector<int16_t> ct;
    std::vector<uint8_t> mask;
    for (int z = 0; z < 10; ++z)
      for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 16; ++x) {
          ct.push_back(int16_t(x + 16 * y - 7 * z - 500));
          mask.push_back(uint8_t(x > y ? 1 : 0));
        }
    ropecast::testing::Hdf5Writer writer(argv[1]);
    const hid_t dataset =
        writer.write({"/scan/ct", {10, 12, 16}, H5T_STD_I16BE, H5T_NATIVE_INT16, ct.data(), {4, 6, 8}, true});
    ropecast::testing::writeNumbersAttribute(dataset, "element_size_um", {2.5, 0.75, 0.5});
    writer.write({"/scan/mask", {10, 12, 16}, H5T_STD_U8LE, H5T_NATIVE_UINT8, mask.data(), {}, false});
  } catch (const std::exception& e) {
    std::cerr << "write_hdf5_volume: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
