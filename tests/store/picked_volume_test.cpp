// Tests of store/picked_volume.h on its own: which volume the options pick and what is said of it, and the
// sources over interleaved components and stacked volumes, read whole, slab by slab and a few slices at a
// time.
#include "store/picked_volume.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "store/array_source.h"

namespace ropecast {
namespace {

std::string pickError(const SourceOptions& options, VolumeCounts counts) {
  try {
    pickVolume(options, std::move(counts), "F");
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(PickedVolume, TheOptionsPickAndTheNoteSaysWhatElseTheFileHolds) {
  PickedVolume single = pickVolume({}, {}, "F");
  EXPECT_EQ(single.timePoint, 0u);
  EXPECT_EQ(single.described, "");
  EXPECT_EQ(single.note, "");

  SourceOptions options;
  options.channel = 2;
  const PickedVolume picked = pickVolume(options, {4, 3}, "F");
  EXPECT_EQ(picked.timePoint, 0u);
  EXPECT_EQ(picked.channel, 2u);
  EXPECT_EQ(picked.described, " (time point 0 of 4, channel 2 of 3)");
  EXPECT_EQ(
      picked.note,
      "F holds 4 time points and 3 channels: time point 0 of 4, channel 2 of 3 is read; --time T (0 to 3) "
      "picks another");
  options.timePoint = 3;
  EXPECT_EQ(pickVolume(options, {4, 3}, "F").note, "");
  EXPECT_EQ(pickVolume({}, {1, 2, "view setup"}, "F").note,
            "F holds 2 view setups: view setup 0 of 2 is read; --channel C (0 to 1) picks another");
  // Named channels: the one read, and all of them where few enough; names for some only are not said.
  options.timePoint.reset();
  options.channel = 1;
  const PickedVolume named = pickVolume(options, {2, 2, "view setup", {"DAPI", "GFP, angle 90"}}, "F");
  EXPECT_EQ(named.described, " (time point 0 of 2, view setup 1 of 2: 'GFP, angle 90')");
  EXPECT_EQ(
      named.note,
      "F holds 2 time points and 2 view setups ('DAPI', 'GFP, angle 90'): time point 0 of 2, view setup 1 "
      "of 2: 'GFP, angle 90' is read; --time T (0 to 1) picks another");
  EXPECT_EQ(pickVolume({}, {1, 3, "channel", {"a", "b"}}, "F").described, " (channel 0 of 3)");
  std::vector<std::string> many(17, "c");
  EXPECT_EQ(pickVolume({}, {1, 17, "channel", many}, "F").note,
            "F holds 17 channels: channel 0 of 17: 'c' is read; --channel C (0 to 16) picks another");
  options.channel = 2;

  options.timePoint = 4;
  EXPECT_EQ(pickError(options, {4, 3}), "--time 4: F holds 4 time points (--time 0 to 3)");
  options.timePoint = 0;
  options.channel = 1;
  EXPECT_EQ(pickError(options, {}), "--channel 1: F holds 1 channel (--channel 0 alone)");
}

TEST(PickedVolume, DescribePickedSaysWhichVolumeInTheInfo) {
  SourceOptions options;
  options.timePoint = 2;
  VolumeInfo info;
  info.description = "nifti:a.nii";
  describePicked(info, pickVolume(options, {5, 3}, "F"));
  EXPECT_EQ(info.description, "nifti:a.nii (time point 2 of 5, channel 0 of 3)");
  EXPECT_EQ(info.timePoints, 5u);
  EXPECT_EQ(info.channels, 3u);
  EXPECT_TRUE(info.channelNames.empty());
  VolumeInfo named;
  describePicked(named, pickVolume({}, {1, 2, "channel", {"DAPI", "GFP"}}, "F"));
  EXPECT_EQ(named.channelNames, (std::vector<std::string>{"DAPI", "GFP"}));
  EXPECT_EQ(info.timePoint, 2u);
  EXPECT_EQ(info.channel, 0u);
  ASSERT_EQ(info.notes.size(), 1u);
  EXPECT_NE(info.notes[0].find("--channel C (0 to 2) picks another"), std::string::npos);
  VolumeInfo single;
  describePicked(single, pickVolume({}, {}, "F"));
  EXPECT_EQ(single.timePoints, 1u);
  EXPECT_TRUE(single.notes.empty());
}

VolumeInfo volumeOf(glm::u32vec3 dims) {
  VolumeInfo info;
  info.dims = dims;
  info.type = SampleType::UInt16;
  info.description = "test";
  return info;
}

std::vector<uint16_t> readAll(VolumeSource& source, uint32_t z0, uint32_t count) {
  std::vector<uint16_t> out(size_t(source.info().dims.x) * source.info().dims.y * count);
  source.readSlab(z0, count, std::as_writable_bytes(std::span(out)));
  return out;
}

TEST(PickedVolume, AComponentOfInterleavedSamplesAFewSlicesAtATime) {
  const glm::u32vec3 dims{5, 4, 6};
  const uint32_t components = 3;
  std::vector<uint16_t> interleaved(size_t(dims.x) * dims.y * dims.z * components);
  for (size_t i = 0; i < interleaved.size(); ++i) interleaved[i] = uint16_t(i);
  const size_t sliceBytes = size_t(dims.x) * dims.y * 2;
  // Room for every component of 2 slices, of less than one slice, and of everything.
  for (const uint64_t room : {2 * sliceBytes * components, sliceBytes, uint64_t(1) << 30}) {
    auto stored = std::make_unique<ArraySource>(
        ArraySource::fromSamples<uint16_t>(volumeOf({dims.x * components, dims.y, dims.z}), interleaved));
    const auto source = pickComponent(std::move(stored), components, 2, volumeOf(dims), room);
    std::vector<uint16_t> expected;
    for (size_t i = 2; i < interleaved.size(); i += components) expected.push_back(interleaved[i]);
    EXPECT_EQ(readAll(*source, 0, dims.z), expected) << room;
    const std::vector<uint16_t> slab = readAll(*source, 1, 5);
    EXPECT_TRUE(std::equal(slab.begin(), slab.end(), expected.begin() + dims.x * dims.y)) << room;
  }
  auto stored = std::make_unique<ArraySource>(
      ArraySource::fromSamples<uint16_t>(volumeOf({dims.x * components, dims.y, dims.z}), interleaved));
  VolumeInfo huge = volumeOf({1 << 16, 1 << 12, 1});
  try {
    pickComponent(std::move(stored), 9, 0, huge);
    ADD_FAILURE() << "a slice of 4.5 GiB of components opened";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("test: a slice of its 9 components is more than 4 GiB"),
              std::string::npos)
        << e.what();
  }
}

TEST(PickedVolume, AVolumeOfVolumesStoredOneAfterAnother) {
  const glm::u32vec3 dims{3, 2, 4};
  std::vector<uint16_t> stacked(size_t(dims.x) * dims.y * dims.z * 3);
  for (size_t i = 0; i < stacked.size(); ++i) stacked[i] = uint16_t(i);
  auto all = std::make_unique<ArraySource>(
      ArraySource::fromSamples<uint16_t>(volumeOf({dims.x, dims.y, dims.z * 3}), stacked));
  const auto source = pickStacked(std::move(all), 2, volumeOf(dims));
  const size_t volume = size_t(dims.x) * dims.y * dims.z;
  EXPECT_EQ(readAll(*source, 0, dims.z),
            std::vector<uint16_t>(stacked.begin() + 2 * long(volume), stacked.end()));
  EXPECT_EQ(readAll(*source, 3, 1), std::vector<uint16_t>(stacked.end() - 6, stacked.end()));
}

}  // namespace
}  // namespace ropecast
