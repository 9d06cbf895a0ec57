// libFuzzer target for the Zarr and N5 metadata parsers (store/zarr_metadata.h, store/n5_metadata.h): the
// first byte picks a v2 `.zarray`, a v3 `zarr.json`, an OME-Zarr `multiscales`, an N5 dataset's attributes
// or an N5 group's (its calibration and multiscale dataset) and a block header, the rest is its text. Any
// input must either parse into metadata that keeps the parser's promises or throw ropecast::Error; never
// crash, hang or throw anything else (a JSON library exception escaping would be a finding).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string_view>

#include "core/error.h"
#include "store/n5_metadata.h"
#include "store/zarr_metadata.h"

namespace {

// Shapes and chunks of one length, chunks positive and at most 2 GiB, shards' inner chunks dividing them:
// what the Zarr source relies on.
void checkArray(const ropecast::ZarrArray& a) {
  if (a.shape.empty() || a.chunks.size() != a.shape.size()) std::abort();
  uint64_t bytes = ropecast::bytesPerSample(a.type);
  for (uint64_t c : a.chunks) {
    if (c == 0) std::abort();
    bytes *= c;
    if (bytes > (uint64_t(1) << 31)) std::abort();
  }
  if (a.separator != '.' && a.separator != '/') std::abort();
  if (a.sharding) {
    if (a.sharding->chunks.size() != a.chunks.size()) std::abort();
    for (size_t i = 0; i < a.chunks.size(); ++i)
      if (a.sharding->chunks[i] == 0 || a.chunks[i] % a.sharding->chunks[i] != 0) std::abort();
  }
  if (!a.dimensionNames.empty() && a.dimensionNames.size() != a.shape.size()) std::abort();
}

// Shapes and blocks of one length, blocks positive and at most 2 GiB: what the N5 source relies on.
void checkN5Dataset(const ropecast::N5Dataset& d) {
  if (d.shape.empty() || d.blockSize.size() != d.shape.size()) std::abort();
  uint64_t bytes = ropecast::bytesPerSample(d.type);
  for (uint64_t b : d.blockSize) {
    if (b == 0) std::abort();
    bytes *= b;
    if (bytes > (uint64_t(1) << 31)) std::abort();
  }
}

// A header's sizes, one per axis, and its length within the block.
void checkN5BlockHeader(std::string_view bytes) {
  const size_t rank = bytes.empty() ? 0 : size_t(uint8_t(bytes[0])) % 6;
  const auto block = std::as_bytes(std::span(bytes.data(), bytes.size()));
  ropecast::N5BlockHeader header;
  if (ropecast::parseN5BlockHeader(block, rank, header).empty() &&
      (header.size.size() != rank || header.bytes > block.size()))
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int parser = data[0] % 5;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    if (parser == 0) {
      checkArray(ropecast::parseZarrArray(text, "fuzz/.zarray"));
    } else if (parser == 1) {
      ropecast::zarrV3NodeType(text, "fuzz/zarr.json");
      checkArray(ropecast::parseZarrV3Array(text, "fuzz/zarr.json"));
    } else if (parser == 3) {
      checkN5Dataset(ropecast::parseN5Dataset(text, "fuzz/attributes.json"));
    } else if (parser == 4) {
      checkN5BlockHeader(text);
      const ropecast::N5Calibration c = ropecast::parseN5Calibration(text, "fuzz/attributes.json");
      if (!c.axisNames.empty() && c.scale && c.scale->size() != c.axisNames.size()) std::abort();
      ropecast::n5MultiscaleDataset(text, "fuzz/attributes.json");
      ropecast::parseN5DownsamplingFactors(text, "fuzz/attributes.json");
    } else if (const auto ome = ropecast::parseOmeMultiscale(text, "fuzz/.zattrs", size % 2 ? "1" : "")) {
      if (ome->scale && !ome->axisNames.empty() && ome->scale->size() != ome->axisNames.size()) std::abort();
      for (const std::string& label : ome->channelLabels)
        if (label.empty()) std::abort();  // labels are all given or none
    }
  } catch (const ropecast::Error&) {
  }
  return 0;
}
