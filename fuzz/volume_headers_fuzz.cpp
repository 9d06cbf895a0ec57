// libFuzzer target for the MetaImage, NIfTI, legacy VTK and VTK image data header parsers
// (store/metaimage_header.h, store/nifti_header.h, store/vtk_header.h, store/vti_header.h) and
// BigDataViewer's XML (store/bdv_xml.h), and the ImageJ and OME-TIFF descriptions of a multi-page TIFF
// (store/tiff_stack_layout.h): the first byte modulo 6 chooses the parser, the rest is its input.
// Any input must either parse into a header whose fields keep the parser's promises or throw ropecast::Error;
// never crash, hang or throw anything else.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string_view>
#include <type_traits>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "store/bdv_xml.h"
#include "store/metaimage_header.h"
#include "store/nifti_header.h"
#include "store/tiff_stack_layout.h"
#include "store/vti_header.h"
#include "store/vtk_header.h"

namespace {

// Sizes positive, their bytes (of every channel) without overflow, spacings positive and finite: what the
// sources rely on.
template <typename Header>
void checkVolume(const Header& header) {
  if (header.sizes.x == 0 || header.sizes.y == 0 || header.sizes.z == 0) std::abort();
  uint64_t channels = 1;  // a MetaImage's samples per point
  if constexpr (requires { header.channels; }) channels = header.channels;
  if constexpr (std::is_same_v<Header, ropecast::VtiHeader>) channels = header.components;
  if (channels == 0 || header.dataBytes() / header.sizes.x / header.sizes.y / header.sizes.z !=
                           ropecast::bytesPerSample(header.type) * channels)
    std::abort();  // dataBytes() overflowed
  for (int axis = 0; axis < 3; ++axis)
    if (!(header.spacing[axis] > 0.0 && std::isfinite(header.spacing[axis]))) std::abort();
}

// Axes: unit directions at right angles (core/orientation.h), which a store then keeps.
void checkAxes(const ropecast::AxisDirections& axes) {
  for (int a = 0; a < 3; ++a) {
    if (!(std::abs(glm::length(axes[a]) - 1.0) <= 1e-9)) std::abort();
    if (!(std::abs(glm::dot(axes[a], axes[(a + 1) % 3])) <= 1e-3)) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int parser = data[0] % 6;
  const bool analyzeAllowed = data[0] >= 128;  // a NIfTI header read as a .hdr's, ANALYZE 7.5 allowed
  ++data;
  --size;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    if (parser == 5) {
      // A layout must name pages that exist, and a spacing that is positive and finite.
      constexpr uint64_t kPages = 1000;
      for (const auto& layout :
           {ropecast::imageJLayout(text, 0.5, 0.25, kPages), ropecast::omeLayout(text, kPages)}) {
        if (!layout) continue;
        if (layout->slices * layout->channels * layout->frames != kPages) std::abort();
        const uint64_t last = layout->page(layout->slices - 1, layout->channels - 1, layout->frames - 1);
        if (last >= kPages) std::abort();
        // Channel names: none, or one (not empty) for every channel.
        if (!layout->channelNames.empty() && layout->channelNames.size() != layout->channels) std::abort();
        for (const std::string& name : layout->channelNames)
          if (name.empty()) std::abort();
        if (layout->spacing)
          for (int a = 0; a < 3; ++a)
            if (!((*layout->spacing)[a] > 0.0 && std::isfinite((*layout->spacing)[a]))) std::abort();
      }
    } else if (parser == 4) {
      const ropecast::BdvDataset dataset = ropecast::parseBdvXml(text, "fuzz.xml");
      if (dataset.setups.empty() || dataset.timepoints.empty() || dataset.images.empty()) std::abort();
      for (const ropecast::BdvSetup& setup : dataset.setups)
        if (setup.voxelSize && !(std::isfinite(setup.voxelSize->x) && std::isfinite(setup.voxelSize->y) &&
                                 std::isfinite(setup.voxelSize->z)))
          std::abort();
    } else if (parser == 3) {
      const ropecast::VtiHeader header = ropecast::parseVtiHeader(text, "fuzz.vti");
      checkVolume(header);
      checkAxes(header.axes);
      if (header.headerWordBytes != 4 && header.headerWordBytes != 8) std::abort();
    } else if (parser == 2) {
      const ropecast::VtkHeader header = ropecast::parseVtkHeader(text, "fuzz.vtk");
      checkVolume(header);
      if (header.headerBytes > size) std::abort();
    } else if (parser == 1) {
      const ropecast::NiftiHeader header =
          ropecast::parseNiftiHeader(std::as_bytes(std::span(data, size)), "fuzz.hdr", analyzeAllowed);
      checkVolume(header);
      checkAxes(header.axes);
      const size_t headerBytes =
          header.version == 2 ? ropecast::kNifti2HeaderBytes : ropecast::kNifti1HeaderBytes;
      if (!header.pairedFile && header.voxOffset < headerBytes) std::abort();
      if (header.analyze && (!analyzeAllowed || !header.pairedFile || header.origin ||
                             header.axes != ropecast::AxisDirections(1.0)))
        std::abort();
      // Every volume of the series ends within 2^62 bytes (a source seeks to the last one).
      const uint64_t volumes = header.timePoints * header.components;
      if (header.timePoints == 0 || header.components == 0 ||
          volumes / header.components != header.timePoints ||
          header.dataBytes() > (uint64_t(1) << 62) / volumes)
        std::abort();
      if (header.scaled &&
          !(std::isfinite(header.slope) && header.slope != 0.0 && std::isfinite(header.intercept)))
        std::abort();
    } else {
      const ropecast::MetaImageHeader header = ropecast::parseMetaImageHeader(text, "fuzz.mha");
      checkVolume(header);
      checkAxes(header.axes);
      if (header.headerBytes > size || header.headerSize < -1) std::abort();
      // A file per slice: as many as slices, uncompressed.
      if (!header.sliceFiles.empty() && (header.sliceFiles.size() != header.sizes.z || header.compressed))
        std::abort();
    }
  } catch (const ropecast::Error&) {
    // Malformed input is expected to be rejected this way.
  }
  return 0;
}
