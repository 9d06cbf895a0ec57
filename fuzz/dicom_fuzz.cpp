// libFuzzer target for reading one DICOM file (store/source_dicom.h): its element structure is checked
// (store/dicom_structure.h) before GDCM reads it, so any file must give a volume whose slices all read, or
// throw ropecast::Error; never crash, abort (GDCM asserts where a file is cut short), hang or throw anything
// else. The reader reads the file's folder, so each input is written as the one file of a private folder.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/sample_type.h"
#include "fuzz/fuzz_input_file.h"
#include "store/source_dicom.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = ropecast::fuzz::writeInputFile("image.dcm", data, size);
  try {
    const auto source = ropecast::openDicomSource(path, {});
    const ropecast::VolumeInfo& info = source->info();
    const size_t slice = size_t(info.dims.x) * info.dims.y * ropecast::bytesPerSample(info.type);
    if (slice == 0) std::abort();
    std::vector<std::byte> samples(slice);
    for (uint32_t z = 0; z < info.dims.z; ++z) source->readSlab(z, 1, samples);
  } catch (const ropecast::Error&) {
    // A file cut short, or one that is not an image GDCM decodes, is expected to be refused this way.
  }
  return 0;
}
