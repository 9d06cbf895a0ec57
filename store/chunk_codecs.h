// Decoders that chunked sources share (Zarr, HDF5): a zlib or gzip stream inflated whole, and the byte
// shuffle (HDF5's filter 2, as blosc's) undone. Pure functions; any thread.
#pragma once

#include <cstddef>
#include <span>

namespace ropecast {

// Inflates a zlib (or, with `gzip`, a gzip) stream into exactly out.size() bytes; false otherwise (damaged,
// or of another length).
bool inflateExactly(std::span<const std::byte> in, std::span<std::byte> out, bool gzip);

// Undoes the byte shuffle of `in` (each sample's byte k stored in the k-th plane of in.size() / width bytes)
// into `out`, of in.size() bytes; bytes past the last whole sample are copied as they are.
void unshuffleBytes(std::span<const std::byte> in, std::span<std::byte> out, size_t width);

}  // namespace ropecast
