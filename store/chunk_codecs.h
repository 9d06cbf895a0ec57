// Decoders that chunked and blocked sources share (Zarr, HDF5, .vti): a zlib or gzip stream inflated whole,
// an LZ4 block, an xz (or legacy .lzma) stream, a bzip2 stream, and the byte shuffle (HDF5's filter 2, as
// blosc's) undone. Pure functions; any thread.
#pragma once

#include <cstddef>
#include <span>
#include <string>

namespace ropecast {

// Inflates a zlib (or, with `gzip`, a gzip) stream into exactly out.size() bytes; false otherwise (damaged,
// or of another length).
bool inflateExactly(std::span<const std::byte> in, std::span<std::byte> out, bool gzip);

// Each decodes `in` into exactly out.size() bytes; "" on success, else what went wrong ("not an LZ4 block
// of that size", ...).
std::string lz4BlockExactly(std::span<const std::byte> in, std::span<std::byte> out);
// An .xz stream or a legacy .lzma one (liblzma's automatic decoder); at most 1 GiB of decoder memory, which
// a damaged header might ask for.
std::string lzmaExactly(std::span<const std::byte> in, std::span<std::byte> out);
std::string bzip2Exactly(std::span<const std::byte> in, std::span<std::byte> out);

// Undoes the byte shuffle of `in` (each sample's byte k stored in the k-th plane of in.size() / width bytes)
// into `out`, of in.size() bytes; bytes past the last whole sample are copied as they are.
void unshuffleBytes(std::span<const std::byte> in, std::span<std::byte> out, size_t width);

}  // namespace ropecast
