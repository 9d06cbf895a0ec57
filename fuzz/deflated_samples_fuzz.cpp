// libFuzzer target for deflated samples read through access points (store/file_samples.h,
// store/deflate_index.h): a payload repeated into megabytes is deflated (gzip or zlib, a level, one member or
// two), one byte of the stream possibly changed, and read twice: front to back, which takes the points, then
// in ranges of random order and length by a second reader, which resumes from them. Every range either reader
// returns must equal what zlib alone inflates from the stream's start; where zlib inflates the whole volume
// through its trailer, no read may fail; failures are ropecast::Error only. Input bytes: [0] level (low 4
// bits, up to 9), zlib (bit 4), two members (bit 5); [1] where the changed byte is (0: none, else a 255th of
// the stream), [2] its xor; [3] the payload's repeats (times 64); [4..11] the ranges' seed; the rest the
// payload.
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <span>
#include <string>

#include <zlib.h>

#include "core/error.h"
#include "fuzz/fuzz_input_file.h"
#include "store/file_samples.h"

namespace {

std::string deflated(const std::string& data, int level, bool gzip) {
  z_stream zs{};
  if (deflateInit2(&zs, level, Z_DEFLATED, gzip ? 15 + 16 : 15, 8, Z_DEFAULT_STRATEGY) != Z_OK) std::abort();
  std::string out(deflateBound(&zs, uLong(data.size())) + 64, '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  zs.avail_in = uInt(data.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = uInt(out.size());
  if (deflate(&zs, Z_FINISH) != Z_STREAM_END) std::abort();
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

// zlib alone, from the stream's start: members in turn until `wanted` bytes are out and a member has ended.
// Returns what it inflated; `whole` says whether that happened without an error.
std::string inflatedByZlib(const std::string& stream, size_t wanted, bool& whole) {
  z_stream zs{};
  if (inflateInit2(&zs, 15 + 32) != Z_OK) std::abort();
  std::string out(wanted + 65536, '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(stream.data()));
  zs.avail_in = uInt(stream.size());
  whole = false;
  for (;;) {
    zs.next_out = reinterpret_cast<Bytef*>(out.data()) + zs.total_out;
    zs.avail_out = uInt(out.size() - zs.total_out);
    const int status = inflate(&zs, Z_NO_FLUSH);
    if (status == Z_STREAM_END) {
      if (zs.total_out >= wanted) {
        whole = true;
        break;
      }
      if (zs.avail_in == 0) break;
      const uLong total = zs.total_out;
      if (inflateReset(&zs) != Z_OK) break;
      zs.total_out = total;
      continue;
    }
    if (status != Z_OK || zs.avail_out == 0) break;
  }
  out.resize(zs.total_out);
  inflateEnd(&zs);
  return out;
}

// A fresh file name per input: the index registry knows a file by its identity, and a file rewritten in place
// within the clock's tick at the same size would look unchanged.
const std::string& freshFile(const uint8_t* data, size_t size) {
  static uint64_t count = 0;
  static std::string last;
  if (!last.empty()) ::unlink(last.c_str());
  const std::string& written = ropecast::fuzz::writeInputFile("deflated", data, size);
  last = written + "." + std::to_string(count++);
  if (std::rename(written.c_str(), last.c_str()) != 0) std::abort();
  return last;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 13) return 0;
  const int level = std::min(data[0] & 15, 9);
  const bool gzip = (data[0] & 16) == 0;
  const bool twoMembers = gzip && (data[0] & 32) != 0;
  uint64_t seed = 0;
  for (int i = 0; i < 8; ++i) seed = seed << 8 | data[4 + i];
  const std::string payload(reinterpret_cast<const char*>(data) + 12, size - 12);
  std::string volume;
  for (int i = 0, repeats = 64 * (1 + data[3]); i < repeats && volume.size() < (size_t(6) << 20); ++i)
    volume += payload;

  std::string stream = twoMembers ? deflated(volume.substr(0, volume.size() / 2), level, true) +
                                        deflated(volume.substr(volume.size() / 2), level, true)
                                  : deflated(volume, level, gzip);
  if (data[1] != 0) stream[(stream.size() - 1) * data[1] / 255] ^= char(data[2] == 0 ? 1 : data[2]);
  bool whole = false;
  const std::string expected = inflatedByZlib(stream, volume.size(), whole);
  const std::string& path = freshFile(reinterpret_cast<const uint8_t*>(stream.data()), stream.size());

  ropecast::SampleBlock block;
  block.encoding = ropecast::SampleEncoding::Deflated;
  block.bytes = volume.size();
  block.fileKind = "fuzz input";
  const auto readerOf = [&] {
    return std::make_unique<ropecast::FileSamples>(std::make_unique<ropecast::PosixFile>(path), block);
  };
  // A range read: equal to zlib's bytes there, and failing only where zlib did not inflate the volume.
  const auto check = [&](ropecast::FileSamples& samples, size_t offset, size_t length) {
    std::string got(length, '\0');
    try {
      samples.read(offset, std::as_writable_bytes(std::span(got)));
    } catch (const ropecast::Error&) {
      if (whole) std::abort();
      return false;
    }
    if (offset + length > expected.size() || expected.compare(offset, length, got) != 0) std::abort();
    return true;
  };
  try {
    auto first = readerOf();
    for (size_t at = 0; at < volume.size(); at += size_t(1) << 18)
      if (!check(*first, at, std::min(size_t(1) << 18, volume.size() - at))) break;
    auto second = readerOf();
    std::mt19937_64 random(seed);
    for (int i = 0; i < 12; ++i) {
      const size_t offset = random() % volume.size();
      check(*second, offset, 1 + random() % std::min<size_t>(volume.size() - offset, size_t(1) << 20));
    }
  } catch (const ropecast::Error&) {
    if (whole) std::abort();
  }
  return 0;
}
