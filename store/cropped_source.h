// A box of voxels of another VolumeSource, read through it (`ropecast convert --crop`): a region of interest
// of a large volume becomes a store of its own. Slabs are read from the wrapped source a few slices at a
// time, so memory stays near the converter's slab whatever the part of each slice that is kept. The value
// range is left for the converter to find in the box, which the whole volume's may exceed. Owns the wrapped
// source; one thread at a time, as every VolumeSource.
#pragma once

#include <memory>

#include <glm/vec3.hpp>

#include "store/volume_source.h"

namespace ropecast {

// The voxels [begin, end) of `source` per axis, x fastest as every source. Throws ropecast::Error, naming the
// source, when the box is empty or leaves the volume.
std::unique_ptr<VolumeSource> cropVolumeSource(std::unique_ptr<VolumeSource> source, glm::u32vec3 begin,
                                               glm::u32vec3 end);

}  // namespace ropecast
