// The procedural VolumeSource (`procedural:NAME:SIZE`): a SIZE^3 uint8 volume of one of the fields in
// store/procedural.h, generated slab by slab on demand and never held whole. Owned by loader/.
//
// Threads: as VolumeSource (readSlab from one thread at a time); readSlab splits large slabs over worker
// threads.
#pragma once

#include <memory>
#include <string_view>

#include "store/procedural.h"
#include "store/volume_source.h"

namespace ropecast {

// `nameAndSize` is the spec after "procedural:". Spacing from options (default 1,1,1); dims and type come
// from the spec. Throws ropecast::Error listing the valid names for an unknown NAME or a bad SIZE.
std::unique_ptr<VolumeSource> openProceduralSource(std::string_view nameAndSize,
                                                   const SourceOptions& options);

// Fills slices [z0, z0 + count) of `field` into `out` (count * size^2 bytes, x fastest) using up to
// `threadCount` threads (0 = all hardware threads).
void generateProceduralSlab(const ProceduralField& field, uint32_t z0, uint32_t count,
                            std::span<std::byte> out, unsigned threadCount = 0);

}  // namespace ropecast
