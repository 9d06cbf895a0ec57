#include "loader/store_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <nlohmann/json.hpp>
#include <vector>

#include "loader/error.h"

namespace ropecast {

namespace {
std::string errnoText() {
  return std::strerror(errno);
}

// Temporary names readable from a signal handler: a slot is claimed, filled, then published.
struct SignalSlot {
  std::atomic<bool> claimed{false};
  std::atomic<bool> ready{false};
  char path[4096];
};
constexpr int kSignalSlots = 32;
SignalSlot signalSlots[kSignalSlots];

int publishTemporary(const std::string& path) {
  if (path.size() >= sizeof(SignalSlot::path)) return -1;
  for (int i = 0; i < kSignalSlots; ++i) {
    bool expected = false;
    if (!signalSlots[i].claimed.compare_exchange_strong(expected, true)) continue;
    std::memcpy(signalSlots[i].path, path.c_str(), path.size() + 1);
    signalSlots[i].ready.store(true);
    return i;
  }
  return -1;  // more than kSignalSlots at once: that one is not removed on a signal
}

void withdrawTemporary(int slot) {
  if (slot < 0) return;
  signalSlots[slot].ready.store(false);
  signalSlots[slot].claimed.store(false);
}

void removeTemporariesAndDie(int signal) {
  for (auto& slot : signalSlots)
    if (slot.ready.load()) ::unlink(slot.path);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

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
  return j.dump(2);
}

TemporaryFile::TemporaryFile(std::filesystem::path output, std::string who)
    : output_(std::move(output)), who_(std::move(who)) {
  std::string pattern = output_.string() + ".tmp-XXXXXX";
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  fd_ = mkstemp(name.data());
  if (fd_ < 0)
    throw Error(who_ + ": cannot create output '" + output_.string() + "' (temporary '" + pattern +
                "'): " + errnoText());
  temporary_ = name.data();
  signalSlot_ = publishTemporary(temporary_.string());
  fchmod(fd_, 0644);  // mkstemp creates 0600; outputs are ordinary data files
}

TemporaryFile::~TemporaryFile() {
  withdrawTemporary(signalSlot_);
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !temporary_.empty()) ::unlink(temporary_.c_str());
}

TemporaryNameGuard::TemporaryNameGuard(const std::string& path) : signalSlot_(publishTemporary(path)) {}

TemporaryNameGuard::~TemporaryNameGuard() {
  withdrawTemporary(signalSlot_);
}

void removeTemporaryFilesOnSignals() {
  for (int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, removeTemporariesAndDie);
}

void TemporaryFile::writeAt(uint64_t offset, std::span<const std::byte> bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::pwrite(fd_, bytes.data() + done, bytes.size() - done, off_t(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw Error(who_ + ": writing '" + temporary_.string() + "' (for '" + output_.string() +
                  "') failed: " + (n < 0 ? errnoText() : "no progress"));
    done += size_t(n);
  }
}

void TemporaryFile::commit() {
  if (committed_ || fd_ < 0) throw Error(who_ + ": '" + output_.string() + "' committed twice");
  // No fsync: the rename makes a complete file appear atomically to readers, which is what we promise;
  // durability across power loss is the file system's business (zstd's CLI does not sync either).
  withdrawTemporary(signalSlot_);  // from here on the name may be the output's
  signalSlot_ = -1;
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) throw Error(who_ + ": closing '" + temporary_.string() + "' failed: " + errnoText());
  if (::rename(temporary_.c_str(), output_.c_str()) != 0)
    throw Error(who_ + ": renaming '" + temporary_.string() + "' to '" + output_.string() +
                "' failed: " + errnoText());
  committed_ = true;
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
