// Damaged, truncated and unwritable stores: one clear Error naming the file (and the node for a brick), and
// no file left behind by a failed conversion.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <functional>
#include <string>

#include "core/error.h"
#include "store/converter.h"
#include "store/store.h"
#include "store/store_writer.h"
#include "store/verify.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::TempDir;
using testing::writeFile;

std::vector<char> readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
std::string openError(const std::filesystem::path& p) {
  try {
    Store::open(p);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Sets every digit of the `index`-th number of the array `key` in `metadata` to `digit`.
void setDigits(std::string& metadata, const std::string& key, int index, char digit) {
  const size_t bracket = metadata.find('[', metadata.find("\"" + key + "\""));
  ASSERT_NE(bracket, std::string::npos) << metadata;
  size_t at = bracket + 1;
  for (int i = 0; i < index; ++i) at = metadata.find(',', at) + 1;
  for (size_t i = at; i < metadata.size() && metadata[i] != ',' && metadata[i] != ']'; ++i)
    if (std::isdigit(static_cast<unsigned char>(metadata[i]))) metadata[i] = digit;
}

class StoreErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    const glm::u32vec3 dims{30, 21, 17};
    samples = testing::toType<uint16_t>(testing::ballField(dims, 6), 0, 3000);
    source = std::make_unique<ArraySource>(
        ArraySource::fromSamples<uint16_t>(testing::volumeInfo(dims, SampleType::UInt16), samples));
    options.brickSize = 8;
    convertVolume(*source, dir / "good.store", options);
    bytes = readFile(dir / "good.store");
  }
  StoreHeader header() const {
    StoreHeader h;
    std::memcpy(&h, bytes.data(), sizeof h);
    return h;
  }
  // The good store with its metadata edited in place (`edit` keeps its length, so no offset moves) and the
  // checksums made to match, written as `name`: what a hand-edited or foreign writer could produce. Returns
  // the error of opening it ("" if it opens).
  std::string openWithEditedMetadata(const char* name, const std::function<void(std::string&)>& edit) {
    StoreHeader h = header();
    auto edited = bytes;
    std::string metadata(edited.data() + h.metadataOffset, h.metadataBytes);
    edit(metadata);
    EXPECT_EQ(metadata.size(), h.metadataBytes);
    std::memcpy(edited.data() + h.metadataOffset, metadata.data(), h.metadataBytes);
    h.metadataCrc =
        storeCrc32(std::as_bytes(std::span(edited.data() + h.metadataOffset, size_t(h.metadataBytes))));
    std::memcpy(edited.data(), &h, sizeof h);
    h.headerCrc = storeCrc32(std::as_bytes(std::span(edited.data(), offsetof(StoreHeader, headerCrc))));
    std::memcpy(edited.data(), &h, sizeof h);
    writeFile(dir / name, edited);
    return openError(dir / name);
  }

  // The good store's payloads and nodes with `metadata`, written by StoreWriter as `name`: metadata that is
  // intact (checksums match) but says something else.
  void writeWithMetadata(const char* name, const Store& good, const StoreMetadata& metadata) {
    std::vector<StoreNodeEntry> entries(good.entries().begin(), good.entries().end());
    StoreWriter writer(dir / name);
    for (StoreNodeEntry& e : entries)
      if (e.payloadBytes > 0)
        e.payloadOffset = writer.appendPayload(
            std::as_bytes(std::span(bytes.data() + e.payloadOffset, size_t(e.payloadBytes))));
    writer.finish(metadata, entries);
  }

  TempDir dir;
  std::vector<uint16_t> samples;
  std::unique_ptr<ArraySource> source;
  ConvertOptions options;
  std::vector<char> bytes;
};

TEST_F(StoreErrors, DamagedHeaderNamesTheFile) {
  for (size_t offset : {0ul, 9ul, 20ul, 44ul, 61ul}) {
    auto damaged = bytes;
    damaged[offset] ^= 0x5A;
    const auto path = dir / ("header" + std::to_string(offset) + ".store");
    writeFile(path, damaged);
    const std::string message = openError(path);
    EXPECT_NE(message.find(path.string()), std::string::npos) << "offset " << offset << ": " << message;
  }
  auto notAStore = bytes;
  std::memcpy(notAStore.data(), "NOTSTORE", 8);
  writeFile(dir / "magic.store", notAStore);
  EXPECT_NE(openError(dir / "magic.store").find("bad magic"), std::string::npos);
}

TEST_F(StoreErrors, DamagedMetadataAndNodeTableAreErrors) {
  const StoreHeader h = header();
  auto metadata = bytes;
  metadata[h.metadataOffset + 3] ^= 0x01;
  writeFile(dir / "meta.store", metadata);
  EXPECT_NE(openError(dir / "meta.store").find("metadata"), std::string::npos);
  auto table = bytes;
  table[h.nodeTableOffset + 17] ^= 0x10;
  writeFile(dir / "table.store", table);
  EXPECT_NE(openError(dir / "table.store").find("node table"), std::string::npos);
}

// Metadata that is intact (checksums match) but gives the volume no box: a zero spacing. Rays could not
// enter it; opening it is the error.
TEST_F(StoreErrors, MetadataSpacingMustBePositive) {
  const std::string message = openWithEditedMetadata(
      "spacing.store", [](std::string& m) { setDigits(m, "spacing", 0, '0'); });  // 0.5 -> 0.0
  EXPECT_NE(message.find("spacing.store': metadata spacing 0,0.75,1.25 must be"), std::string::npos)
      << message;
}

// The value of `key` in the pretty-printed `metadata` replaced with `value` (no shorter), the length kept by
// taking indentation away after it.
void replaceValue(std::string& metadata, const std::string& key, const std::string& value) {
  const size_t at = metadata.find("\"" + key + "\": ");
  ASSERT_NE(at, std::string::npos) << metadata;
  const size_t begin = at + key.size() + 4;
  const size_t end = metadata.find_first_of(",\n", begin);
  const size_t length = metadata.size();
  metadata.replace(begin, end - begin, value);
  for (size_t i = begin; metadata.size() > length;) {
    i = metadata.find("\n ", i);
    ASSERT_NE(i, std::string::npos) << "not enough indentation to keep the length";
    metadata.erase(i + 1, 1);
  }
}

// Integer fields read as uint32 take exact integers in [0, 2^32) only: a reader that converted would take a
// fraction or a wrapped 2^32 + 8 for another value (8), and the damage would pass.
TEST_F(StoreErrors, MetadataIntegersMustBeExactUint32) {
  EXPECT_TRUE(openWithEditedMetadata("same.store", [](std::string& m) {
                replaceValue(m, "brickSize", "8");
              }).empty());
  for (const char* value : {"8.5", "8.0", "4294967304", "-8"}) {
    const std::string message =
        openWithEditedMetadata("int.store", [&](std::string& m) { replaceValue(m, "brickSize", value); });
    EXPECT_NE(message.find("int.store': damaged metadata: brickSize: expected an integer in [0, 2^32), got"),
              std::string::npos)
        << value << ": " << message;
  }
  const std::string message =
      openWithEditedMetadata("dims.store", [](std::string& m) { replaceValue(m, "levels", "4294967297"); });
  EXPECT_NE(message.find("levels: expected an integer in [0, 2^32)"), std::string::npos) << message;
}

// A field of the wrong kind or a missing one is named: a key in quotes, not a JSON library's message.
TEST_F(StoreErrors, MetadataFieldsOfTheWrongKindAreNamed) {
  std::string message =
      openWithEditedMetadata("kind.store", [](std::string& m) { replaceValue(m, "discardBelow", "\"xy\""); });
  EXPECT_NE(message.find("kind.store': damaged metadata: \"discardBelow\": expected a number, got \"xy\""),
            std::string::npos)
      << message;
  message = openWithEditedMetadata("missing.store", [](std::string& m) {
    const size_t at = m.find("\"creationTool\"");
    ASSERT_NE(at, std::string::npos);
    m[at + 1] = 'k';  // "kreationTool": an unknown key, and creationTool missing
  });
  EXPECT_NE(message.find("missing.store': damaged metadata: missing \"creationTool\""), std::string::npos)
      << message;
}

// The axes are a rotation: unit vectors at right angles that do not mirror (the converter turns a mirroring
// volume's x around). A store written before axes were kept has none: the identity.
TEST_F(StoreErrors, MetadataAxesMustBeARotation) {
  const std::unique_ptr<Store> good = Store::open(dir / "good.store");
  EXPECT_EQ(good->info().volume.axes, AxisDirections(1.0));
  StoreMetadata metadata = good->metadata();
  metadata.volume.axes = AxisDirections(glm::dvec3(0, 0, 1), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0));
  writeWithMetadata("turned.store", *good, metadata);
  EXPECT_EQ(Store::open(dir / "turned.store")->info().volume.axes, metadata.volume.axes);
  const std::pair<AxisDirections, const char*> bad[] = {
      {AxisDirections(glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)), "a rotation"},
      {AxisDirections(glm::dvec3(1, 0, 0), glm::dvec3(0.5, 1, 0), glm::dvec3(0, 0, 1)), "unit vectors"},
      {AxisDirections(glm::dvec3(1, 0, 0), glm::dvec3(0.6, 0.8, 0), glm::dvec3(0, 0, 1)), "a rotation"},
      {AxisDirections(2.0), "unit vectors"}};
  for (const auto& [axes, expected] : bad) {
    metadata.volume.axes = axes;
    writeWithMetadata("axes.store", *good, metadata);
    const std::string message = openError(dir / "axes.store");
    EXPECT_NE(message.find("axes.store': damaged metadata: axes: expected " + std::string(expected)),
              std::string::npos)
        << message;
  }
  EXPECT_TRUE(openWithEditedMetadata("old.store", [](std::string& m) {
                const size_t at = m.find("\"axes\"");
                ASSERT_NE(at, std::string::npos);
                m[at + 1] = 'b';  // "bxes": an unknown key, and no axes
              }).empty());
  EXPECT_EQ(Store::open(dir / "old.store")->info().volume.axes, AxisDirections(1.0));
}

// A value range whose max lies below its min (the default isovalue and transfer function come from it),
// written by StoreWriter with the good store's payloads: only the reader's check can catch it.
TEST_F(StoreErrors, MetadataValueRangeMustBeOrdered) {
  const std::unique_ptr<Store> good = Store::open(dir / "good.store");
  StoreMetadata metadata = good->metadata();
  metadata.volume.valueMin = 3000.0;
  metadata.volume.valueMax = 0.0;
  writeWithMetadata("range.store", *good, metadata);
  const std::string message = openError(dir / "range.store");
  EXPECT_NE(
      message.find("range.store': damaged metadata: valueRange: expected finite [min, max] with min <= max"),
      std::string::npos)
      << message;
}

TEST_F(StoreErrors, TruncatedFileIsAnError) {
  for (size_t size : {0ul, 10ul, 64ul, bytes.size() / 2, bytes.size() - 1}) {
    const auto path = dir / ("cut" + std::to_string(size) + ".store");
    writeFile(path, std::vector<char>(bytes.begin(), bytes.begin() + long(size)));
    const std::string message = openError(path);
    EXPECT_NE(message.find(path.string()), std::string::npos) << "size " << size << ": " << message;
  }
  EXPECT_NE(openError(dir / "missing.store").find("missing.store"), std::string::npos);
}

TEST_F(StoreErrors, DamagedBrickNamesTheNode) {
  const auto store = Store::open(dir / "good.store");
  const OctreeLayout& layout = store->info().layout;
  uint64_t index = 0;
  while (store->entries()[index].payloadBytes == 0) ++index;
  const StoreNodeEntry e = store->entries()[index];
  auto damaged = bytes;
  damaged[e.payloadOffset + e.payloadBytes / 2] ^= 0x22;
  writeFile(dir / "brick.store", damaged);
  const auto bad = Store::open(dir / "brick.store");  // the header and table are fine
  std::vector<std::byte> out(bad->brickBytes());
  const NodeKey key = layout.nodeAt(index);
  try {
    bad->readBrick(key, out);
    FAIL() << "a damaged brick was read without error";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(Store::describeNode(key)), std::string::npos) << message;
    EXPECT_NE(message.find("brick.store"), std::string::npos) << message;
    EXPECT_NE(message.find("checksum"), std::string::npos) << message;
  }
  // Other nodes still read.
  const NodeKey other = layout.nodeAt(index == 0 ? 1 : 0);
  EXPECT_NO_THROW(bad->readBrick(other, out));
}

TEST_F(StoreErrors, UnwritableOutputPathIsAnErrorNamingIt) {
  const auto blocker = dir / "a-file";
  writeFile(blocker, {'x'});
  for (const auto& out : {blocker / "v.store", dir / "no-such-dir" / "v.store"}) {
    try {
      convertVolume(*source, out, options);
      FAIL() << "converted into " << out;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(out.string()), std::string::npos) << error.what();
    }
  }
}

// A source that fails part-way, like a truncated raw file.
class FailingSource final : public VolumeSource {
 public:
  FailingSource(VolumeSource& inner, uint32_t failAtSlice) : inner_(inner), failAt_(failAtSlice) {}
  const VolumeInfo& info() const override { return inner_.info(); }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    if (z0 + count > failAt_)
      throw Error("FailingSource: slice " + std::to_string(failAt_) + " is unreadable");
    inner_.readSlab(z0, count, out);
  }

  VolumeSource& inner_;
  uint32_t failAt_;
};

TEST_F(StoreErrors, FailedConversionLeavesNoFile) {
  TempDir out;
  FailingSource failing(*source, 12);
  EXPECT_THROW(convertVolume(failing, out / "v.store", options), Error);
  EXPECT_EQ(out.fileCount(), 0u);
  // A failure must not touch an existing output either.
  writeFile(out / "v.store", bytes);
  EXPECT_THROW(convertVolume(failing, out / "v.store", options), Error);
  EXPECT_EQ(out.fileCount(), 1u);
  EXPECT_EQ(readFile(out / "v.store"), bytes);
}

TEST_F(StoreErrors, BadOptionsAreErrors) {
  TempDir out;
  ConvertOptions bad = options;
  bad.brickSize = 12;
  EXPECT_THROW(convertVolume(*source, out / "v.store", bad), Error);
  bad = options;
  bad.zstdLevel = 1000;
  EXPECT_THROW(convertVolume(*source, out / "v.store", bad), Error);
  // A threshold the metadata cannot record (JSON has no inf or NaN); inf also emptied every node.
  for (double threshold : {HUGE_VAL, -HUGE_VAL, std::nan("")}) {
    bad = options;
    bad.discardBelow = threshold;
    EXPECT_THROW(convertVolume(*source, out / "v.store", bad), Error) << threshold;
  }
  EXPECT_EQ(out.fileCount(), 0u);
}

TEST_F(StoreErrors, SourceWithoutAPositiveSpacingIsAnError) {
  TempDir out;
  for (glm::dvec3 spacing : {glm::dvec3(0, 1, 1), glm::dvec3(1, -2, 1), glm::dvec3(1, 1, HUGE_VAL)}) {
    VolumeInfo info = source->info();
    info.spacing = spacing;
    ArraySource flat = ArraySource::fromSamples<uint16_t>(info, samples);
    try {
      convertVolume(flat, out / "v.store", options);
      ADD_FAILURE() << "spacing " << formatSpacing(spacing) << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("has spacing " + formatSpacing(spacing)), std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(out.fileCount(), 0u);
}

// A value range that is ordered and finite but not the data's: the reader cannot tell, verify does.
TEST_F(StoreErrors, VerifyFindsAValueRangeThatIsNotTheData) {
  const std::unique_ptr<Store> good = Store::open(dir / "good.store");
  EXPECT_TRUE(verifyStore(*good).ok());
  StoreMetadata metadata = good->metadata();
  metadata.volume.valueMax = *metadata.volume.valueMax + 1.0;
  writeWithMetadata("wide.store", *good, metadata);
  const VerifyReport report = verifyStore(*Store::open(dir / "wide.store"));
  ASSERT_EQ(report.problemCount, 1u);
  EXPECT_NE(report.problems[0].find("metadata valueRange"), std::string::npos) << report.problems[0];
}

}  // namespace
}  // namespace ropecast
