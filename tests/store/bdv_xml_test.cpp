// BigDataViewer's dataset XML (store/bdv_xml.h): the HDF5 file or N5 container resolved from the XML's folder
// and BasePath, setups with their voxel sizes, time points of each kind, the cells' dataset paths, and each
// malformed XML refused naming the file (a ViewSetup outside ViewSetups among them: no setup).
#include "store/bdv_xml.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace ropecast {
namespace {

std::string bdvSpimData(const std::string& basePath, const std::string& hdf5, const std::string& setups,
                        const std::string& timepoints) {
  return "<?xml version=\"1.0\"?><SpimData version=\"0.2\">" + basePath +
         "<SequenceDescription><ImageLoader format=\"bdv.hdf5\"><hdf5 type=\"relative\">" + hdf5 +
         "</hdf5></ImageLoader><ViewSetups>" + setups + "</ViewSetups>" + timepoints +
         "</SequenceDescription></SpimData>";
}

const std::string kBdvSetup =
    "<ViewSetup><id>2</id><name>left</name><voxelSize><unit>micron</unit>"
    "<size>0.4 0.4 3</size></voxelSize></ViewSetup>";
const std::string kBdvOneTimepoint = "<Timepoints type=\"range\"><first>0</first><last>0</last></Timepoints>";

std::string bdvErrorOf(const std::string& text) {
  try {
    parseBdvXml(text, "/data/d.xml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(BdvXml, TheFileSetupsAndTimepoints) {
  const BdvDataset d =
      parseBdvXml(bdvSpimData("<BasePath type=\"relative\">../raw</BasePath>", "d.h5",
                              kBdvSetup + "<ViewSetup><id>5</id></ViewSetup>",
                              "<Timepoints type=\"range\"><first>3</first><last>5</last></Timepoints>"),
                  "/data/xml/d.xml");
  EXPECT_EQ(d.images, "/data/raw/d.h5");
  ASSERT_EQ(d.setups.size(), 2u);
  EXPECT_EQ(d.setups[0].id, 2);
  EXPECT_EQ(d.setups[0].name, "left");
  EXPECT_EQ(d.setups[0].unit, "micron");
  EXPECT_EQ(d.setups[0].voxelSize, glm::dvec3(0.4, 0.4, 3.0));
  EXPECT_EQ(d.setups[1].id, 5);
  EXPECT_FALSE(d.setups[1].voxelSize);
  EXPECT_EQ(d.timepoints, (std::vector<int>{3, 4, 5}));

  EXPECT_EQ(d.format, BdvImageFormat::Hdf5);
  // BigStitcher's N5 export: the container's folder.
  std::string n5 = bdvSpimData("", "", kBdvSetup, kBdvOneTimepoint);
  n5.replace(n5.find("<ImageLoader"), n5.find("</ImageLoader>") - n5.find("<ImageLoader"),
             "<ImageLoader format=\"bdv.n5\" version=\"1.0\"><n5 type=\"relative\">d.n5</n5>");
  const BdvDataset inN5 = parseBdvXml(n5, "/data/d.xml");
  EXPECT_EQ(inN5.format, BdvImageFormat::N5);
  EXPECT_EQ(inN5.images, "/data/d.n5");
  EXPECT_EQ(bdvN5DatasetPath(7, 12), "setup12/timepoint7/s0");

  // No BasePath: the XML's folder; an absolute file as it is; a pattern's range and a list of ids.
  EXPECT_EQ(parseBdvXml(bdvSpimData("", "d.h5", kBdvSetup, kBdvOneTimepoint), "/data/d.xml").images,
            "/data/d.h5");
  EXPECT_EQ(
      parseBdvXml(bdvSpimData("", "/elsewhere/d.h5", kBdvSetup, kBdvOneTimepoint), "/data/d.xml").images,
      "/elsewhere/d.h5");
  EXPECT_EQ(parseBdvXml(
                bdvSpimData("", "d.h5", kBdvSetup,
                            "<Timepoints type=\"pattern\"><integerpattern>7-9</integerpattern></Timepoints>"),
                "/data/d.xml")
                .timepoints,
            (std::vector<int>{7, 8, 9}));
  EXPECT_EQ(parseBdvXml(bdvSpimData("", "d.h5", kBdvSetup,
                                    "<Timepoints type=\"list\"><id>4</id><id>1</id></Timepoints>"),
                        "/data/d.xml")
                .timepoints,
            (std::vector<int>{4, 1}));
  EXPECT_EQ(bdvCellsPath(12, 3), "/t00012/s03/0/cells");
}

TEST(BdvXml, MalformedXmlIsRefusedNamingTheFile) {
  const struct {
    std::string text, expected;
  } cases[] = {
      {"<SpimData><unclosed></SpimData>", "not well-formed XML at line 1"},
      {"<VTKFile/>", "expected a SpimData element first, got 'VTKFile'"},
      {bdvSpimData("", "d.h5", "", kBdvOneTimepoint), "no ViewSetup"},
      // A ViewSetup outside ViewSetups is no setup, nor are its fields.
      {"<SpimData><SequenceDescription><ImageLoader format=\"bdv.hdf5\"><hdf5>d.h5</hdf5></ImageLoader>"
       "<Setups><ViewSetup><id>0</id><voxelSize><size>1 1 1</size></voxelSize></ViewSetup></Setups>" +
           kBdvOneTimepoint + "</SequenceDescription></SpimData>",
       "no ViewSetup"},
      {bdvSpimData("", "d.h5", kBdvSetup, ""), "no Timepoints"},
      {bdvSpimData("", "", kBdvSetup, kBdvOneTimepoint), "names no hdf5 file"},
      {bdvSpimData("", "d.h5", "<ViewSetup><id>x</id></ViewSetup>", kBdvOneTimepoint),
       "a ViewSetup's id 'x' is not a whole number"},
      {bdvSpimData("", "d.h5", "<ViewSetup><id>0</id><voxelSize><size>1 nan 1</size></voxelSize></ViewSetup>",
                   kBdvOneTimepoint),
       "a ViewSetup's voxel size '1 nan 1' is not three numbers"},
      {bdvSpimData("", "d.h5", kBdvSetup, "<Timepoints type=\"other\"/>"),
       "its Timepoints are of type 'other'"},
      {"<SpimData><SequenceDescription><ImageLoader "
       "format=\"bdv.ome.zarr\"/></SequenceDescription></SpimData>",
       "loaded by 'bdv.ome.zarr'"},
  };
  for (const auto& c : cases) {
    const std::string message = bdvErrorOf(c.text);
    EXPECT_NE(message.find("BigDataViewer XML /data/d.xml: "), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.expected << " in: " << message;
  }
}

}  // namespace
}  // namespace ropecast
