#include "store/picked_volume.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "core/error.h"

namespace ropecast {
namespace {

// The most one slice of every component may take: more is refused when the source opens.
constexpr uint64_t kMaxSliceOfComponents = uint64_t(4) << 30;

class ComponentSource final : public VolumeSource {
 public:
  ComponentSource(std::unique_ptr<VolumeSource> interleaved, uint32_t components, uint32_t component,
                  VolumeInfo info, uint64_t maxStoredBytes)
      : interleaved_(std::move(interleaved)),
        components_(components),
        component_(component),
        maxStoredBytes_(maxStoredBytes),
        info_(std::move(info)) {}

  const VolumeInfo& info() const override { return info_; }

 protected:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    const size_t width = bytesPerSample(info_.type), sliceBytes = info_.sliceBytes();
    // Slices of every component, as many at a time as maxStoredBytes_ holds (one at least).
    const uint32_t perRead =
        uint32_t(std::clamp<uint64_t>(maxStoredBytes_ / (uint64_t(sliceBytes) * components_), 1, count));
    for (uint32_t done = 0; done < count; done += perRead) {
      const uint32_t slices = std::min(perRead, count - done);
      stored_.resize(size_t(slices) * sliceBytes * components_);
      interleaved_->readSlab(z0 + done, slices, stored_);
      const std::byte* from = stored_.data() + size_t(component_) * width;
      std::byte* to = out.data() + size_t(done) * sliceBytes;
      const size_t step = size_t(components_) * width;
      for (size_t i = 0, n = size_t(slices) * sliceBytes / width; i < n; ++i, from += step)
        std::memcpy(to + i * width, from, width);
    }
  }

 private:
  std::unique_ptr<VolumeSource> interleaved_;
  uint32_t components_, component_;
  uint64_t maxStoredBytes_;
  VolumeInfo info_;
  std::vector<std::byte> stored_;  // slices of every component
};

// "120 time points", "1 channel".
std::string countOf(uint64_t count, const std::string& singular) {
  return std::to_string(count) + " " + singular + (count == 1 ? "" : "s");
}

uint32_t pickIndex(const std::optional<uint32_t>& given, uint64_t count, const std::string& option,
                   const std::string& singular, const std::string& file) {
  if (!given) return 0;
  if (*given >= count)
    throw UsageError(option + " " + std::to_string(*given) + ": " + file + " holds " +
                     countOf(count, singular) +
                     (count == 1 ? " (" + option + " 0 alone)"
                                 : " (" + option + " 0 to " + std::to_string(count - 1) + ")"));
  return *given;
}

class StackedSource final : public VolumeSource {
 public:
  StackedSource(std::unique_ptr<VolumeSource> stacked, uint32_t index, VolumeInfo info)
      : stacked_(std::move(stacked)), firstSlice_(uint64_t(index) * info.dims.z), info_(std::move(info)) {}

  const VolumeInfo& info() const override { return info_; }

 protected:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    stacked_->readSlab(uint32_t(firstSlice_ + z0), count, out);
  }

 private:
  std::unique_ptr<VolumeSource> stacked_;
  uint64_t firstSlice_;
  VolumeInfo info_;
};

}  // namespace

// A note lists the channels' names up to this many.
constexpr size_t kListedChannelNames = 16;

// Whether the file names every channel (a name for each, none empty): only then are names said.
bool namesEveryChannel(const VolumeCounts& counts) {
  return counts.channelNames.size() == counts.channels &&
         std::ranges::none_of(counts.channelNames, &std::string::empty);
}

PickedVolume pickVolume(const SourceOptions& options, VolumeCounts counts, const std::string& file) {
  PickedVolume picked;
  picked.timePoint = pickIndex(options.timePoint, counts.timePoints, "--time", "time point", file);
  const std::string& channel = counts.channelWord;
  picked.channel = pickIndex(options.channel, counts.channels, "--channel", channel, file);
  std::string described, held, unpicked;
  const auto add = [](std::string& list, const std::string& item, const char* separator = ", ") {
    list += (list.empty() ? "" : separator) + item;
  };
  if (counts.timePoints > 1) {
    add(described,
        "time point " + std::to_string(picked.timePoint) + " of " + std::to_string(counts.timePoints));
    add(held, countOf(counts.timePoints, "time point"));
    if (!options.timePoint) add(unpicked, "--time T (0 to " + std::to_string(counts.timePoints - 1) + ")");
  }
  if (counts.channels > 1) {
    const std::vector<std::string>& names = counts.channelNames;
    const bool named = namesEveryChannel(counts);
    add(described, channel + " " + std::to_string(picked.channel) + " of " + std::to_string(counts.channels) +
                       (named ? ": '" + names[picked.channel] + "'" : ""));
    std::string listed;  // the names, where they are few enough to read
    for (size_t i = 0; named && names.size() <= kListedChannelNames && i < names.size(); ++i)
      listed += (i ? ", '" : " ('") + names[i] + "'" + (i + 1 == names.size() ? ")" : "");
    add(held, countOf(counts.channels, channel) + listed, " and ");
    if (!options.channel)
      add(unpicked, "--channel C (0 to " + std::to_string(counts.channels - 1) + ")", " or ");
  }
  picked.counts = counts;
  if (!described.empty()) picked.described = " (" + described + ")";
  if (!unpicked.empty())
    picked.note = file + " holds " + held + ": " + described + " is read; " + unpicked + " picks another";
  return picked;
}

void describePicked(VolumeInfo& info, const PickedVolume& picked) {
  info.timePoints = picked.counts.timePoints;
  info.channels = picked.counts.channels;
  info.timePoint = picked.timePoint;
  info.channel = picked.channel;
  if (namesEveryChannel(picked.counts)) info.channelNames = picked.counts.channelNames;
  info.description += picked.described;
  if (!picked.note.empty()) info.notes.push_back(picked.note);
}

std::unique_ptr<VolumeSource> pickComponent(std::unique_ptr<VolumeSource> interleaved, uint32_t components,
                                            uint32_t component, VolumeInfo info, uint64_t maxStoredBytes) {
  if (uint64_t(info.sliceBytes()) * components > kMaxSliceOfComponents)
    throw Error(info.description + ": a slice of its " + std::to_string(components) +
                " components is more than " + std::to_string(kMaxSliceOfComponents >> 30) +
                " GiB, too much to read for one of them");
  return std::make_unique<ComponentSource>(std::move(interleaved), components, component, std::move(info),
                                           maxStoredBytes);
}

std::unique_ptr<VolumeSource> pickStacked(std::unique_ptr<VolumeSource> stacked, uint32_t index,
                                          VolumeInfo info) {
  return std::make_unique<StackedSource>(std::move(stacked), index, std::move(info));
}

}  // namespace ropecast
