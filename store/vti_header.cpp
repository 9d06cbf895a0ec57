#include "store/vti_header.h"

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "core/error.h"
#include "core/header_text.h"
#include "core/number_text.h"
#include "store/volume_source.h"
#include "store/xml_reading.h"

namespace ropecast {
namespace {

// The types read, for messages.
constexpr std::string_view kVtiTypeList = "Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32 or Float64";

std::optional<SampleType> parseVtiType(std::string_view name) {
  struct TypeName {
    std::string_view name;
    SampleType type;
  };
  static constexpr TypeName kTypes[] = {{"Int8", SampleType::Int8},       {"UInt8", SampleType::UInt8},
                                        {"Int16", SampleType::Int16},     {"UInt16", SampleType::UInt16},
                                        {"Int32", SampleType::Int32},     {"UInt32", SampleType::UInt32},
                                        {"Float32", SampleType::Float32}, {"Float64", SampleType::Float64}};
  for (const TypeName& entry : kTypes)
    if (entry.name == name) return entry.type;
  return std::nullopt;
}

// What the expat callbacks gather: the elements on the way to the point data's active array and to the
// appended data. A problem is kept and the parser stopped, since exceptions must not cross expat's C frames.
class VtiParser {
 public:
  VtiParser(std::string_view text, const std::string& fileName) : text_(text), fileName_(fileName) {}

  VtiHeader parse() {
    const XmlParser parser = makeXmlParser(*this);
    if (!parser) fail("cannot create an XML parser");
    parser_ = parser.get();
    const XML_Status status = XML_Parse(parser_, text_.data(), int(text_.size()), XML_FALSE);
    if (!problem_.empty()) fail(problem_);
    if (status == XML_STATUS_ERROR && XML_GetErrorCode(parser_) != XML_ERROR_ABORTED)
      fail("not well-formed XML at line " + std::to_string(XML_GetCurrentLineNumber(parser_)) + " (" +
           XML_ErrorString(XML_GetErrorCode(parser_)) + ")");
    if (!done_) {
      if (!arrayFound_)
        fail("no point data array within the first " + std::to_string(text_.size()) + " bytes");
      fail("no AppendedData element within the first " + std::to_string(text_.size()) +
           " bytes, where the array's data is");
    }
    return header_;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("VTK image data (.vti) header of " + fileName_ + ": " + what);
  }
  void stop(const std::string& problem) {
    if (problem_.empty()) problem_ = problem;
    XML_StopParser(parser_, XML_FALSE);
  }
  void finish() {
    done_ = true;
    XML_StopParser(parser_, XML_FALSE);
  }

  // The end of the current start tag, in the text.
  uint64_t afterCurrentTag() const {
    return uint64_t(XML_GetCurrentByteIndex(parser_)) + uint64_t(XML_GetCurrentByteCount(parser_));
  }

  std::optional<std::vector<double>> numbers(std::string_view text, size_t count) const {
    const auto words = splitWords(text);
    if (words.size() != count) return std::nullopt;
    std::vector<double> out;
    for (std::string_view word : words) {
      const auto n = parseWholeNumber<double>(word);
      if (!n || !std::isfinite(*n)) return std::nullopt;
      out.push_back(*n);
    }
    return out;
  }

 public:  // expat's callbacks (store/xml_reading.h)
  void startElement(std::string_view name, const XML_Char** attributes) {
    path_.emplace_back(name);
    if (!problem_.empty() || done_) return;
    if (path_.size() == 1) {
      if (name != "VTKFile") return stop("expected a VTKFile element first, got '" + std::string(name) + "'");
      vtkFile(attributes);
    } else if (name == "ImageData" && path_.size() == 2) {
      imageData(attributes);
    } else if (name == "Piece" && path_.size() == 3) {
      piece(attributes);
    } else if (name == "PointData" && path_.size() == 4 && pieces_ == 1) {
      scalars_ = xmlAttribute(attributes, "Scalars").value_or("");
      inPointData_ = true;
    } else if (name == "DataArray" && inPointData_ && path_.size() == 5 && !arrayFound_) {
      dataArray(attributes);
    } else if (name == "AppendedData" && path_.size() == 2 && appended_) {
      appendedData(attributes);
    }
  }

  void endElement(std::string_view name) {
    path_.pop_back();
    if (!problem_.empty() || done_) return;
    if (name == "PointData" && inPointData_) {
      inPointData_ = false;
      if (!arrayFound_)
        stop(scalars_.empty() ? "the point data holds no DataArray"
                              : "the point data holds no DataArray named '" + scalars_ + "' (its Scalars)");
    }
  }

 private:
  void vtkFile(const XML_Char** attributes) {
    const std::string_view type = xmlAttribute(attributes, "type").value_or("");
    if (type != "ImageData")
      return stop("VTKFile type '" + std::string(type) +
                  "': only ImageData (.vti) is read; other datasets are not volumes of samples on a grid");
    const std::string_view order = xmlAttribute(attributes, "byte_order").value_or("LittleEndian");
    if (order != "LittleEndian" && order != "BigEndian")
      return stop("byte_order '" + std::string(order) + "': expected LittleEndian or BigEndian");
    header_.bigEndian = order == "BigEndian";
    const std::string_view headerType = xmlAttribute(attributes, "header_type").value_or("UInt32");
    if (headerType != "UInt32" && headerType != "UInt64")
      return stop("header_type '" + std::string(headerType) + "': expected UInt32 or UInt64");
    header_.headerWordBytes = headerType == "UInt64" ? 8 : 4;
    const std::string_view compressor = xmlAttribute(attributes, "compressor").value_or("");
    if (compressor == "vtkZLibDataCompressor")
      header_.compressor = VtiCompressor::ZLib;
    else if (compressor == "vtkLZ4DataCompressor")
      header_.compressor = VtiCompressor::LZ4;
    else if (compressor == "vtkLZMADataCompressor")
      header_.compressor = VtiCompressor::LZMA;
    else if (!compressor.empty())
      return stop("compressor '" + std::string(compressor) +
                  "' is not read; save without compression or with ZLib, LZ4 or LZMA (ParaView: the "
                  "writer's Compressor Type), or as .vtk, .nrrd or .mha");
  }

  void imageData(const XML_Char** attributes) {
    const auto extent = numbers(xmlAttribute(attributes, "WholeExtent").value_or(""), 6);
    if (!extent) return stop("ImageData WholeExtent: expected 6 integers");
    std::string sizes;
    for (int axis = 0; axis < 3; ++axis) {
      const double lo = (*extent)[size_t(2 * axis)], hi = (*extent)[size_t(2 * axis + 1)];
      if (lo != std::floor(lo) || hi != std::floor(hi) || hi < lo || hi - lo >= 4294967295.0)
        return stop(
            "ImageData WholeExtent: expected 3 pairs of integers, each low <= high, less than 2^32 apart");
      sizes += std::to_string(uint64_t(hi - lo) + 1) + " ";
      wholeExtent_[size_t(2 * axis)] = lo;
      wholeExtent_[size_t(2 * axis + 1)] = hi;
    }
    const SizesText parsed = parseSizesText(sizes);
    if (!parsed.problem.empty()) return stop("ImageData WholeExtent: " + parsed.problem);
    header_.sizes = parsed.sizes;
    glm::dvec3 signedSpacing(1.0);
    if (const auto spacingText = xmlAttribute(attributes, "Spacing")) {
      const auto spacing = numbers(*spacingText, 3);
      if (!spacing || (*spacing)[0] == 0.0 || (*spacing)[1] == 0.0 || (*spacing)[2] == 0.0)
        return stop("ImageData Spacing: expected 3 non-zero numbers");
      header_.spacing = glm::dvec3(std::abs((*spacing)[0]), std::abs((*spacing)[1]), std::abs((*spacing)[2]));
      signedSpacing = glm::dvec3((*spacing)[0], (*spacing)[1], (*spacing)[2]);
    }
    glm::dmat3 direction(1.0);  // columns: where x, y and z point
    if (const auto directionText = xmlAttribute(attributes, "Direction")) {
      const auto m = numbers(*directionText, 9);
      if (!m) return stop("ImageData Direction: expected 9 numbers");
      const std::vector<double>& d = *m;
      direction = glm::dmat3(d[0], d[3], d[6], d[1], d[4], d[7], d[2], d[5], d[8]);
      const std::optional<AxisDirections> axes = axisDirectionsOf(direction[0], direction[1], direction[2]);
      header_.axes = axes.value_or(AxisDirections(1.0));
      header_.directionNotApplied = !axes;
    }
    // VTK places point (i, j, k) of the extent at Origin + Direction (i, j, k) Spacing: the first sample is
    // the WholeExtent's low corner.
    if (const auto originText = xmlAttribute(attributes, "Origin")) {
      const auto o = numbers(*originText, 3);
      if (!o) return stop("ImageData Origin: expected 3 numbers");
      const glm::dvec3 low(wholeExtent_[0], wholeExtent_[2], wholeExtent_[4]);
      header_.origin = glm::dvec3((*o)[0], (*o)[1], (*o)[2]) + direction * (low * signedSpacing);
    }
  }

  void piece(const XML_Char** attributes) {
    if (++pieces_ > 1)
      return stop(
          "several Pieces; only image data in one piece is read (ParaView: save without splitting "
          "it into pieces)");
    const auto extent = numbers(xmlAttribute(attributes, "Extent").value_or(""), 6);
    if (!extent || !std::equal(extent->begin(), extent->end(), wholeExtent_))
      stop("the Piece's Extent is not the WholeExtent; only a piece holding the whole image is read");
  }

  void dataArray(const XML_Char** attributes) {
    const std::string_view arrayName = xmlAttribute(attributes, "Name").value_or("");
    if (!scalars_.empty() && arrayName != scalars_) return;  // not the active scalars
    header_.arrayName = std::string(arrayName);
    arrayFound_ = true;
    const std::string_view type = xmlAttribute(attributes, "type").value_or("");
    const auto sampleType = parseVtiType(type);
    if (!sampleType)
      return stop("DataArray '" + header_.arrayName + "' of type '" + std::string(type) +
                  "' is not read; expected " + std::string(kVtiTypeList));
    header_.type = *sampleType;
    const std::string_view components = xmlAttribute(attributes, "NumberOfComponents").value_or("1");
    const auto count = parseWholeNumber<uint32_t>(components);
    if (!count || *count == 0 || *count > 65536)
      return stop("DataArray '" + header_.arrayName + "': NumberOfComponents '" + std::string(components) +
                  "' is not a count from 1 to 65536");
    const uint64_t componentBytes = uint64_t(header_.sizes.x) * header_.sizes.y * header_.sizes.z * 8;
    if (componentBytes > (uint64_t(1) << 62) / *count)
      return stop("DataArray '" + header_.arrayName + "': " + std::string(components) +
                  " components of the WholeExtent's samples are more than 2^62 bytes");
    header_.components = *count;
    const std::string_view format = xmlAttribute(attributes, "format").value_or("");
    if (format == "appended") {
      const auto offset = parseWholeNumber<uint64_t>(xmlAttribute(attributes, "offset").value_or(""));
      if (!offset) return stop("DataArray '" + header_.arrayName + "': appended without a valid offset");
      appended_ = true;
      arrayOffset_ = *offset;
    } else if (format == "binary") {
      header_.base64 = true;
      header_.dataStart = firstNonBlank(afterCurrentTag());
      finish();
    } else {
      stop("DataArray '" + header_.arrayName + "' of format '" + std::string(format) +
           "'; ASCII data is not read (save as binary or appended data)");
    }
  }

  void appendedData(const XML_Char** attributes) {
    const std::string_view encoding = xmlAttribute(attributes, "encoding").value_or("");
    if (encoding != "raw" && encoding != "base64")
      return stop("AppendedData encoding '" + std::string(encoding) + "': expected raw or base64");
    header_.base64 = encoding == "base64";
    const uint64_t underscore = firstNonBlank(afterCurrentTag());
    if (underscore >= text_.size() || text_[underscore] != '_')
      return stop("AppendedData does not start with '_'");
    header_.dataStart = underscore + 1 + arrayOffset_;
    finish();
  }

  uint64_t firstNonBlank(uint64_t from) const {
    while (from < text_.size() && isBlank(text_[from])) ++from;
    return from;
  }

  std::string_view text_;
  const std::string& fileName_;
  XML_Parser parser_ = nullptr;
  std::vector<std::string> path_;
  std::string problem_, scalars_;
  VtiHeader header_;
  double wholeExtent_[6] = {};
  int pieces_ = 0;
  bool inPointData_ = false, arrayFound_ = false, appended_ = false, done_ = false;
  uint64_t arrayOffset_ = 0;
};

}  // namespace

VtiHeader parseVtiHeader(std::string_view text, const std::string& fileName) {
  return VtiParser(text, fileName).parse();
}

}  // namespace ropecast
