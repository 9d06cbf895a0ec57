#include "store/source_vti.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "store/chunk_codecs.h"
#include "store/picked_volume.h"
#include "store/source_raw.h"

namespace ropecast {
namespace {

// The bytes a run of a file's text decodes to: the text itself (raw), or base64 decoded by whole quads, so
// any range of the decoded bytes is read without decoding what comes before it.
class DecodedRun {
 public:
  DecodedRun(const PosixFile& file, uint64_t start, bool base64)
      : file_(file), start_(start), base64_(base64) {}

  // The file offset just past `decodedBytes` decoded bytes: where a run that follows starts (base64 runs
  // end with their padding).
  uint64_t endAfter(uint64_t decodedBytes) const {
    return start_ + (base64_ ? (decodedBytes + 2) / 3 * 4 : decodedBytes);
  }

  void read(uint64_t offset, std::span<std::byte> out) const {
    if (!base64_) return file_.readAt(start_ + offset, out);
    const uint64_t firstQuad = offset / 3, endQuad = (offset + out.size() + 2) / 3;
    std::vector<std::byte> text(size_t(endQuad - firstQuad) * 4);
    file_.readAt(start_ + firstQuad * 4, text);
    std::vector<std::byte> decoded(text.size() / 4 * 3);
    for (size_t quad = 0; quad < text.size() / 4; ++quad) {
      uint32_t bits = 0;
      for (size_t i = 0; i < 4; ++i) {
        const char c = char(text[quad * 4 + i]);
        const int value = c == '=' ? 0 : sextet(c);
        if (value < 0)
          throw Error("VTK image data file " + file_.path() + ": not base64 data at byte " +
                      std::to_string(start_ + (firstQuad + quad) * 4 + i) + " (a character of code " +
                      std::to_string(int(static_cast<unsigned char>(c))) + ")");
        bits = bits << 6 | uint32_t(value);
      }
      for (size_t i = 0; i < 3; ++i) decoded[quad * 3 + i] = std::byte(bits >> (16 - 8 * i));
    }
    std::memcpy(out.data(), decoded.data() + (offset - firstQuad * 3), out.size());
  }

 private:
  static int sextet(char c) {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  }

  const PosixFile& file_;
  uint64_t start_;
  bool base64_;
};

uint64_t wordAt(const std::vector<std::byte>& bytes, size_t index, size_t width, bool bigEndian) {
  uint64_t value = 0;
  for (size_t i = 0; i < width; ++i) {
    const size_t at = index * width + (bigEndian ? i : width - 1 - i);
    value = value << 8 | uint64_t(bytes[at]);
  }
  return value;
}

const char* compressorName(VtiCompressor compressor) {
  switch (compressor) {
    case VtiCompressor::ZLib:
      return "zlib";
    case VtiCompressor::LZ4:
      return "LZ4";
    case VtiCompressor::LZMA:
      return "LZMA";
    case VtiCompressor::None:
      break;
  }
  return "uncompressed";
}

// Decompresses one block of a compressed array into exactly out.size() bytes, as VTK's compressors store a
// block: a zlib stream (vtkZLibDataCompressor), an LZ4 block (vtkLZ4DataCompressor), an xz stream
// (vtkLZMADataCompressor). Returns "" or what went wrong.
std::string decompressBlock(VtiCompressor compressor, std::span<const std::byte> in,
                            std::span<std::byte> out) {
  switch (compressor) {
    case VtiCompressor::ZLib: {
      uLongf produced = uLongf(out.size());
      const int status = uncompress(reinterpret_cast<Bytef*>(out.data()), &produced,
                                    reinterpret_cast<const Bytef*>(in.data()), uLong(in.size()));
      if (status != Z_OK) return zError(status);
      return produced == out.size()
                 ? ""
                 : std::to_string(produced) + " bytes instead of " + std::to_string(out.size());
    }
    case VtiCompressor::LZ4:
      return lz4BlockExactly(in, out);
    case VtiCompressor::LZMA:
      return lzmaExactly(in, out);
    case VtiCompressor::None:
      break;
  }
  return "not compressed";
}

class VtiSource final : public VolumeSource {
 public:
  VtiSource(const std::string& path, const SourceOptions& options)
      : header_(readVtiHeaderFile(path)), file_(path), data_(file_, header_.dataStart, header_.base64) {
    info_.dims = header_.sizes;
    info_.dims.x *= header_.components;  // components interleaved: rows of every component (openVtiSource)
    info_.type = header_.type;
    info_.spacing = options.spacing.value_or(header_.spacing);
    if (info_.type == SampleType::UInt8) {
      info_.valueMin = 0.0;
      info_.valueMax = 255.0;
    }
    info_.description = "vti:" + path + " (" + header_.arrayName + ")";
    info_.axes = header_.axes;
    info_.origin = header_.origin;
    if (header_.directionNotApplied) info_.notes.push_back(unappliedTransformNote(path, "its Direction"));
    if (header_.compressor != VtiCompressor::None)
      readCompressionHeader();
    else
      readByteCount();
  }

  const VolumeInfo& info() const override { return info_; }
  const VtiHeader& header() const { return header_; }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("VTK image data file " + file_.path() + ": " + what);
  }

  std::vector<std::byte> words(const DecodedRun& run, uint64_t offset, size_t count) const {
    std::vector<std::byte> bytes(count * header_.headerWordBytes);
    run.read(offset, bytes);
    return bytes;
  }

  // Uncompressed: one word, the data's byte count, then the samples (in one run, base64 or not).
  void readByteCount() {
    checkWithinFile(data_, header_.headerWordBytes + header_.dataBytes());
    const uint64_t count = wordAt(words(data_, 0, 1), 0, header_.headerWordBytes, header_.bigEndian);
    if (count != header_.dataBytes())
      fail("the array '" + header_.arrayName + "' says it holds " + std::to_string(count) + " bytes, but " +
           formatDims(header_.sizes) + " " + std::string(sampleTypeName(header_.type)) + " samples are " +
           std::to_string(header_.dataBytes()));
  }

  // Compressed: the block count, the uncompressed size of a block and of the last one, each block's
  // compressed size; then the blocks, in a run of their own.
  void readCompressionHeader() {
    const size_t width = header_.headerWordBytes;
    checkWithinFile(data_, 3 * width);
    const auto head = words(data_, 0, 3);
    const uint64_t blocks = wordAt(head, 0, width, header_.bigEndian);
    blockBytes_ = wordAt(head, 1, width, header_.bigEndian);
    const uint64_t last = wordAt(head, 2, width, header_.bigEndian);
    const uint64_t lastBytes = last == 0 ? blockBytes_ : last;
    if (blocks == 0 || blockBytes_ == 0 || blocks > header_.dataBytes() / blockBytes_ + 1 ||
        lastBytes > blockBytes_ || (blocks - 1) * blockBytes_ + lastBytes != header_.dataBytes())
      fail("the compression header of the array '" + header_.arrayName + "' (" + std::to_string(blocks) +
           " blocks of " + std::to_string(blockBytes_) + " bytes, the last " + std::to_string(lastBytes) +
           ") does not hold the " + std::to_string(header_.dataBytes()) + " bytes of " +
           formatDims(header_.sizes) + " " + std::string(sampleTypeName(header_.type)) + " samples");
    if (blocks > file_.sizeBytes() / width)  // each block's size is a word of the file
      fail("the compression header of the array '" + header_.arrayName + "' counts " +
           std::to_string(blocks) + " blocks, more than the file holds");
    checkWithinFile(data_, (3 + blocks) * width);
    const auto sizes = words(data_, 3 * width, size_t(blocks));
    uint64_t offset = 0;
    for (uint64_t block = 0; block < blocks; ++block) {
      blockOffsets_.push_back(offset);
      offset += wordAt(sizes, size_t(block), width, header_.bigEndian);
      if (offset > file_.sizeBytes()) fail("its compressed blocks end past the end of the file (truncated)");
    }
    blockOffsets_.push_back(offset);
    lastBlockBytes_ = lastBytes;
    blocks_ = std::make_unique<DecodedRun>(file_, data_.endAfter((3 + blocks) * width), header_.base64);
    checkWithinFile(*blocks_, offset);
  }

  void checkWithinFile(const DecodedRun& run, uint64_t decodedBytes) const {
    if (run.endAfter(decodedBytes) > file_.sizeBytes())
      fail("its data ends past the end of the file at byte " + std::to_string(file_.sizeBytes()) +
           " (truncated)");
  }

  const std::vector<std::byte>& block(uint64_t index) {
    if (cachedBlock_ == index) return blockData_;
    const uint64_t compressedBytes = blockOffsets_[index + 1] - blockOffsets_[index];
    std::vector<std::byte> compressed(compressedBytes);
    blocks_->read(blockOffsets_[index], compressed);
    const uint64_t expected = index + 2 == blockOffsets_.size() ? lastBlockBytes_ : blockBytes_;
    blockData_.resize(expected);
    if (const std::string problem = decompressBlock(header_.compressor, compressed, blockData_);
        !problem.empty())
      fail(std::string(compressorName(header_.compressor)) + " block " + std::to_string(index) +
           " of the array '" + header_.arrayName + "' is damaged (" + problem + ")");
    cachedBlock_ = index;
    return blockData_;
  }

  void readSlices(uint32_t z0, uint32_t, std::span<std::byte> out) override {
    const uint64_t offset = uint64_t(z0) * info_.sliceBytes();
    if (header_.compressor == VtiCompressor::None) {
      data_.read(header_.headerWordBytes + offset, out);
    } else {
      for (uint64_t done = 0; done < out.size();) {
        const uint64_t at = offset + done, index = at / blockBytes_, within = at % blockBytes_;
        const std::vector<std::byte>& bytes = block(index);
        const uint64_t n = std::min<uint64_t>(bytes.size() - within, out.size() - done);
        std::memcpy(out.data() + done, bytes.data() + within, size_t(n));
        done += n;
      }
    }
    samplesToNative(out, info_.type, header_.bigEndian);
  }

  VtiHeader header_;
  PosixFile file_;
  DecodedRun data_;  // the array's data: its header words first
  VolumeInfo info_;
  // Compressed arrays: the blocks' run, their offsets in it (and its end), their uncompressed size.
  std::unique_ptr<DecodedRun> blocks_;
  std::vector<uint64_t> blockOffsets_;
  uint64_t blockBytes_ = 0, lastBlockBytes_ = 0;
  uint64_t cachedBlock_ = UINT64_MAX;
  std::vector<std::byte> blockData_;
};

}  // namespace

VtiHeader readVtiHeaderFile(const std::string& path) {
  const PosixFile file(path);
  return parseVtiHeader(file.readStart(kMaxVtiHeaderBytes), path);
}

std::unique_ptr<VolumeSource> openVtiSource(const std::string& path, const SourceOptions& options) {
  auto source = std::make_unique<VtiSource>(path, options);
  const VtiHeader& header = source->header();
  const PickedVolume picked =
      pickVolume(options, {1, header.components, "component"}, "VTK image data file " + path);
  if (header.components == 1) return source;
  if (uint64_t(header.sizes.x) * header.components > UINT32_MAX)
    throw Error("VTK image data file " + path + ": rows of " + std::to_string(header.sizes.x) +
                " points of " + std::to_string(header.components) + " components each are too long to read");
  VolumeInfo info = source->info();
  info.dims.x = header.sizes.x;
  describePicked(info, picked);
  const uint32_t components = header.components;
  return pickComponent(std::move(source), components, picked.channel, std::move(info));
}

}  // namespace ropecast
