#include "store/store_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/error.h"

namespace ropecast {

uint32_t storeCrc32(std::span<const std::byte> bytes) {
  uLong crc = crc32(0L, Z_NULL, 0);
  // zlib takes uInt lengths: feed large spans in pieces.
  size_t done = 0;
  while (done < bytes.size()) {
    const size_t piece = std::min<size_t>(bytes.size() - done, size_t(1) << 30);
    crc = crc32(crc, reinterpret_cast<const Bytef*>(bytes.data() + done), uInt(piece));
    done += piece;
  }
  return uint32_t(crc);
}

std::string storeMetadataToJson(const StoreMetadata& m) {
  nlohmann::json j;
  j["format"] = "ropecast octree store";
  j["dims"] = {m.volume.dims.x, m.volume.dims.y, m.volume.dims.z};
  j["spacing"] = {m.volume.spacing.x, m.volume.spacing.y, m.volume.spacing.z};
  const AxisDirections& a = m.volume.axes;
  j["axes"] = {{a[0].x, a[0].y, a[0].z}, {a[1].x, a[1].y, a[1].z}, {a[2].x, a[2].y, a[2].z}};
  if (m.xReversed) j["xReversed"] = true;
  if (m.volume.patientFrame) j["patientFrame"] = true;
  if (m.volume.origin) j["origin"] = {m.volume.origin->x, m.volume.origin->y, m.volume.origin->z};
  j["originalType"] = std::string(sampleTypeName(m.volume.type));
  j["valueRange"] = {m.volume.valueMin.value_or(0.0), m.volume.valueMax.value_or(0.0)};
  j["storedType"] = std::string(sampleTypeName(m.storedType));
  j["mapping"] = {{"scale", m.mapping.scale}, {"offset", m.mapping.offset}};
  j["brickSize"] = m.brickSize;
  j["border"] = m.border;
  j["levels"] = m.levels;
  j["discardBelow"] = m.discardBelow ? nlohmann::json(*m.discardBelow) : nlohmann::json(nullptr);
  j["zstdLevel"] = m.zstdLevel;
  j["payloadEncoding"] = m.payloadEncoding == PayloadEncoding::ZstdBytePlanes ? "zstd-byteplanes" : "zstd";
  j["source"] = m.volume.description;
  j["creationTool"] = m.creationTool;
  // The source names a file, and file names need not be UTF-8: bytes that are not become U+FFFD.
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

StoreWriter::StoreWriter(std::filesystem::path output) : file_(std::move(output), "StoreWriter") {}

uint64_t StoreWriter::appendPayload(std::span<const std::byte> payload) {
  uint64_t offset;
  {
    std::lock_guard lock(reserveMutex_);
    offset = endOffset_;
    endOffset_ += payload.size();
  }
  file_.writeAt(offset, payload);
  return offset;
}

void StoreWriter::finish(const StoreMetadata& metadata, std::span<const StoreNodeEntry> nodes) {
  if (finished_) throw Error("StoreWriter::finish: called twice for '" + output().string() + "'");
  const std::string json = storeMetadataToJson(metadata);
  const auto jsonBytes = std::as_bytes(std::span(json.data(), json.size()));
  const auto tableBytes = std::as_bytes(nodes);

  StoreHeader h{};
  std::memcpy(h.magic, kStoreMagic, sizeof h.magic);
  h.version = kStoreVersion;
  h.headerBytes = sizeof(StoreHeader);
  h.metadataOffset = endOffset_;
  h.metadataBytes = json.size();
  h.nodeTableOffset = h.metadataOffset + h.metadataBytes;
  h.nodeCount = nodes.size();
  h.metadataCrc = storeCrc32(jsonBytes);
  h.nodeTableCrc = storeCrc32(tableBytes);
  h.nodeEntryBytes = sizeof(StoreNodeEntry);
  h.headerCrc = storeCrc32(std::as_bytes(std::span(&h, 1)).first(offsetof(StoreHeader, headerCrc)));

  file_.writeAt(h.metadataOffset, jsonBytes);
  file_.writeAt(h.nodeTableOffset, tableBytes);
  file_.writeAt(0, std::as_bytes(std::span(&h, 1)));
  file_.commit();
  finished_ = true;
}

}  // namespace ropecast
