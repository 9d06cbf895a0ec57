#include "store/text_samples.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.h"
#include "core/header_text.h"

namespace ropecast {
namespace {

constexpr size_t kBufferBytes = size_t(1) << 20;
constexpr size_t kMaxNumberChars = 256;  // longer words are not numbers VTK writes

// `number` as a T; false when it is not one (a fraction or an out-of-range value for an integer T).
template <typename T>
bool parseSample(std::string_view number, double scale, T& out) {
  const char* first = number.data();
  const char* last = first + number.size();
  if (first < last && *first == '+') ++first;  // from_chars takes a leading '-' only
  if constexpr (std::is_integral_v<T>) {
    if (scale == 1.0) {
      const auto [end, error] = std::from_chars(first, last, out);  // fails when T cannot hold it
      return error == std::errc() && end == last;
    }
  }
  double value = 0.0;
  const auto [end, error] = std::from_chars(first, last, value);
  if (error != std::errc() || end != last) return false;
  value *= scale;
  if constexpr (std::is_integral_v<T>) {
    value = std::nearbyint(value);
    if (!(value >= double(std::numeric_limits<T>::min()) && value <= double(std::numeric_limits<T>::max())))
      return false;
  }
  out = T(value);
  return true;
}

class TextSampleSource final : public VolumeSource {
 public:
  TextSampleSource(VolumeInfo info, std::unique_ptr<PosixFile> file, TextSamples text)
      : info_(std::move(info)), file_(std::move(file)), text_(std::move(text)), buffer_(kBufferBytes) {
    if (info_.type == SampleType::UInt8) {
      info_.valueMin = 0.0;
      info_.valueMax = 255.0;
    }
    restart();
  }

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    const uint64_t sliceSamples = uint64_t(info_.dims.x) * info_.dims.y;
    const uint64_t first = z0 * sliceSamples;
    if (first < nextSample_) restart();
    while (nextSample_ < first) {
      nextNumber();
      ++nextSample_;
    }
    const size_t size = bytesPerSample(info_.type);
    for (std::byte* at = out.data(); at < out.data() + out.size(); at += size) {
      store(nextNumber(), at);
      ++nextSample_;
    }
  }

  void restart() {
    fileOffset_ = text_.start;
    begin_ = end_ = 0;
    atEnd_ = false;
    nextSample_ = 0;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(text_.fileKind + " " + file_->path() + ": " + what);
  }

  // Refills the buffer after its unread part, which moves to its front; false at the end of the file.
  bool refill() {
    if (atEnd_) return false;
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
    const size_t got =
        file_->readSomeAt(fileOffset_, std::as_writable_bytes(std::span(buffer_)).subspan(end_));
    fileOffset_ += got;
    end_ += got;
    atEnd_ = got == 0;
    return got > 0;
  }

  // The next number's characters (valid until the next call); fails at the end of the file.
  std::string_view nextNumber() {
    for (;;) {
      while (begin_ < end_ && isBlank(buffer_[begin_])) ++begin_;
      if (begin_ < end_ || !refill()) break;
    }
    if (begin_ == end_)
      fail("ends after " + std::to_string(nextSample_) + " of its " + std::to_string(info_.sampleCount()) +
           " samples");
    size_t stop = begin_;
    for (;;) {
      while (stop < end_ && !isBlank(buffer_[stop])) ++stop;
      if (stop < end_ || stop - begin_ > kMaxNumberChars) break;
      const size_t read = stop - begin_;
      const bool more = refill();  // moves the number's start to the buffer's front
      stop = begin_ + read;
      if (!more) break;  // the file ends with this number
    }
    if (stop - begin_ > kMaxNumberChars)
      fail("sample " + std::to_string(nextSample_) + " is a word of more than " +
           std::to_string(kMaxNumberChars) + " characters, not a number");
    const std::string_view number(buffer_.data() + begin_, stop - begin_);
    begin_ = stop;
    return number;
  }

  void store(std::string_view number, std::byte* out) const {
    bool ok = false;
    forSampleType(info_.type, [&](auto typed) {
      decltype(typed) value{};
      ok = parseSample(number, text_.scale, value);
      std::memcpy(out, &value, sizeof value);
    });
    if (!ok)
      fail("sample " + std::to_string(nextSample_) + " is " + quotedExcerpt(number) + ", not a " +
           std::string(sampleTypeName(info_.type)) +
           (text_.scale == 1.0 ? "" : " once multiplied by " + formatNumber(text_.scale)));
  }

  VolumeInfo info_;
  std::unique_ptr<PosixFile> file_;
  TextSamples text_;
  std::vector<char> buffer_;
  size_t begin_ = 0, end_ = 0;  // the unread part of the buffer
  uint64_t fileOffset_ = 0;     // where the buffer's next bytes come from
  bool atEnd_ = false;
  uint64_t nextSample_ = 0;  // the index of the sample the next number is
};

}  // namespace

std::unique_ptr<VolumeSource> openTextSampleSource(VolumeInfo info, std::unique_ptr<PosixFile> file,
                                                   TextSamples text) {
  return std::make_unique<TextSampleSource>(std::move(info), std::move(file), std::move(text));
}

}  // namespace ropecast
