// How ImageJ and OME-TIFF describe a multi-page TIFF (store/tiff_stack_layout.h): a hyperstack's channels,
// slices and frames and the page of each slice of the first channel and time point, the calibration from the
// description and the resolution tags, and descriptions that do not fit the pages left unread.
#include "store/tiff_stack_layout.h"

#include <gtest/gtest.h>

namespace ropecast {
namespace {

TEST(TiffStackLayout, AnImageJHyperstack) {
  const std::string description =
      "ImageJ=1.54f\nimages=24\nchannels=2\nslices=4\nframes=3\nhyperstack=true\nmode=composite\n"
      "unit=\\u00B5m\nspacing=2.5\nloop=false\n";
  const auto layout = imageJLayout(description, 4.0, 2.0, 24);
  ASSERT_TRUE(layout);
  EXPECT_EQ(layout->writer, "ImageJ");
  EXPECT_EQ(layout->channels, 2u);
  EXPECT_EQ(layout->slices, 4u);
  EXPECT_EQ(layout->frames, 3u);
  EXPECT_EQ(layout->page(0, 1, 0), 1u);  // channels fastest, then slices, then frames
  EXPECT_EQ(layout->page(1, 0, 0), 2u);
  EXPECT_EQ(layout->page(3, 1, 2), 2u * 4u * 2u + 3u * 2u + 1u);
  EXPECT_EQ(layout->spacing, glm::dvec3(0.25, 0.5, 2.5));
  EXPECT_EQ(layout->unit, "µm");
  EXPECT_FALSE(imageJLayout(description, 4.0, 2.0, 23));  // the counts do not fit the pages
  // Counts whose product wraps around 2^64 (to 0, or to the pages) are no layout.
  EXPECT_FALSE(imageJLayout("ImageJ=1\nchannels=9223372036854775808\nframes=2\n", 0, 0, 4));
  EXPECT_FALSE(imageJLayout("ImageJ=1\nchannels=9223372036854775809\nslices=2\nframes=2\n", 0, 0, 4));

  // A plain stack: slices from the pages; no resolution: z alone; neither: no spacing.
  const auto stack = imageJLayout("ImageJ=1.53t\nimages=7\nunit=micron\nspacing=3\n", 0.0, 0.0, 7);
  ASSERT_TRUE(stack);
  EXPECT_EQ(stack->slices, 7u);
  EXPECT_EQ(stack->page(6, 0, 0), 6u);
  EXPECT_EQ(stack->spacing, glm::dvec3(1.0, 1.0, 3.0));
  const auto uncalibrated = imageJLayout("ImageJ=1.53t\nimages=7\n", 0.0, 0.0, 7);
  ASSERT_TRUE(uncalibrated);
  EXPECT_FALSE(uncalibrated->spacing);
  // Resolution without spacing= gives z the x spacing.
  EXPECT_EQ(imageJLayout("ImageJ=1.53t\n", 2.0, 2.0, 3)->spacing, glm::dvec3(0.5, 0.5, 0.5));
  EXPECT_FALSE(imageJLayout("Made by a scanner", 2.0, 2.0, 3));
}

std::string omeXml(const std::string& pixelsAttributes) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?><OME "
         "xmlns=\"http://www.openmicroscopy.org/Schemas/OME/2016-06\">"
         "<Image ID=\"Image:0\"><Pixels ID=\"Pixels:0\" Type=\"uint16\" SizeX=\"8\" SizeY=\"6\" " +
         pixelsAttributes + "><TiffData/></Pixels></Image></OME>";
}

TEST(TiffStackLayout, AnOmeTiffsPixels) {
  const auto zct = omeLayout(omeXml("DimensionOrder=\"XYZCT\" SizeZ=\"5\" SizeC=\"2\" SizeT=\"1\" "
                                    "PhysicalSizeX=\"0.2\" PhysicalSizeY=\"0.2\" PhysicalSizeZ=\"1.5\""),
                             10);
  ASSERT_TRUE(zct);
  EXPECT_EQ(zct->writer, "OME-TIFF");
  EXPECT_EQ(zct->page(1, 0, 0), 1u);  // z fastest, then c
  EXPECT_EQ(zct->page(4, 1, 0), 9u);
  EXPECT_EQ(zct->slices, 5u);
  EXPECT_EQ(zct->channels, 2u);
  EXPECT_EQ(zct->spacing, glm::dvec3(0.2, 0.2, 1.5));
  EXPECT_EQ(zct->unit, "µm");  // OME's default
  const auto ctz = omeLayout(omeXml("DimensionOrder=\"XYCTZ\" SizeZ=\"4\" SizeC=\"3\" SizeT=\"2\" "
                                    "PhysicalSizeX=\"1\" PhysicalSizeY=\"1\" PhysicalSizeXUnit=\"nm\""),
                             24);
  ASSERT_TRUE(ctz);
  EXPECT_EQ(ctz->page(1, 0, 0), 6u);  // channels and time points before z
  EXPECT_EQ(ctz->page(0, 1, 0), 1u);
  EXPECT_EQ(ctz->page(3, 2, 1), 3u * 6u + 2u + 3u);
  EXPECT_EQ(ctz->spacing, glm::dvec3(1.0, 1.0, 1.0));
  EXPECT_EQ(ctz->unit, "nm");
  EXPECT_FALSE(omeLayout(omeXml("DimensionOrder=\"XYZCT\" SizeZ=\"5\" SizeC=\"2\" SizeT=\"1\""), 12));
  EXPECT_FALSE(omeLayout(omeXml("SizeZ=\"5\" SizeC=\"1\" SizeT=\"1\""), 5));  // no DimensionOrder
  EXPECT_FALSE(omeLayout(omeXml("DimensionOrder=\"XYQCT\" SizeZ=\"5\" SizeC=\"1\" SizeT=\"1\""), 5));
  EXPECT_FALSE(omeLayout(omeXml("DimensionOrder=\"XYZCC\" SizeZ=\"5\" SizeC=\"1\" SizeT=\"1\""), 5));
  EXPECT_FALSE(omeLayout("<OME><unclosed", 5));
  EXPECT_FALSE(
      omeLayout(omeXml("DimensionOrder=\"XYZCT\" SizeZ=\"2\" SizeC=\"9223372036854775809\" SizeT=\"2\""), 4));
  EXPECT_FALSE(omeLayout("ImageJ=1.53t\n", 5));
  const auto plain = omeLayout(omeXml("DimensionOrder=\"XYZCT\" SizeZ=\"5\" SizeC=\"1\" SizeT=\"1\""), 5);
  ASSERT_TRUE(plain);
  EXPECT_FALSE(plain->spacing);
}

// The first image's channels' names, where every one has a Name; another image's channels are not its.
TEST(TiffStackLayout, AnOmeTiffsChannelNames) {
  const auto ome = [](const std::string& channels) {
    return "<OME xmlns=\"http://www.openmicroscopy.org/Schemas/OME/2016-06\"><Image ID=\"Image:0\">"
           "<Pixels ID=\"Pixels:0\" DimensionOrder=\"XYZCT\" SizeX=\"8\" SizeY=\"6\" SizeZ=\"3\" SizeC=\"2\" "
           "SizeT=\"1\" Type=\"uint8\">" +
           channels +
           "<TiffData/></Pixels></Image><Image ID=\"Image:1\"><Pixels ID=\"Pixels:1\"><Channel "
           "Name=\"other\"/></Pixels></Image></OME>";
  };
  const auto named = omeLayout(ome("<Channel ID=\"Channel:0:0\" Name=\"DAPI\" SamplesPerPixel=\"1\"/>"
                                   "<Channel ID=\"Channel:0:1\" Name=\"GFP\" SamplesPerPixel=\"1\"/>"),
                               6);
  ASSERT_TRUE(named);
  EXPECT_EQ(named->channelNames, (std::vector<std::string>{"DAPI", "GFP"}));
  const auto unnamed =
      omeLayout(ome("<Channel ID=\"Channel:0:0\" Name=\"DAPI\"/><Channel ID=\"Channel:0:1\"/>"), 6);
  ASSERT_TRUE(unnamed);
  EXPECT_TRUE(unnamed->channelNames.empty());
  EXPECT_TRUE(omeLayout(ome(""), 6)->channelNames.empty());
}

}  // namespace
}  // namespace ropecast
