#include "store/store.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "core/error.h"
#include "core/file_names.h"
#include "core/input_file.h"
#include "store/procedural.h"

namespace ropecast {

namespace {

// One zstd decompression context per thread, so concurrent readBrick calls share nothing.
struct ThreadDecoder {
  ZSTD_DCtx* context = ZSTD_createDCtx();
  std::vector<std::byte> compressed, planes;
  ThreadDecoder() {
    if (!context) throw Error("Store: cannot create a zstd decompression context (out of memory)");
  }
  ~ThreadDecoder() { ZSTD_freeDCtx(context); }
};
ThreadDecoder& threadDecoder() {
  thread_local ThreadDecoder decoder;
  return decoder;
}

void fillBrick(std::span<std::byte> out, SampleType storedType, uint16_t value) {
  if (storedType == SampleType::UInt8) {
    std::memset(out.data(), int(value & 0xFF), out.size());
  } else {
    auto* p = reinterpret_cast<uint16_t*>(out.data());
    std::fill(p, p + out.size() / 2, value);
  }
}

// get<uint32_t>() would wrap 2^32 + 8 to 8 and cut 8.5 to 8: a damaged field must not pass for another value.
uint32_t readUint32(const nlohmann::json& j, const std::string& what) {
  if (!j.is_number_unsigned() || j.get<uint64_t>() > UINT32_MAX)
    throw std::runtime_error(what + ": expected an integer in [0, 2^32), got " + j.dump());
  return uint32_t(j.get<uint64_t>());
}
glm::u32vec3 readVec3u(const nlohmann::json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3) throw std::runtime_error(what + ": expected an array of 3 integers");
  return {readUint32(j.at(0), what), readUint32(j.at(1), what), readUint32(j.at(2), what)};
}
glm::dvec3 readVec3d(const nlohmann::json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3 || !j.at(0).is_number() || !j.at(1).is_number() || !j.at(2).is_number())
    throw std::runtime_error(what + ": expected an array of 3 numbers");
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

// "axes": the unit world directions of x, y and z, at right angles and not mirroring (the converter turns
// a mirroring volume's x around).
AxisDirections readAxes(const nlohmann::json& j) {
  if (!j.is_array() || j.size() != 3) throw std::runtime_error("axes: expected 3 arrays of 3 numbers");
  const glm::dvec3 x = readVec3d(j.at(0), "axes"), y = readVec3d(j.at(1), "axes"),
                   z = readVec3d(j.at(2), "axes");
  const std::optional<AxisDirections> axes = axisDirectionsOf(x, y, z);
  constexpr double kUnit = 1e-6;
  for (const glm::dvec3& v : {x, y, z})
    if (!(std::abs(glm::length(v) - 1.0) <= kUnit)) throw std::runtime_error("axes: expected unit vectors");
  if (!axes || mirrors(*axes))
    throw std::runtime_error("axes: expected a rotation (at right angles, not mirroring)");
  return *axes;
}

// The metadata's key, or an error naming it.
const nlohmann::json& field(const nlohmann::json& j, const std::string& key) {
  if (!j.is_object() || !j.contains(key)) throw std::runtime_error("missing \"" + key + "\"");
  return j[key];
}
double numberField(const nlohmann::json& j, const std::string& key) {
  const nlohmann::json& v = field(j, key);
  if (!v.is_number()) throw std::runtime_error("\"" + key + "\": expected a number, got " + v.dump());
  return v.get<double>();
}
std::string textField(const nlohmann::json& j, const std::string& key) {
  const nlohmann::json& v = field(j, key);
  if (!v.is_string()) throw std::runtime_error("\"" + key + "\": expected a string, got " + v.dump());
  return v.get<std::string>();
}

StoreMetadata parseMetadata(const std::string& text, const std::string& name) {
  StoreMetadata m;
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    m.volume.dims = readVec3u(field(j, "dims"), "dims");
    m.volume.spacing = readVec3d(field(j, "spacing"), "spacing");
    if (j.contains("axes")) m.volume.axes = readAxes(j["axes"]);  // absent in stores written before
    if (j.contains("origin")) {  // absent where the source placed its samples nowhere, or written before
      m.volume.origin = readVec3d(j["origin"], "origin");
      if (!std::isfinite(m.volume.origin->x) || !std::isfinite(m.volume.origin->y) ||
          !std::isfinite(m.volume.origin->z))
        throw std::runtime_error("origin: expected finite numbers");
    }
    if (j.contains("patientFrame")) {  // absent: false (and in stores written before it)
      if (!j["patientFrame"].is_boolean())
        throw std::runtime_error("\"patientFrame\": expected true or false");
      m.volume.patientFrame = j["patientFrame"].get<bool>();
    }
    if (j.contains("xReversed")) {
      if (!j["xReversed"].is_boolean()) throw std::runtime_error("\"xReversed\": expected true or false");
      m.xReversed = j["xReversed"].get<bool>();
    }
    const auto type = parseSampleType(textField(j, "originalType"));
    const auto stored = parseSampleType(textField(j, "storedType"));
    if (!type || !stored) throw std::runtime_error("unknown sample type");
    m.volume.type = *type;
    m.storedType = *stored;
    const auto& range = field(j, "valueRange");
    if (!range.is_array() || range.size() != 2 || !range.at(0).is_number() || !range.at(1).is_number())
      throw std::runtime_error("valueRange: expected [min, max]");
    m.volume.valueMin = range.at(0).get<double>();
    m.volume.valueMax = range.at(1).get<double>();
    if (!(*m.volume.valueMin <= *m.volume.valueMax) || !std::isfinite(*m.volume.valueMin) ||
        !std::isfinite(*m.volume.valueMax))
      throw std::runtime_error("valueRange: expected finite [min, max] with min <= max");
    m.mapping.scale = numberField(field(j, "mapping"), "scale");
    m.mapping.offset = numberField(field(j, "mapping"), "offset");
    m.brickSize = readUint32(field(j, "brickSize"), "brickSize");
    m.border = readUint32(field(j, "border"), "border");
    m.levels = readUint32(field(j, "levels"), "levels");
    if (!field(j, "discardBelow").is_null()) m.discardBelow = numberField(j, "discardBelow");
    const double zstdLevel = numberField(j, "zstdLevel");  // informative; any zstd level is in [-2^17, 22]
    if (!(std::abs(zstdLevel) <= 1e6)) throw std::runtime_error("\"zstdLevel\": expected a zstd level");
    m.zstdLevel = int(zstdLevel);
    const std::string encoding = textField(j, "payloadEncoding");
    if (encoding == "zstd-byteplanes")
      m.payloadEncoding = PayloadEncoding::ZstdBytePlanes;
    else if (encoding != "zstd")
      throw std::runtime_error("unknown payloadEncoding '" + encoding + "'");
    m.volume.description = textField(j, "source");
    m.creationTool = textField(j, "creationTool");
  } catch (const nlohmann::json::exception& e) {
    throw Error("Store: '" + name + "': damaged metadata: " + e.what());
  } catch (const std::runtime_error& e) {
    throw Error("Store: '" + name + "': damaged metadata: " + e.what());
  }
  const auto& d = m.volume.dims;
  if (!isValidDims(d)) throw Error("Store: '" + name + "': metadata dims must be in [1, 2^20] per axis");
  if (m.storedType != storedTypeFor(m.volume.type))
    throw Error("Store: '" + name + "': metadata storedType does not match originalType");
  if (m.payloadEncoding == PayloadEncoding::ZstdBytePlanes && m.storedType != SampleType::UInt16)
    throw Error("Store: '" + name + "': metadata payloadEncoding zstd-byteplanes needs storedType uint16");
  if (m.border != kBrickBorder)
    throw Error("Store: '" + name + "': metadata border " + std::to_string(m.border) + ", expected " +
                std::to_string(kBrickBorder));
  if (!(m.mapping.scale > 0.0) || !std::isfinite(m.mapping.scale) || !std::isfinite(m.mapping.offset))
    throw Error("Store: '" + name + "': metadata mapping must have a finite positive scale");
  if (!isValidSpacing(m.volume.spacing))
    throw Error("Store: '" + name + "': metadata spacing " + formatSpacing(m.volume.spacing) + " must be " +
                validSpacingText());
  return m;
}

}  // namespace

bool isStoreFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the read
  char magic[sizeof kStoreMagic] = {};
  std::ifstream file(path, std::ios::binary);
  return file.read(magic, sizeof magic) && std::equal(magic, magic + sizeof magic, kStoreMagic);
}

bool isStoreInput(const std::string& path) {
  return isStoreFile(path) || lowerExtension(path) == ".rcast";
}

std::string Store::describeNode(const NodeKey& k) {
  return "depth " + std::to_string(k.depth) + " (" + std::to_string(k.coord.x) + ", " +
         std::to_string(k.coord.y) + ", " + std::to_string(k.coord.z) + ")";
}

std::unique_ptr<Store> Store::open(const std::filesystem::path& path) {
  std::unique_ptr<Store> store(new Store());
  store->name_ = path.string();
  std::error_code ec;
  if (isProceduralSpec(path.string()) && !std::filesystem::exists(path, ec))
    throw UsageError(
        "'" + path.string() +
        "' is a procedural volume, not a store file: render, view and bench take it as it is, and "
        "`ropecast convert " +
        path.string() + " -o FILE` makes a store of it");
  requireRegularFile(path.string(),
                     "Store: '" + path.string() + "'");  // before open(), which waits on a FIFO
  store->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (store->fd_ < 0) throw Error("Store: cannot open '" + path.string() + "': " + std::strerror(errno));
  struct stat st {};
  if (::fstat(store->fd_, &st) != 0 || !S_ISREG(st.st_mode))
    throw Error("Store: '" + path.string() + "' is not a regular file");
  store->fileBytes_ = uint64_t(st.st_size);
  store->load();
  return store;
}

std::unique_ptr<Store> Store::openMemory(std::vector<std::byte> bytes, std::string name) {
  std::unique_ptr<Store> store(new Store());
  store->name_ = std::move(name);
  store->memory_ = std::move(bytes);
  store->fileBytes_ = store->memory_.size();
  store->load();
  return store;
}

Store::~Store() {
  if (fd_ >= 0) ::close(fd_);
}

void Store::readAt(uint64_t offset, std::span<std::byte> out) const {
  if (offset > fileBytes_ || out.size() > fileBytes_ - offset)
    throw Error("Store: '" + name_ + "' is truncated (read of " + std::to_string(out.size()) + " bytes at " +
                std::to_string(offset) + " beyond its " + std::to_string(fileBytes_) + " bytes)");
  if (fd_ < 0) {
    if (!out.empty()) std::memcpy(out.data(), memory_.data() + offset, out.size());
    return;
  }
  size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, off_t(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Error("Store: reading '" + name_ + "' failed: " + std::strerror(errno));
    if (n == 0) throw Error("Store: '" + name_ + "' is truncated (unexpected end of file)");
    done += size_t(n);
  }
}

void Store::load() {
  const std::string damaged = "Store: '" + name_ + "': ";
  if (fileBytes_ < sizeof(StoreHeader))
    throw Error(damaged + "too short for a store header (" + std::to_string(fileBytes_) + " bytes)");
  StoreHeader h{};
  readAt(0, std::as_writable_bytes(std::span(&h, 1)));
  if (std::memcmp(h.magic, kStoreMagic, sizeof h.magic) != 0)
    throw Error(damaged + "not a ropecast store (bad magic); a volume becomes one with `ropecast convert`");
  if (h.version != kStoreVersion)
    throw Error(damaged + "unsupported store version " + std::to_string(h.version) + " (expected " +
                std::to_string(kStoreVersion) + ")");
  if (storeCrc32(std::as_bytes(std::span(&h, 1)).first(offsetof(StoreHeader, headerCrc))) != h.headerCrc)
    throw Error(damaged + "damaged header (checksum mismatch)");
  if (h.headerBytes != sizeof(StoreHeader) || h.nodeEntryBytes != sizeof(StoreNodeEntry))
    throw Error(damaged + "damaged header (unexpected header or node entry size)");
  if (h.metadataOffset < sizeof(StoreHeader) || h.metadataOffset > fileBytes_ ||
      h.metadataBytes > fileBytes_ - h.metadataOffset || h.metadataBytes > (64u << 20))
    throw Error(damaged + "truncated or damaged (metadata beyond the end of the file)");
  if (h.nodeTableOffset < h.metadataOffset + h.metadataBytes || h.nodeTableOffset > fileBytes_ ||
      h.nodeCount > (fileBytes_ - h.nodeTableOffset) / sizeof(StoreNodeEntry))
    throw Error(damaged + "truncated or damaged (node table beyond the end of the file)");

  std::string text(h.metadataBytes, '\0');
  readAt(h.metadataOffset, std::as_writable_bytes(std::span(text.data(), text.size())));
  if (storeCrc32(std::as_bytes(std::span(text.data(), text.size()))) != h.metadataCrc)
    throw Error(damaged + "damaged metadata (checksum mismatch)");
  metadata_ = parseMetadata(text, name_);

  OctreeLayout layout;
  try {
    layout = OctreeLayout::forVolume(metadata_.volume.dims, metadata_.brickSize);
  } catch (const std::invalid_argument& e) {
    throw Error(damaged + "damaged metadata: " + e.what());
  }
  if (metadata_.levels != layout.maxDepth + 1)
    throw Error(damaged + "metadata levels " + std::to_string(metadata_.levels) +
                " do not match dims and brick");
  if (h.nodeCount != layout.insideNodeCount())
    throw Error(damaged + "node table has " + std::to_string(h.nodeCount) + " nodes, the layout needs " +
                std::to_string(layout.insideNodeCount()));

  entries_.resize(h.nodeCount);
  const auto table = std::as_writable_bytes(std::span(entries_));
  readAt(h.nodeTableOffset, table);
  if (storeCrc32(table) != h.nodeTableCrc) throw Error(damaged + "damaged node table (checksum mismatch)");
  nodeTableEnd_ = h.nodeTableOffset + table.size();

  info_.layout = layout;
  info_.volume = metadata_.volume;
  info_.storedType = metadata_.storedType;
  info_.mapping = metadata_.mapping;
  info_.xReversed = metadata_.xReversed;

  const uint64_t maxPayload = ZSTD_compressBound(brickBytes());
  const uint16_t maxValue = metadata_.storedType == SampleType::UInt8 ? 255 : 65535;
  for (uint64_t i = 0; i < entries_.size(); ++i) {
    const StoreNodeEntry& e = entries_[i];
    const auto bad = [&](const char* what) {
      return Error(damaged + "node " + describeNode(layout.nodeAt(i)) + ": " + what);
    };
    if (e.kind < uint8_t(NodeKind::Empty) || e.kind > uint8_t(NodeKind::Data)) throw bad("invalid kind");
    if (e.minValue > e.maxValue || e.maxValue > maxValue) throw bad("invalid value range");
    if (e.payloadBytes > 0) {
      if (e.kind != uint8_t(NodeKind::Data)) throw bad("payload on a node without data");
      if (e.payloadBytes > maxPayload || e.payloadOffset < sizeof(StoreHeader) ||
          e.payloadOffset > h.metadataOffset || e.payloadBytes > h.metadataOffset - e.payloadOffset)
        throw bad("payload outside the payload region");
    }
  }
}

NodeInfo Store::node(const NodeKey& key) const {
  if (!info_.layout.isInside(key)) return {};
  const StoreNodeEntry& e = entries_[info_.layout.nodeIndex(key)];
  return {NodeKind(e.kind), e.minValue, e.maxValue};
}

void Store::readBrick(const NodeKey& key, std::span<std::byte> out) const {
  const size_t bytes = brickBytes();
  if (out.size() != bytes)
    throw Error("Store::readBrick: output buffer has " + std::to_string(out.size()) + " bytes, expected " +
                std::to_string(bytes));
  if (!info_.layout.isInside(key)) {
    std::memset(out.data(), 0, out.size());
    return;
  }
  const StoreNodeEntry& e = entries_[info_.layout.nodeIndex(key)];
  switch (NodeKind(e.kind)) {
    case NodeKind::Outside:
      std::memset(out.data(), 0, out.size());
      return;
    case NodeKind::Empty:  // its samples were not kept: its brick's minimum stands for them
    case NodeKind::Constant:
      fillBrick(out, info_.storedType, e.fillValue);
      return;
    case NodeKind::Data:
      break;
  }
  if (e.payloadBytes == 0) {
    fillBrick(out, info_.storedType, e.fillValue);
    return;
  }
  ThreadDecoder& decoder = threadDecoder();
  decoder.compressed.resize(e.payloadBytes);
  readAt(e.payloadOffset, decoder.compressed);
  const auto fail = [&](const std::string& what) {
    return Error("Store::readBrick: '" + name_ + "': node " + describeNode(key) + ": " + what);
  };
  if (storeCrc32(decoder.compressed) != e.payloadCrc) throw fail("damaged brick (checksum mismatch)");
  const bool planes = metadata_.payloadEncoding == PayloadEncoding::ZstdBytePlanes;
  if (planes) decoder.planes.resize(bytes);
  const std::span<std::byte> target = planes ? std::span<std::byte>(decoder.planes) : out;
  const size_t n = ZSTD_decompressDCtx(decoder.context, target.data(), target.size(),
                                       decoder.compressed.data(), decoder.compressed.size());
  if (ZSTD_isError(n)) throw fail(std::string("damaged brick (") + ZSTD_getErrorName(n) + ")");
  if (n != bytes) throw fail("damaged brick (decompressed to " + std::to_string(n) + " bytes)");
  if (planes) joinBytePlanes(decoder.planes.data(), bytes / 2, reinterpret_cast<uint16_t*>(out.data()));
}

uint64_t Store::compressedBytes(const NodeKey& key) const {
  if (!info_.layout.isInside(key)) return 0;
  return entries_[info_.layout.nodeIndex(key)].payloadBytes;
}

StoreSummary summarizeStore(const Store& store) {
  StoreSummary s;
  const OctreeLayout& layout = store.info().layout;
  const uint64_t brick = store.brickBytes();
  for (uint32_t depth = layout.maxDepth + 1; depth-- > 0;) {
    StoreSummary::Level level;
    level.depth = depth;
    level.level = layout.levelOfDepth(depth);
    level.dims = layout.levelDims(level.level);
    level.nodes = layout.insideNodes(depth);
    s.levels.push_back(level);
  }
  const auto entries = store.entries();
  for (uint64_t i = 0; i < entries.size(); ++i) {
    const StoreNodeEntry& e = entries[i];
    StoreSummary::Level& level = s.levels[layout.levelOfDepth(layout.nodeAt(i).depth)];
    ++level.total;
    if (e.kind == uint8_t(NodeKind::Empty)) ++level.empty;
    if (e.kind == uint8_t(NodeKind::Constant)) ++level.constant;
    if (e.kind == uint8_t(NodeKind::Data)) ++level.data;
    level.payloadBytes += e.payloadBytes;
    if (e.payloadBytes > 0) s.uncompressedBytes += brick;
  }
  for (const auto& level : s.levels) {
    s.total += level.total;
    s.empty += level.empty;
    s.constant += level.constant;
    s.data += level.data;
    s.payloadBytes += level.payloadBytes;
  }
  s.allBricksBytes = s.total * brick;
  s.rawBytes = store.info().volume.sampleCount() * bytesPerSample(store.info().volume.type);
  s.fileBytes = store.fileBytes();
  return s;
}

}  // namespace ropecast
