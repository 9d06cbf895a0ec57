#include "store/chunk_codecs.h"

#include <blosc.h>
#include <bzlib.h>
#include <lz4.h>
#include <lzma.h>
#include <xxhash.h>
#include <zlib.h>
#include <zstd.h>

#include <cstdint>
#include <cstring>

namespace ropecast {

bool inflateExactly(std::span<const std::byte> in, std::span<std::byte> out, bool gzip) {
  z_stream zs{};
  if (inflateInit2(&zs, gzip ? 15 + 16 : 15) != Z_OK) return false;
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(in.data()));
  zs.avail_in = uInt(in.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = uInt(out.size());
  const int status = inflate(&zs, Z_FINISH);
  const bool whole = status == Z_STREAM_END && zs.total_out == out.size();
  inflateEnd(&zs);
  return whole;
}

std::string lz4BlockExactly(std::span<const std::byte> in, std::span<std::byte> out) {
  if (in.size() > size_t(LZ4_MAX_INPUT_SIZE) || out.size() > size_t(INT32_MAX)) return "too large for LZ4";
  const int produced =
      LZ4_decompress_safe(reinterpret_cast<const char*>(in.data()), reinterpret_cast<char*>(out.data()),
                          int(in.size()), int(out.size()));
  if (produced < 0) return "not an LZ4 block, or one of more than " + std::to_string(out.size()) + " bytes";
  if (size_t(produced) != out.size())
    return std::to_string(produced) + " bytes instead of " + std::to_string(out.size());
  return "";
}

std::string lzmaExactly(std::span<const std::byte> in, std::span<std::byte> out) {
  lzma_stream stream = LZMA_STREAM_INIT;
  if (lzma_auto_decoder(&stream, uint64_t(1) << 30, 0) != LZMA_OK) return "liblzma could not start";
  stream.next_in = reinterpret_cast<const uint8_t*>(in.data());
  stream.avail_in = in.size();
  stream.next_out = reinterpret_cast<uint8_t*>(out.data());
  stream.avail_out = out.size();
  lzma_ret status = lzma_code(&stream, LZMA_FINISH);
  const size_t produced = out.size() - stream.avail_out;
  if (status == LZMA_OK && stream.avail_out == 0) {  // full: only the stream's end may follow
    uint8_t extra = 0;
    stream.next_out = &extra;
    stream.avail_out = 1;
    status = lzma_code(&stream, LZMA_FINISH);
    if (stream.avail_out == 0) status = LZMA_BUF_ERROR;
  }
  lzma_end(&stream);
  if (status == LZMA_STREAM_END)
    return produced == out.size()
               ? ""
               : std::to_string(produced) + " bytes instead of " + std::to_string(out.size());
  if (status == LZMA_MEMLIMIT_ERROR) return "it needs more than 1 GiB to decode";
  if (status == LZMA_BUF_ERROR) return "more than " + std::to_string(out.size()) + " bytes, or cut short";
  return "not an xz or lzma stream, or a damaged one (liblzma error " + std::to_string(int(status)) + ")";
}

std::string bzip2Exactly(std::span<const std::byte> in, std::span<std::byte> out) {
  if (in.size() > UINT32_MAX || out.size() > UINT32_MAX) return "too large for bzip2";
  unsigned produced = unsigned(out.size());
  const int status = BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(out.data()), &produced,
                                                const_cast<char*>(reinterpret_cast<const char*>(in.data())),
                                                unsigned(in.size()), 0, 0);
  if (status == BZ_OUTBUFF_FULL) return "more than " + std::to_string(out.size()) + " bytes";
  if (status != BZ_OK)
    return "not a bzip2 stream, or a damaged one (bzip2 error " + std::to_string(status) + ")";
  if (produced != out.size())
    return std::to_string(produced) + " bytes instead of " + std::to_string(out.size());
  return "";
}

namespace {

uint32_t littleEndian32(const std::byte* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// lz4-java's LZ4BlockOutputStream (N5's lz4 compression): blocks, each after a header of 21 bytes
// ("LZ4Block", a token whose high bits say raw 0x10 or LZ4 0x20, the stored and the decompressed length and
// the xxHash32 of the decompressed bytes (seed 0x9747b28c) masked to 28 bits, little-endian), ended by an
// empty raw block.
std::string lz4JavaBlocksExactly(std::span<const std::byte> in, std::span<std::byte> out) {
  constexpr size_t kHeaderBytes = 21;
  constexpr int kRaw = 0x10, kLz4 = 0x20;
  constexpr uint32_t kSeed = 0x9747b28c, kChecksumMask = 0x0fffffff;
  size_t read = 0, produced = 0;
  for (;;) {
    if (in.size() - read < kHeaderBytes) return "cut short (a block header, or the stream's end, is missing)";
    const std::byte* header = in.data() + read;
    if (std::memcmp(header, "LZ4Block", 8) != 0)
      return "not lz4-java's block stream (no LZ4Block header at byte " + std::to_string(read) + ")";
    const int method = std::to_integer<int>(header[8]) & 0xf0;
    const uint32_t stored = littleEndian32(header + 9), size = littleEndian32(header + 13);
    const uint32_t checksum = littleEndian32(header + 17);
    read += kHeaderBytes;
    if (method != kRaw && method != kLz4)
      return "a block of unknown method " + std::to_string(method) + " at byte " + std::to_string(read);
    if (stored == 0 && size == 0) break;  // the stream's end
    if (stored > in.size() - read) return "cut short (a block of " + std::to_string(stored) + " bytes)";
    if (size > out.size() - produced) return "more than " + std::to_string(out.size()) + " bytes";
    const std::span<const std::byte> block = in.subspan(read, stored);
    const std::span<std::byte> into = out.subspan(produced, size);
    if (method == kRaw) {
      if (stored != size)
        return "a raw block of " + std::to_string(stored) + " bytes holding " + std::to_string(size);
      std::memcpy(into.data(), block.data(), size);
    } else if (std::string problem = lz4BlockExactly(block, into); !problem.empty()) {
      return problem;
    }
    if ((XXH32(into.data(), into.size(), kSeed) & kChecksumMask) != checksum)
      return "a block's checksum does not match its bytes";
    read += stored;
    produced += size;
  }
  if (produced != out.size())
    return std::to_string(produced) + " bytes instead of " + std::to_string(out.size());
  return "";
}

}  // namespace

std::string decompressExactly(Compressor compressor, std::span<const std::byte> in,
                              std::span<std::byte> out) {
  const std::string expected = "; expected " + std::to_string(out.size()) + " bytes";
  switch (compressor) {
    case Compressor::Blosc: {
      size_t bytes = 0;
      if (blosc_cbuffer_validate(in.data(), in.size(), &bytes) != 0) return "is not blosc data" + expected;
      if (bytes != out.size()) return "decompresses to " + std::to_string(bytes) + " bytes" + expected;
      if (blosc_decompress_ctx(in.data(), out.data(), out.size(), 1) != int(out.size()))
        return "is damaged (blosc)";
      return "";
    }
    case Compressor::Zlib:
    case Compressor::Gzip:
      if (!inflateExactly(in, out, compressor == Compressor::Gzip))
        return std::string("is damaged or of another size (") +
               (compressor == Compressor::Gzip ? "gzip" : "zlib") + ")" + expected;
      return "";
    case Compressor::Zstd: {
      const size_t n = ZSTD_decompress(out.data(), out.size(), in.data(), in.size());
      if (ZSTD_isError(n)) return std::string("is damaged (zstd: ") + ZSTD_getErrorName(n) + ")";
      if (n != out.size()) return "decompresses to " + std::to_string(n) + " bytes" + expected;
      return "";
    }
    case Compressor::Lz4Sized: {
      // numcodecs' LZ4: the decompressed size, 4 bytes little-endian, before the block.
      if (in.size() < 4) return "is too short for numcodecs' LZ4 (its size header)";
      const uint32_t size = littleEndian32(in.data());
      if (size != out.size()) return "says it holds " + std::to_string(size) + " bytes" + expected;
      if (std::string problem = lz4BlockExactly(in.subspan(4), out); !problem.empty())
        return "is damaged (lz4: " + problem + ")";
      return "";
    }
    case Compressor::Xz:
      if (std::string problem = lzmaExactly(in, out); !problem.empty())
        return "is damaged (lzma: " + problem + ")";
      return "";
    case Compressor::Bzip2:
      if (std::string problem = bzip2Exactly(in, out); !problem.empty())
        return "is damaged (bz2: " + problem + ")";
      return "";
    case Compressor::Lz4Blocks:
      if (std::string problem = lz4JavaBlocksExactly(in, out); !problem.empty())
        return "is damaged (lz4: " + problem + ")";
      return "";
  }
  return "has an unknown compressor";
}

void unshuffleBytes(std::span<const std::byte> in, std::span<std::byte> out, size_t width) {
  const size_t samples = width ? in.size() / width : 0;
  for (size_t k = 0; k < width; ++k) {
    const std::byte* plane = in.data() + k * samples;
    for (size_t i = 0; i < samples; ++i) out[i * width + k] = plane[i];
  }
  const size_t whole = samples * width;
  if (whole < in.size()) std::memcpy(out.data() + whole, in.data() + whole, in.size() - whole);
}

}  // namespace ropecast
