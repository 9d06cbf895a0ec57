// libFuzzer target for the store reader (store/store.h) and verifier (store/verify.h): any bytes opened as
// a store must either be rejected with ropecast::Error or open into a store whose every node reads (or throws
// ropecast::Error) and verifies without crashing, hanging or throwing anything else.
//
// Input: one mode byte, then the file. With mode bit 0 set, the harness first recomputes the checksums
// (payloads, node table, metadata, header) where the offsets allow, so mutations reach the JSON and
// node-table checks instead of stopping at a checksum.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "store/store.h"
#include "store/verify.h"

namespace {

using namespace ropecast;

void fixChecksums(std::vector<std::byte>& file) {
  if (file.size() < sizeof(StoreHeader)) return;
  StoreHeader h;
  std::memcpy(&h, file.data(), sizeof h);
  const uint64_t n = file.size();
  if (h.nodeTableOffset <= n && h.nodeCount <= (n - h.nodeTableOffset) / sizeof(StoreNodeEntry)) {
    for (uint64_t i = 0; i < h.nodeCount; ++i) {
      StoreNodeEntry e;
      std::byte* at = file.data() + h.nodeTableOffset + i * sizeof e;
      std::memcpy(&e, at, sizeof e);
      if (e.payloadOffset <= n && e.payloadBytes <= n - e.payloadOffset) {
        e.payloadCrc = storeCrc32(std::span(file).subspan(e.payloadOffset, e.payloadBytes));
        std::memcpy(at, &e, sizeof e);
      }
    }
    h.nodeTableCrc =
        storeCrc32(std::span(file).subspan(h.nodeTableOffset, h.nodeCount * sizeof(StoreNodeEntry)));
  }
  if (h.metadataOffset <= n && h.metadataBytes <= n - h.metadataOffset)
    h.metadataCrc = storeCrc32(std::span(file).subspan(h.metadataOffset, h.metadataBytes));
  h.headerCrc = storeCrc32(std::as_bytes(std::span(&h, 1)).first(offsetof(StoreHeader, headerCrc)));
  std::memcpy(file.data(), &h, sizeof h);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  std::vector<std::byte> file(size - 1);
  if (!file.empty()) std::memcpy(file.data(), data + 1, file.size());
  if (data[0] & 1) fixChecksums(file);
  std::unique_ptr<Store> store;
  try {
    store = Store::openMemory(std::move(file), "fuzz.store");
  } catch (const Error&) {
    return 0;
  }
  const OctreeLayout& layout = store->info().layout;
  std::vector<std::byte> brick(store->brickBytes());
  for (uint64_t i = 0; i < layout.insideNodeCount(); ++i) {
    try {
      store->readBrick(layout.nodeAt(i), brick);
    } catch (const Error&) {
    }
  }
  if (layout.insideNodeCount() <= 4096 && layout.storedBrickSamples() <= 40 * 40 * 40) verifyStore(*store);
  return 0;
}
