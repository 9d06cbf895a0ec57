// Tests of the HDF5 VolumeSource and of how inputs name HDF5 datasets: every sample type, big-endian and
// chunked, compressed datasets read in slabs thinner than a chunk and out of order, a dataset chosen by path
// or alone, the axes of ilastik's and BigDataViewer's layouts, spacings from element_size_um and from
// Imaris's extents (with its padded datasets cut to the image), chunks decoded by ropecast itself, and each
// refusal naming the file, the dataset and why.
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "store/bdv_xml.h"
#include "store/hdf5_spec.h"
#include "store/source_hdf5.h"
#include "store/volume_source.h"
#include "tests/store/store_test_util.h"
#include "tests/store/testutil_hdf5.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;
using testing::errorOf;
using testing::expectVolume;
using testing::Hdf5Writer;
using testing::readSlab;
using testing::samplePattern;
using testing::TempDir;
using testing::writeFile;

// One dataset at `dataset` of the file `path`, z, y, x = 5, 6, 9.
template <typename T>
std::vector<T> writeVolume(const std::string& path, const std::string& dataset, hid_t fileType,
                           hid_t memoryType, std::vector<hsize_t> chunk = {}, bool compressed = false) {
  const auto values = samplePattern<T>(9 * 6 * 5);
  Hdf5Writer writer(path);
  writer.write({dataset, {5, 6, 9}, fileType, memoryType, values.data(), std::move(chunk), compressed});
  return values;
}

TEST(SourceHdf5, EverySampleTypeReadsAsWritten) {
  TempDir dir;
  auto check = [&](auto tag, const std::string& name, hid_t fileType, hid_t memoryType, SampleType type) {
    using T = decltype(tag);
    const std::string path = dir.file(name + ".h5");
    const auto values = writeVolume<T>(path, "/volume", fileType, memoryType);
    expectVolume(*openVolumeSource(path), {{9, 6, 5}, type, {1.0, 1.0, 1.0}, "hdf5:" + path + ":/volume"},
                 values);
  };
  check(uint8_t{}, "u8", H5T_STD_U8LE, H5T_NATIVE_UINT8, SampleType::UInt8);
  check(int8_t{}, "i8", H5T_STD_I8LE, H5T_NATIVE_INT8, SampleType::Int8);
  check(uint16_t{}, "u16", H5T_STD_U16LE, H5T_NATIVE_UINT16, SampleType::UInt16);
  check(int16_t{}, "i16", H5T_STD_I16LE, H5T_NATIVE_INT16, SampleType::Int16);
  check(uint32_t{}, "u32", H5T_STD_U32LE, H5T_NATIVE_UINT32, SampleType::UInt32);
  check(int32_t{}, "i32", H5T_STD_I32LE, H5T_NATIVE_INT32, SampleType::Int32);
  check(float{}, "f32", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, SampleType::Float32);
  check(double{}, "f64", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, SampleType::Float64);
}

TEST(SourceHdf5, BigEndianChunkedCompressedSlabsInAnyOrder) {
  TempDir dir;
  const std::string path = dir.file("chunked.hdf5");
  // Chunks 3 slices deep: slabs of one and two slices end inside them.
  const auto values = writeVolume<int16_t>(path, "/scan", H5T_STD_I16BE, H5T_NATIVE_INT16, {3, 4, 4}, true);
  const auto source = openVolumeSource(path);
  ASSERT_EQ(source->info().type, SampleType::Int16);
  const size_t slice = 9 * 6;
  for (uint32_t z : {4u, 0u, 2u, 1u, 3u}) {
    const auto got = readSlab<int16_t>(*source, z, 1);
    EXPECT_TRUE(std::equal(got.begin(), got.end(), values.begin() + z * slice)) << "slice " << z;
  }
  const auto pair = readSlab<int16_t>(*source, 2, 2);
  EXPECT_TRUE(std::equal(pair.begin(), pair.end(), values.begin() + 2 * slice));
  expectVolume(*source, {{9, 6, 5}, SampleType::Int16, {1.0, 1.0, 1.0}, "hdf5:" + path + ":/scan"}, values);
}

// Deflated and shuffled datasets are decoded by ropecast, a layer of chunks at a time on one thread per core:
// chunks the file stores with their filters skipped (bit i of a chunk's mask: filter i), chunks never written
// (the dataset's fill value), filters in either order, and a damaged chunk named by where it starts.
TEST(SourceHdf5, ChunksDecodedOnWorkersAsTheFileStoresThem) {
  TempDir dir;
  const hsize_t extent[3] = {4, 6, 9}, chunk[3] = {2, 3, 4};
  // A dataset of uint16, chunks 2 x 3 x 4, with `filters` in that order and a fill value of 7.
  const auto create = [&](hid_t file, const std::vector<H5Z_filter_t>& filters) {
    const hid_t space = H5Screate_simple(3, extent, nullptr);
    const hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(plist, 3, chunk);
    for (const H5Z_filter_t f : filters)
      f == H5Z_FILTER_DEFLATE ? H5Pset_deflate(plist, 6) : H5Pset_shuffle(plist);
    const uint16_t fill = 7;
    H5Pset_fill_value(plist, H5T_NATIVE_UINT16, &fill);
    const hid_t dataset = H5Dcreate2(file, "/v", H5T_STD_U16LE, space, H5P_DEFAULT, plist, H5P_DEFAULT);
    H5Pclose(plist);
    H5Sclose(space);
    return dataset;
  };
  const auto values = samplePattern<uint16_t>(4 * 6 * 9);

  // Filters in both orders, every chunk written.
  for (const auto& filters : std::vector<std::vector<H5Z_filter_t>>{
           {H5Z_FILTER_SHUFFLE, H5Z_FILTER_DEFLATE}, {H5Z_FILTER_DEFLATE, H5Z_FILTER_SHUFFLE}}) {
    const std::string path = dir.file("order.h5");
    {
      const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
      const hid_t dataset = create(file, filters);
      ASSERT_GE(H5Dwrite(dataset, H5T_NATIVE_UINT16, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
      H5Dclose(dataset);
      H5Fclose(file);
    }
    const auto source = openVolumeSource(path);
    EXPECT_EQ(readSlab<uint16_t>(*source, 1, 3), std::vector<uint16_t>(values.begin() + 9 * 6, values.end()));
  }

  // The first chunk layer written, its first chunk stored again with both filters skipped; the second layer
  // never written.
  const std::string path = dir.file("sparse.h5");
  std::vector<uint16_t> raw(2 * 3 * 4);
  for (size_t i = 0; i < raw.size(); ++i) raw[i] = uint16_t(1000 + i);
  {
    const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t dataset = create(file, {H5Z_FILTER_SHUFFLE, H5Z_FILTER_DEFLATE});
    const hsize_t start[3] = {0, 0, 0}, count[3] = {2, 6, 9};
    const hid_t fileSpace = H5Dget_space(dataset), memorySpace = H5Screate_simple(3, count, nullptr);
    H5Sselect_hyperslab(fileSpace, H5S_SELECT_SET, start, nullptr, count, nullptr);
    ASSERT_GE(H5Dwrite(dataset, H5T_NATIVE_UINT16, memorySpace, fileSpace, H5P_DEFAULT, values.data()), 0);
    ASSERT_GE(H5Dwrite_chunk(dataset, H5P_DEFAULT, 0x3, start, raw.size() * 2, raw.data()), 0);
    H5Sclose(memorySpace);
    H5Sclose(fileSpace);
    H5Dclose(dataset);
    H5Fclose(file);
  }
  std::vector<uint16_t> expected(values.begin(), values.begin() + 2 * 6 * 9);
  for (uint32_t z = 0; z < 2; ++z)
    for (uint32_t y = 0; y < 3; ++y)
      for (uint32_t x = 0; x < 4; ++x) expected[(z * 6 + y) * 9 + x] = raw[(z * 3 + y) * 4 + x];
  expected.resize(4 * 6 * 9, 7);
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(path), 0, 4), expected);

  // A chunk whose stored bytes are no deflate stream.
  const std::string damaged = dir.file("damaged.h5");
  {
    const hid_t file = H5Fcreate(damaged.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t dataset = create(file, {H5Z_FILTER_SHUFFLE, H5Z_FILTER_DEFLATE});
    const hsize_t at[3] = {2, 3, 4};
    const std::vector<uint8_t> garbage(40, 0xab);
    ASSERT_GE(H5Dwrite_chunk(dataset, H5P_DEFAULT, 0, at, garbage.size(), garbage.data()), 0);
    H5Dclose(dataset);
    H5Fclose(file);
  }
  const auto source = openVolumeSource(damaged);
  EXPECT_EQ(readSlab<uint16_t>(*source, 0, 2), std::vector<uint16_t>(2 * 6 * 9, 7));  // the layer before it
  try {
    readSlab<uint16_t>(*source, 2, 1);
    FAIL() << "a damaged chunk was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("HDF5 file " + damaged +
                                         ", dataset /v: the chunk at (2, 3, 4) is "
                                         "damaged or of another size (deflate)"),
              std::string::npos)
        << e.what();
  }
}

TEST(SourceHdf5, ADatasetIsNamedByPathOrChosenWhenItIsTheOnlyVolume) {
  TempDir dir;
  const std::string path = dir.file("two.h5");
  const auto a = samplePattern<uint8_t>(9 * 6 * 5);
  std::vector<uint16_t> b(4 * 3 * 2);
  for (size_t i = 0; i < b.size(); ++i) b[i] = uint16_t(1000 + 7 * i);
  {
    Hdf5Writer writer(path);
    writer.write({"/raw/a", {5, 6, 9}, H5T_STD_U8LE, H5T_NATIVE_UINT8, a.data(), {}, false});
    writer.write({"/processed/deep/b", {2, 3, 4}, H5T_STD_U16LE, H5T_NATIVE_UINT16, b.data(), {}, false});
    writer.writeText("/notes", "not a volume");
  }
  const std::string many = errorOf(path);
  for (const std::string& word : std::vector<std::string>{
           "HDF5 file", "2 datasets that are volumes", "/raw/a", "/processed/deep/b", "as in " + path + ":/"})
    EXPECT_NE(many.find(word), std::string::npos) << word << " in: " << many;
  expectVolume(*openVolumeSource(path + ":/processed/deep/b"),
               {{4, 3, 2}, SampleType::UInt16, {1.0, 1.0, 1.0}, "hdf5:" + path + ":/processed/deep/b"}, b);
  // Without the leading slash too.
  EXPECT_EQ(openVolumeSource(path + ":raw/a")->info().description, "hdf5:" + path + ":/raw/a");

  const std::string one = dir.file("one.h5");
  {
    Hdf5Writer writer(one);
    writer.write({"/only/volume", {2, 3, 4}, H5T_STD_U16LE, H5T_NATIVE_UINT16, b.data(), {}, false});
    writer.writeText("/label", "text");
  }
  expectVolume(*openVolumeSource(one),
               {{4, 3, 2}, SampleType::UInt16, {1.0, 1.0, 1.0}, "hdf5:" + one + ":/only/volume"}, b);
}

TEST(SourceHdf5, LengthOneAxesAroundZyxAreTimePointsAndChannels) {
  TempDir dir;
  const auto values = samplePattern<uint16_t>(9 * 6 * 5);
  const auto check = [&](const std::string& name, std::vector<hsize_t> extent) {
    const std::string path = dir.file(name + ".h5");
    {
      Hdf5Writer writer(path);
      writer.write({"/data", extent, H5T_STD_U16LE, H5T_NATIVE_UINT16, values.data(), {}, false});
    }
    expectVolume(*openVolumeSource(path),
                 {{9, 6, 5}, SampleType::UInt16, {1.0, 1.0, 1.0}, "hdf5:" + path + ":/data"}, values);
  };
  check("tczyx", {1, 1, 5, 6, 9});  // BigDataViewer, OME
  check("zyxc", {5, 6, 9, 1});      // ilastik's export
  check("tzcyx", {1, 5, 1, 6, 9});

  // A single slice in five axes keeps z as the length-1 axis before y.
  const std::string flat = dir.file("flat.h5");
  {
    Hdf5Writer writer(flat);
    writer.write({"/data", {1, 1, 1, 6, 9}, H5T_STD_U16LE, H5T_NATIVE_UINT16, values.data(), {}, false});
  }
  EXPECT_EQ(openVolumeSource(flat)->info().dims, glm::u32vec3(9, 6, 1));

  // Two volumes along a fourth axis that the file does not name: refused, asking for --axes; with --axes,
  // the volume picked along the axis named t (--time) or c (--channel). The second volume is the first
  // plus 1.
  const std::string series = dir.file("series.h5");
  std::vector<uint16_t> twice(values);
  for (const uint16_t v : values) twice.push_back(uint16_t(v + 1));
  {
    Hdf5Writer writer(series);
    writer.write({"/data", {2, 5, 6, 9}, H5T_STD_U16LE, H5T_NATIVE_UINT16, twice.data(), {}, false});
  }
  const std::string refused = errorOf(series);
  for (const char* word : {"/data", "4 axes longer than 1", "2x5x6x9", "--axes", "tzyx"})
    EXPECT_NE(refused.find(word), std::string::npos) << word << " in: " << refused;
  const std::vector<uint16_t> second(twice.begin() + long(values.size()), twice.end());
  SourceOptions options;
  options.axes = "tzyx";
  options.timePoint = 1;
  auto picked = openVolumeSource(series, options);
  EXPECT_EQ(readSlab<uint16_t>(*picked, 0, 5), second);
  EXPECT_NE(picked->info().description.find("time point 1 of 2"), std::string::npos)
      << picked->info().description;
  options.axes = "czyx";
  options.timePoint.reset();
  options.channel = 1;
  EXPECT_EQ(readSlab<uint16_t>(*openVolumeSource(series + ":/data", options), 0, 5), second);
  options.channel.reset();
  options.axes = "zyx";
  EXPECT_NE(errorOf(series, options).find("--axes zyx names 3 axes; it has 4 (2x5x6x9)"), std::string::npos)
      << errorOf(series, options);
  // A file that names its axes keeps them; other files take none.
  const std::string named = dir.file("named.h5");
  {
    Hdf5Writer writer(named);
    const hid_t dataset =
        writer.write({"/data", {5, 6, 9}, H5T_STD_U16LE, H5T_NATIVE_UINT16, values.data(), {}, false});
    testing::writeCharsAttribute(dataset, "axistags",
                                 R"({"axes": [{"key": "z"}, {"key": "y"}, {"key": "x"}]})");
  }
  options.axes = "zyx";
  EXPECT_NE(errorOf(named + ":/data", options).find("names its axes itself (z, y, x)"), std::string::npos)
      << errorOf(named + ":/data", options);
}

// ilastik's exports name their axes in an `axistags` attribute: a probability map of 2 time points and 3
// channels (t, z, y, x, c) is a volume of each, picked by --time and --channel; contiguous (the library's
// reads) and in chunks of 2 channels and 1 time point, deflated (ropecast's own). Time point t, channel c
// holds 10 (3 t + c) plus the sample's index.
TEST(SourceHdf5, IlastikAxisTagsNameTimeAndChannelAxes) {
  TempDir dir;
  std::vector<uint8_t> map(2 * 3 * 4 * 5 * 3);
  for (size_t t = 0, i = 0; t < 2; ++t)
    for (size_t zyx = 0; zyx < 3 * 4 * 5; ++zyx)
      for (size_t c = 0; c < 3; ++c) map[i++] = uint8_t(10 * (3 * t + c) + zyx);
  const auto volumeOf = [](size_t t, size_t c) {
    std::vector<uint8_t> v(3 * 4 * 5);
    for (size_t i = 0; i < v.size(); ++i) v[i] = uint8_t(10 * (3 * t + c) + i);
    return v;
  };
  const std::string tags =
      R"({"axes": [{"key": "t", "typeFlags": 8}, {"key": "z", "typeFlags": 2}, {"key": "y", "typeFlags": 2},)"
      R"( {"key": "x", "typeFlags": 2}, {"key": "c", "typeFlags": 1}]})";
  for (const bool chunked : {false, true}) {
    const std::string path = dir.file(chunked ? "chunked.h5" : "plain.h5");
    {
      Hdf5Writer writer(path);
      const hid_t dataset =
          writer.write({"/exported_data",
                        {2, 3, 4, 5, 3},
                        H5T_STD_U8LE,
                        H5T_NATIVE_UINT8,
                        map.data(),
                        chunked ? std::vector<hsize_t>{1, 2, 3, 4, 2} : std::vector<hsize_t>{},
                        chunked});
      testing::writeCharsAttribute(dataset, "axistags", tags);
    }
    const auto first = openVolumeSource(path);
    EXPECT_EQ(first->info().dims, glm::u32vec3(5, 4, 3));
    EXPECT_EQ(readSlab<uint8_t>(*first, 0, 3), volumeOf(0, 0)) << path;
    ASSERT_EQ(first->info().notes.size(), 1u);
    EXPECT_NE(first->info().notes[0].find("holds 2 time points and 3 channels"), std::string::npos);
    for (const auto& [t, c] : std::vector<std::pair<uint32_t, uint32_t>>{{1, 2}, {0, 1}, {1, 0}}) {
      SourceOptions options;
      options.timePoint = t;
      options.channel = c;
      const auto source = openVolumeSource(path, options);
      const std::vector<uint8_t> expected = volumeOf(t, c);
      EXPECT_EQ(readSlab<uint8_t>(*source, 0, 3), expected) << path << " t " << t << " c " << c;
      EXPECT_EQ(readSlab<uint8_t>(*source, 1, 2), std::vector<uint8_t>(expected.begin() + 20, expected.end()))
          << path;
    }
  }
}

TEST(SourceHdf5, SpacingFromElementSizeOrOptions) {
  TempDir dir;
  const std::string path = dir.file("sized.h5");
  const auto values = samplePattern<uint8_t>(9 * 6 * 5);
  {
    Hdf5Writer writer(path);
    const hid_t d =
        writer.write({"/volume", {5, 6, 9}, H5T_STD_U8LE, H5T_NATIVE_UINT8, values.data(), {}, false});
    testing::writeNumbersAttribute(d, "element_size_um", {2.0, 0.5, 0.25});  // z, y, x
  }
  EXPECT_EQ(openVolumeSource(path)->info().spacing, glm::dvec3(0.25, 0.5, 2.0));
  SourceOptions options;
  options.spacing = glm::dvec3(3.0, 4.0, 5.0);
  EXPECT_EQ(openVolumeSource(path, options)->info().spacing, glm::dvec3(3.0, 4.0, 5.0));
  options = {};
  options.dims = glm::u32vec3(9, 6, 5);
  const std::string refused = errorOf(path, options);
  EXPECT_NE(refused.find("--dims applies to raw files only"), std::string::npos) << refused;
}

TEST(SourceHdf5, ImarisFilesReadTheFullResolutionCutToTheImage) {
  TempDir dir;
  const std::string path = dir.file("cells.ims");
  // The image is 13 x 7 x 3 samples, stored padded to 16 x 8 x 4; a coarser level beside it.
  std::vector<uint16_t> padded(16 * 8 * 4, 9999), expected;
  for (uint32_t z = 0; z < 4; ++z)
    for (uint32_t y = 0; y < 8; ++y)
      for (uint32_t x = 0; x < 16; ++x)
        if (x < 13 && y < 7 && z < 3) {
          padded[(z * 8 + y) * 16 + x] = uint16_t(x + 20 * y + 200 * z);
          expected.push_back(padded[(z * 8 + y) * 16 + x]);
        }
  const std::vector<uint16_t> coarse(8 * 4 * 2, 1);
  {
    Hdf5Writer writer(path);
    writer.write({"/DataSet/ResolutionLevel 0/TimePoint 0/Channel 0/Data",
                  {4, 8, 16},
                  H5T_STD_U16LE,
                  H5T_NATIVE_UINT16,
                  padded.data(),
                  {4, 8, 16},
                  true});
    writer.write({"/DataSet/ResolutionLevel 1/TimePoint 0/Channel 0/Data",
                  {2, 4, 8},
                  H5T_STD_U16LE,
                  H5T_NATIVE_UINT16,
                  coarse.data(),
                  {},
                  false});
    const hid_t image = writer.group("/DataSetInfo/Image");
    for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{{"X", "13"},
                                                                                     {"Y", "7"},
                                                                                     {"Z", "3"},
                                                                                     {"ExtMin0", "-6.5"},
                                                                                     {"ExtMax0", "6.5"},
                                                                                     {"ExtMin1", "0"},
                                                                                     {"ExtMax1", "3.5"},
                                                                                     {"ExtMin2", "10"},
                                                                                     {"ExtMax2", "16"}})
      testing::writeCharsAttribute(image, name, text);
  }
  expectVolume(*openVolumeSource(path),
               {{13, 7, 3},
                SampleType::UInt16,
                {1.0, 0.5, 2.0},
                "hdf5:" + path + ":/DataSet/ResolutionLevel 0/TimePoint 0/Channel 0/Data"},
               expected);
  // A coarser level named by path is read as it is stored.
  EXPECT_EQ(openVolumeSource(path + ":/DataSet/ResolutionLevel 1/TimePoint 0/Channel 0/Data")->info().dims,
            glm::u32vec3(8, 4, 2));
  SourceOptions second;
  second.timePoint = 1;
  EXPECT_EQ(errorOf(path, second), "--time 1: Imaris file " + path + " holds 1 time point (--time 0 alone)");
}

// An Imaris file of 3 time points of 2 channels: the first read by default, with a warning; --time and
// --channel pick another (the volume of time point t, channel c holds 10 (2 t + c) + its index).
TEST(SourceHdf5, ImarisTimePointsAndChannelsArePickedByTimeAndChannel) {
  TempDir dir;
  const std::string path = dir.file("series.ims");
  const auto volumeOf = [](int t, int c) {
    std::vector<uint8_t> v(4 * 3 * 2);
    for (size_t i = 0; i < v.size(); ++i) v[i] = uint8_t(10 * (2 * t + c) + int(i));
    return v;
  };
  {
    Hdf5Writer writer(path);
    for (int t = 0; t < 3; ++t)
      for (int c = 0; c < 2; ++c) {
        const std::vector<uint8_t> v = volumeOf(t, c);
        writer.write({"/DataSet/ResolutionLevel 0/TimePoint " + std::to_string(t) + "/Channel " +
                          std::to_string(c) + "/Data",
                      {2, 3, 4},
                      H5T_STD_U8LE,
                      H5T_NATIVE_UINT8,
                      v.data(),
                      {},
                      false});
      }
  }
  auto source = openVolumeSource(path);
  EXPECT_EQ(readSlab<uint8_t>(*source, 0, 2), volumeOf(0, 0));
  ASSERT_EQ(source->info().notes.size(), 1u);
  EXPECT_EQ(source->info().notes[0],
            "Imaris file " + path +
                " holds 3 time points and 2 channels: time point 0 of 3, channel 0 "
                "of 2 is read; --time T (0 to 2) or --channel C (0 to 1) picks another");
  SourceOptions options;
  options.timePoint = 2;
  options.channel = 1;
  source = openVolumeSource(path, options);
  EXPECT_EQ(readSlab<uint8_t>(*source, 0, 2), volumeOf(2, 1));
  EXPECT_EQ(source->info().description, "hdf5:" + path +
                                            ":/DataSet/ResolutionLevel 0/TimePoint 2/Channel 1/Data (time "
                                            "point 2 of 3, channel 1 of 2)");
  EXPECT_TRUE(source->info().notes.empty());
  options.channel.reset();
  options.timePoint = 1;
  EXPECT_EQ(readSlab<uint8_t>(*openVolumeSource(path, options), 0, 2), volumeOf(1, 0));
  options.timePoint = 3;
  EXPECT_EQ(errorOf(path, options), "--time 3: Imaris file " + path + " holds 3 time points (--time 0 to 2)");
  // A dataset named by path is one volume.
  options.timePoint = 1;
  EXPECT_NE(errorOf(path + ":/DataSet/ResolutionLevel 0/TimePoint 0/Channel 0/Data", options)
                .find("holds 1 time point (--time 0 alone)"),
            std::string::npos);
}

// A BigDataViewer dataset given by its XML: the full resolution of its one view, at the voxel size the XML
// gives, its signed 16-bit cells read as the unsigned samples they hold; of several view setups, the one
// --channel picks; XML of another loader is refused.
TEST(SourceHdf5, ABigDataViewerXmlReadsItsViewAtItsVoxelSize) {
  TempDir dir;
  fs::create_directories(dir.path() / "data");
  const std::string h5 = (dir.path() / "data" / "beads.h5").string();
  std::vector<int16_t> cells(5 * 6 * 9);
  for (size_t i = 0; i < cells.size(); ++i) cells[i] = int16_t(uint16_t(i * 1201 + 7));  // past 32767 too
  const std::vector<int16_t> coarse(3 * 3 * 5, 1);
  std::vector<int16_t> other(cells.size());  // setup 3's
  for (size_t i = 0; i < other.size(); ++i) other[i] = int16_t(i);
  {
    Hdf5Writer writer(h5);
    writer.write(
        {"/t00000/s00/0/cells", {5, 6, 9}, H5T_STD_I16LE, H5T_NATIVE_INT16, cells.data(), {2, 3, 4}, true});
    writer.write(
        {"/t00000/s03/0/cells", {5, 6, 9}, H5T_STD_I16LE, H5T_NATIVE_INT16, other.data(), {}, false});
    writer.write(
        {"/t00000/s00/1/cells", {3, 3, 5}, H5T_STD_I16LE, H5T_NATIVE_INT16, coarse.data(), {}, false});
  }
  const auto xmlWith = [](const std::string& setups, const std::string& loader = "bdv.hdf5") {
    return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<SpimData version=\"0.2\">\n"
           "  <BasePath type=\"relative\">data</BasePath>\n  <SequenceDescription>\n"
           "    <ImageLoader format=\"" +
           loader +
           "\">\n      <hdf5 type=\"relative\">beads.h5</hdf5>\n    </ImageLoader>\n"
           "    <ViewSetups>\n" +
           setups +
           "    </ViewSetups>\n    <Timepoints type=\"range\"><first>0</first><last>0</last></Timepoints>\n"
           "  </SequenceDescription>\n</SpimData>\n";
  };
  const auto setup = [](int id, const char* name, const char* voxelSize = "0.25 0.25 1.5") {
    return "      <ViewSetup><id>" + std::to_string(id) + "</id><name>" + name +
           "</name><size>9 6 5</size><voxelSize><unit>µm</unit><size>" + voxelSize +
           "</size></voxelSize></ViewSetup>\n";
  };
  const std::string xml = dir.file("beads.xml");
  writeFile(xml, xmlWith(setup(0, "beads")));
  const auto source = openVolumeSource(xml);
  std::vector<uint16_t> expected(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) expected[i] = uint16_t(cells[i]);
  expectVolume(
      *source,
      {{9, 6, 5}, SampleType::UInt16, {0.25, 0.25, 1.5}, "bdv:" + xml + " (" + h5 + ":/t00000/s00/0/cells)"},
      expected);

  // The dataset given directly is read as the XML reads it (unsigned), another dataset's signed samples not.
  EXPECT_EQ(openVolumeSource(h5 + ":/t00000/s00/0/cells")->info().type, SampleType::UInt16);
  EXPECT_EQ(openVolumeSource(h5 + ":/t00000/s00/1/cells")->info().type, SampleType::UInt16);
  EXPECT_TRUE(isBdvCellsPath("/t00012/s03/10/cells"));
  for (const char* other : {"/t0000/s00/0/cells", "/t00000/s00//cells", "/t00000/s00/0/cell", "/scan/ct",
                            "/t00000/s00/0/cells/x", "/t00000/sx0/0/cells"})
    EXPECT_FALSE(isBdvCellsPath(other)) << other;

  // Several view setups: the first is read, with a warning; --channel picks another, at its voxel size.
  writeFile(xml, xmlWith(setup(0, "beads") + setup(3, "beads, other angle", "0.5 0.5 2")));
  const auto first = openVolumeSource(xml);
  EXPECT_EQ(first->info().spacing, glm::dvec3(0.25, 0.25, 1.5));
  ASSERT_EQ(first->info().notes.size(), 1u);
  EXPECT_EQ(first->info().notes[0],
            "BigDataViewer dataset " + xml +
                " holds 2 view setups ('beads', 'beads, other angle'): view setup 0 of 2: 'beads' is read; "
                "--channel C (0 to 1) picks another");
  SourceOptions angle;
  angle.channel = 1;
  const auto picked = openVolumeSource(xml, angle);
  EXPECT_EQ(picked->info().spacing, glm::dvec3(0.5, 0.5, 2.0));
  EXPECT_EQ(picked->info().description,
            "bdv:" + xml + " (" + h5 + ":/t00000/s03/0/cells) (view setup 1 of 2: 'beads, other angle')");
  std::vector<uint16_t> otherValues(other.begin(), other.end());
  EXPECT_EQ(readSlab<uint16_t>(*picked, 0, 5), otherValues);
  angle.channel = 2;
  EXPECT_EQ(errorOf(xml, angle),
            "--channel 2: BigDataViewer dataset " + xml + " holds 2 view setups (--channel 0 to 1)");
  angle.channel.reset();
  angle.timePoint = 1;
  EXPECT_EQ(errorOf(xml, angle),
            "--time 1: BigDataViewer dataset " + xml + " holds 1 time point (--time 0 alone)");
  writeFile(xml, xmlWith(setup(0, "beads"), "bdv.ome.zarr"));
  EXPECT_NE(errorOf(xml).find("loaded by 'bdv.ome.zarr'; BigDataViewer's HDF5 (format \"bdv.hdf5\") and N5"),
            std::string::npos)
      << errorOf(xml);
  writeFile(xml, "<VTKFile type=\"ImageData\"/>\n");
  EXPECT_NE(errorOf(xml).find("is XML but no BigDataViewer dataset"), std::string::npos) << errorOf(xml);
}

TEST(SourceHdf5, RefusalsNameTheFileTheDatasetAndWhy) {
  TempDir dir;
  const std::string path = dir.file("mixed.h5");
  const std::vector<int64_t> wide(2 * 3 * 4, 5);
  const std::vector<float> plane(3 * 4, 1.0f);
  {
    Hdf5Writer writer(path);
    writer.write({"/wide", {2, 3, 4}, H5T_STD_I64LE, H5T_NATIVE_INT64, wide.data(), {}, false});
    writer.write({"/plane", {3, 4}, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, plane.data(), {}, false});
    writer.writeText("/text", "words");
    writer.group("/empty_group");
  }
  const auto expectRefused = [&](const std::string& spec, std::vector<std::string> words) {
    const std::string message = errorOf(spec);
    EXPECT_FALSE(message.empty()) << spec;
    for (const std::string& word : words)
      EXPECT_NE(message.find(word), std::string::npos) << word << " in: " << message;
  };
  expectRefused(
      path, {"HDF5 file " + path, "no dataset that is a volume", "/wide (its elements are 64-bit integers",
             "/plane (it has 2 axes", "/text (its elements are strings)"});
  expectRefused(path + ":/wide", {path, "dataset /wide", "not a volume", "64-bit integers"});
  expectRefused(path + ":/nothing/here", {path, "has no object /nothing/here"});
  expectRefused(path + ":/empty_group", {"dataset /empty_group", "is a group"});

  const std::string bare = dir.file("bare.h5");
  { Hdf5Writer writer(bare); }
  expectRefused(bare, {"HDF5 file " + bare, "no dataset that is a volume", "no dataset at all"});

  const std::string text = dir.file("notes.h5");
  writeFile(text, "not HDF5 at all\n");
  expectRefused(text, {"HDF5 file " + text, "not an HDF5 file"});
  const std::string hdf4 = dir.file("old.hdf");
  writeFile(hdf4, std::string("\x0e\x03\x13\x01", 4) + std::string(100, '\0'));
  expectRefused(hdf4, {"not an HDF5 file", "HDF4 files are not read"});

  // A file cut short: refused when opened or when its samples are read, never read as other values.
  const std::string whole = dir.file("whole.h5");
  writeVolume<uint16_t>(whole, "/volume", H5T_STD_U16LE, H5T_NATIVE_UINT16);
  const std::string cut = dir.file("cut.h5");
  fs::copy_file(whole, cut);
  fs::resize_file(cut, fs::file_size(whole) / 2);
  try {
    const auto source = openVolumeSource(cut);
    readSlab<uint16_t>(*source, 0, source->info().dims.z);
    ADD_FAILURE() << "a file cut short read without error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
  }
}

TEST(Hdf5Spec, AFileOrAFileAndADatasetPath) {
  TempDir dir;
  const std::string h5 = dir.file("a.h5");
  writeFile(h5, "x");  // named HDF5: whether it is one the source says
  const std::string signed5 = dir.file("volume.bin");
  writeFile(signed5, std::string("\x89HDF\r\n\x1a\n", 8) + "rest");
  const std::string raw = dir.file("scan_4x4x4_uint8.raw");
  writeFile(raw, std::string(64, '\0'));

  const auto parts = [](const std::string& spec) {
    const auto p = hdf5SpecOf(spec);
    return p ? p->file + "|" + p->dataset : std::string("none");
  };
  EXPECT_EQ(parts(h5), h5 + "|");
  EXPECT_EQ(parts(h5 + ":/group/data"), h5 + "|/group/data");
  EXPECT_EQ(parts(h5 + ":/a:b"), h5 + "|/a:b");
  EXPECT_EQ(parts(signed5), signed5 + "|");
  EXPECT_EQ(parts(signed5 + ":/d"), signed5 + "|/d");
  EXPECT_EQ(parts(raw), "none");
  EXPECT_EQ(parts(raw + ":/d"), "none");
  EXPECT_EQ(parts(dir.file("missing.h5")), "none");
  EXPECT_EQ(parts(dir.file("missing.h5") + ":/d"), "none");
  EXPECT_EQ(parts("procedural:sphere:32"), "none");

  // A folder whose name holds a colon.
  fs::create_directory(dir.file("run:3"));
  const std::string inColonFolder = dir.file("run:3/out.h5");
  writeFile(inColonFolder, "x");
  EXPECT_EQ(parts(inColonFolder + ":/d"), inColonFolder + "|/d");
}

}  // namespace
}  // namespace ropecast
