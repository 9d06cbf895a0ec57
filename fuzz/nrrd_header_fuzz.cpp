// libFuzzer target for the NRRD header parser (store/nrrd_header.h): any input must either parse into a
// header whose fields keep the parser's promises or throw ropecast::Error; never crash, hang or throw
// anything else.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "store/nrrd_header.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const ropecast::NrrdHeader header = ropecast::parseNrrdHeader(text, "fuzz.nrrd");
    // Promises a caller relies on.
    if (header.headerBytes > size) std::abort();
    if (header.sizes.x == 0 || header.sizes.y == 0 || header.sizes.z == 0) std::abort();
    if (header.dataBytes() / header.sizes.x / header.sizes.y / header.sizes.z !=
        ropecast::bytesPerSample(header.type))
      std::abort();  // dataBytes() overflowed
    // Every volume of a 4-dimensional file ends within 2^62 bytes.
    if (header.volumes == 0 || header.dataBytes() > (uint64_t(1) << 62) / header.volumes) std::abort();
    if (!(header.spacing.x > 0.0 && header.spacing.y > 0.0 && header.spacing.z > 0.0)) std::abort();
    if (header.byteSkip < -1 || header.lineSkip < 0) std::abort();
    for (int a = 0; a < 3; ++a) {  // axes: unit directions at right angles, which a store then keeps
      if (!(std::abs(glm::length(header.axes[a]) - 1.0) <= 1e-9)) std::abort();
      if (!(std::abs(glm::dot(header.axes[a], header.axes[(a + 1) % 3])) <= 1e-3)) std::abort();
    }
  } catch (const ropecast::Error&) {
    // Malformed input is expected to be rejected this way.
  }
  return 0;
}
