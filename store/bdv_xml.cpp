#include "store/bdv_xml.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "core/error.h"
#include "core/header_text.h"
#include "core/number_text.h"
#include "store/xml_reading.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

// What the expat callbacks gather, by the path of elements. A problem is kept and the parser stopped, since
// exceptions must not cross expat's C frames.
class BdvParser {
 public:
  BdvParser(std::string_view text, const std::string& path) : input_(text), path_(path) {}

  BdvDataset parse() {
    const XmlParser parser = makeXmlParser(*this);
    if (!parser) fail("cannot create an XML parser");
    parser_ = parser.get();
    const XML_Status status = XML_Parse(parser_, input_.data(), int(input_.size()), XML_TRUE);
    if (!problem_.empty()) fail(problem_);
    if (status == XML_STATUS_ERROR)
      fail("not well-formed XML at line " + std::to_string(XML_GetCurrentLineNumber(parser_)) + " (" +
           XML_ErrorString(XML_GetErrorCode(parser_)) + ")");
    if (loader_ != "bdv.hdf5" && loader_ != "bdv.n5")
      fail(loader_.empty()
               ? "no ImageLoader element"
               : "its images are loaded by '" + loader_ +
                     "'; BigDataViewer's HDF5 (format \"bdv.hdf5\") and N5 (\"bdv.n5\") are read");
    dataset_.format = loader_ == "bdv.n5" ? BdvImageFormat::N5 : BdvImageFormat::Hdf5;
    const std::string& images = dataset_.format == BdvImageFormat::N5 ? n5_ : hdf5_;
    if (images.empty())
      fail(std::string("its ImageLoader names no ") +
           (dataset_.format == BdvImageFormat::N5 ? "n5 container" : "hdf5 file"));
    if (dataset_.setups.empty()) fail("no ViewSetup");
    if (dataset_.timepoints.empty()) fail("no Timepoints");
    const fs::path folder = fs::path(path_).parent_path();
    fs::path base = basePath_.empty() ? fs::path(".") : fs::path(basePath_);
    if (base.is_relative()) base = folder / base;
    const fs::path file(images);
    dataset_.images = (file.is_relative() ? base / file : file).lexically_normal().string();
    return dataset_;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("BigDataViewer XML " + path_ + ": " + what);
  }
  void stop(const std::string& problem) {
    if (problem_.empty()) problem_ = problem;
    XML_StopParser(parser_, XML_FALSE);
  }

  // Whether the open elements end with `names` (innermost last).
  bool within(std::initializer_list<std::string_view> names) const {
    if (open_.size() < names.size()) return false;
    size_t i = open_.size() - names.size();
    for (std::string_view name : names)
      if (open_[i++] != name) return false;
    return true;
  }

 public:  // expat's callbacks (store/xml_reading.h)
  void startElement(std::string_view name, const XML_Char** attributes) {
    if (!problem_.empty()) return;
    if (open_.empty() && name != "SpimData")
      return stop("expected a SpimData element first, got '" + std::string(name) + "'");
    open_.emplace_back(name);
    chars_.clear();
    if (within({"SequenceDescription", "ImageLoader"}))
      loader_ = std::string(xmlAttribute(attributes, "format").value_or(""));
    if (within({"ViewSetups", "ViewSetup"})) dataset_.setups.emplace_back();
    if (within({"SequenceDescription", "Timepoints"})) {
      timepointsType_ = std::string(xmlAttribute(attributes, "type").value_or(""));
      if (timepointsType_ != "range" && timepointsType_ != "pattern" && timepointsType_ != "list")
        return stop("its Timepoints are of type '" + timepointsType_ + "'; range, pattern and list are read");
    }
  }

  // A ViewSetup's fields are read only within ViewSetups/ViewSetup, where startElement added the setup.
  void characters(std::string_view text) { chars_.append(text); }

  void endElement(std::string_view) {
    if (!problem_.empty() || open_.empty()) return;
    const std::string text(trimBlanks(chars_));
    if (within({"SpimData", "BasePath"})) basePath_ = text;
    if (within({"ImageLoader", "hdf5"})) hdf5_ = text;
    if (within({"ImageLoader", "n5"})) n5_ = text;
    if (within({"ViewSetups", "ViewSetup", "id"}))
      dataset_.setups.back().id = integer(text, "a ViewSetup's id");
    if (within({"ViewSetups", "ViewSetup", "name"})) dataset_.setups.back().name = text;
    if (within({"ViewSetups", "ViewSetup", "voxelSize", "unit"})) dataset_.setups.back().unit = text;
    if (within({"ViewSetups", "ViewSetup", "voxelSize", "size"})) {
      const auto words = splitWords(text);
      glm::dvec3 size(0.0);
      for (size_t a = 0; a < 3 && words.size() == 3; ++a) {
        const auto n = parseWholeNumber<double>(words[a]);
        if (!n || !std::isfinite(*n))
          return stop("a ViewSetup's voxel size '" + text + "' is not three numbers");
        size[int(a)] = *n;
      }
      if (words.size() != 3) return stop("a ViewSetup's voxel size '" + text + "' is not three numbers");
      dataset_.setups.back().voxelSize = size;
    }
    if (within({"SequenceDescription", "Timepoints", "first"}))
      first_ = integer(text, "the first time point");
    if (within({"SequenceDescription", "Timepoints", "last"})) {
      const int last = integer(text, "the last time point");
      for (int t = first_; t <= last && dataset_.timepoints.size() < 1000000; ++t)
        dataset_.timepoints.push_back(t);
    }
    if (within({"SequenceDescription", "Timepoints", "id"}))
      dataset_.timepoints.push_back(integer(text, "a time point"));
    if (within({"SequenceDescription", "Timepoints", "integerpattern"})) {
      // One number, or first-last (BigDataViewer's pattern form); steps and lists are not read.
      const size_t dash = text.find('-', 1);
      const int from = integer(text.substr(0, dash), "a time point pattern");
      const int to =
          dash == std::string::npos ? from : integer(text.substr(dash + 1), "a time point pattern");
      for (int t = from; t <= to && dataset_.timepoints.size() < 1000000; ++t)
        dataset_.timepoints.push_back(t);
    }
    open_.pop_back();
    chars_.clear();
  }

 private:
  int integer(std::string_view text, const char* what) {
    const auto n = parseWholeNumber<int>(trimBlanks(text));
    if (!n || *n < 0) {
      stop(std::string(what) + " '" + std::string(text) + "' is not a whole number of 0 or more");
      return 0;
    }
    return *n;
  }

  std::string_view input_;
  std::string chars_;  // the text of the element that ends next
  const std::string& path_;
  XML_Parser parser_ = nullptr;
  std::vector<std::string> open_;
  std::string problem_, loader_, hdf5_, n5_, basePath_, timepointsType_;
  int first_ = 0;
  BdvDataset dataset_;
};

}  // namespace

bool isBdvXml(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(in.gcount()));
  return head.find("<SpimData") != std::string::npos;
}

BdvDataset parseBdvXml(std::string_view text, const std::string& path) {
  return BdvParser(text, path).parse();
}

PickedVolume pickBdvView(const BdvDataset& dataset, const SourceOptions& options, const std::string& xml) {
  // The setups' names say what each is (a channel, an angle, a tile).
  std::vector<std::string> names;
  for (const BdvSetup& setup : dataset.setups) names.push_back(setup.name);
  return pickVolume(options,
                    {dataset.timepoints.size(), dataset.setups.size(), "view setup", std::move(names)},
                    "BigDataViewer dataset " + xml);
}

std::string bdvCellsPath(int timepoint, int setup) {
  char path[64];
  std::snprintf(path, sizeof path, "/t%05d/s%02d/0/cells", timepoint, setup);
  return path;
}

std::string bdvN5DatasetPath(int timepoint, int setup) {
  return "setup" + std::to_string(setup) + "/timepoint" + std::to_string(timepoint) + "/s0";
}

bool isBdvCellsPath(std::string_view path) {
  const auto digits = [&](size_t count) {
    if (path.size() < count) return false;
    for (size_t i = 0; i < count; ++i)
      if (path[i] < '0' || path[i] > '9') return false;
    path.remove_prefix(count);
    return true;
  };
  const auto literal = [&](std::string_view text) {
    if (!path.starts_with(text)) return false;
    path.remove_prefix(text.size());
    return true;
  };
  if (!literal("/t") || !digits(5) || !literal("/s") || !digits(2) || !literal("/")) return false;
  size_t level = 0;
  while (level < path.size() && path[level] >= '0' && path[level] <= '9') ++level;
  return level > 0 && digits(level) && path == "/cells";
}

}  // namespace ropecast
