#include "store/chunk_codecs.h"

#include <cstring>

#include <zlib.h>

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
