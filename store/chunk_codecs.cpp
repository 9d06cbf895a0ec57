#include "store/chunk_codecs.h"

#include <bzlib.h>
#include <lz4.h>
#include <lzma.h>
#include <zlib.h>

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
