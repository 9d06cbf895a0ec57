// How a multi-page TIFF of a microscope lays out its pages and how large its voxels are, as the two writers
// microscopy users meet describe it in the first page's ImageDescription: ImageJ (Fiji's "Save As > Tiff":
// its hyperstacks interleave channels, slices and frames, channels fastest; `spacing=` and `unit=` calibrate
// z, the XResolution and YResolution tags x and y) and OME-TIFF (the OME-XML Pixels element: DimensionOrder,
// sizes and physical sizes). The volume read is one channel's slices at one time point. Pure functions; any
// thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace ropecast {

struct TiffStackLayout {
  std::string writer;                 // "ImageJ" or "OME-TIFF"
  std::optional<glm::dvec3> spacing;  // x, y, z where the description gives them
  std::string unit;                   // of the spacing ("micron", "µm", ...), where named
  uint64_t channels = 1, slices = 1, frames = 1;
  std::vector<std::string> channelNames;  // where the description names every channel (OME's Channel Name)
  // Pages between one slice, channel and frame and the next.
  uint64_t sliceStride = 1, channelStride = 1, frameStride = 1;

  // The page of z slice k of `channel` at time point `frame` (each below its count).
  uint64_t page(uint64_t k, uint64_t channel, uint64_t frame) const {
    return k * sliceStride + channel * channelStride + frame * frameStride;
  }
};

// The layout an ImageJ description gives ("ImageJ=1.54f\nimages=200\nchannels=2\nslices=100\n..."), with
// the first page's XResolution and YResolution (pixels per unit; 0 where absent); nullopt for a description
// that is not ImageJ's, or whose counts do not fit `pages`.
std::optional<TiffStackLayout> imageJLayout(std::string_view description, double xResolution,
                                            double yResolution, uint64_t pages);

// The layout of an OME-XML description's first image (its Pixels element); nullopt for a description that is
// not OME-XML, one whose Pixels element lacks sizes or a DimensionOrder, or whose sizes do not fit `pages`
// (an image spread over several files, or pages not in the dimension order).
std::optional<TiffStackLayout> omeLayout(std::string_view description, uint64_t pages);

}  // namespace ropecast
