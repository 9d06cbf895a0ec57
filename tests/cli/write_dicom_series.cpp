// Writes a small CT series for tests/cli/dicom.sh: COUNT single-frame images of 5x4 pixels, 2.5 mm apart,
// stored values 100 + 37 z + 3 i (12 bits) with CT's rescale (intercept -1024), named so that name order is
// the reverse of position order; with TILT, each slice TILT mm further down its columns than the one below (a
// tilted gantry's series).
// Usage: write_dicom_series DIR COUNT [SERIES_UID [PREFIX [TILT]]]
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include "tests/store/testutil_dicom.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: write_dicom_series DIR COUNT [SERIES_UID [PREFIX [TILT]]]\n";
    return 2;
  }
  const std::string dir = argv[1];
  const int count = std::atoi(argv[2]);
  const std::string prefix = argc > 4 ? argv[4] : "IM";
  const double tilt = argc > 5 ? std::atof(argv[5]) : 0.0;
  try {
    for (int z = 0; z < count; ++z) {
      ropecast::testing::DicomSliceSpec spec;
      if (argc > 3) spec.seriesUid = argv[3];
      spec.stored.resize(size_t(spec.columns) * spec.rows);
      for (size_t i = 0; i < spec.stored.size(); ++i) spec.stored[i] = 100 + 37 * z + 3 * int64_t(i);
      spec.position = glm::dvec3(-10.0, 20.0 + tilt * z, 30.0 + 2.5 * z);
      spec.instance = z + 1;
      spec.slope = 1.0;
      spec.intercept = -1024.0;
      ropecast::testing::writeDicomSlice(dir + "/" + prefix + std::to_string(count - z), spec);
    }
  } catch (const std::exception& e) {
    std::cerr << "write_dicom_series: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
