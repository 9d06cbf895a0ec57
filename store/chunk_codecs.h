// Decoders that chunked and blocked sources share (Zarr, N5, HDF5, .vti): a zlib or gzip stream inflated
// whole, an LZ4 block, an xz (or legacy .lzma) stream, a bzip2 stream, the compressors of chunked arrays by
// name, and the byte shuffle (HDF5's filter 2, as blosc's) undone. Pure functions; any thread.
#pragma once

#include <cstddef>
#include <cstdint>
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

// The compressors of chunked arrays' chunks (Zarr's, N5's blocks).
enum class Compressor : uint8_t {
  Blosc,
  Zlib,
  Gzip,
  Zstd,
  Lz4Sized,   // numcodecs' LZ4: the decompressed size (4 bytes, little-endian), then an LZ4 block
  Lz4Blocks,  // lz4-java's block stream (N5's lz4): blocks after "LZ4Block" headers, each one's xxHash32
  Xz,         // an .xz stream or a legacy .lzma one
  Bzip2,
};

// Decompresses `in` into exactly out.size() bytes; "" on success, else what is wrong, worded to follow the
// chunk's name ("is damaged (zstd: ...)", "decompresses to 10 bytes; expected 12 bytes").
std::string decompressExactly(Compressor compressor, std::span<const std::byte> in, std::span<std::byte> out);

// Undoes the byte shuffle of `in` (each sample's byte k stored in the k-th plane of in.size() / width bytes)
// into `out`, of in.size() bytes; bytes past the last whole sample are copied as they are.
void unshuffleBytes(std::span<const std::byte> in, std::span<std::byte> out, size_t width);

}  // namespace ropecast
