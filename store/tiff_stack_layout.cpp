#include "store/tiff_stack_layout.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "core/header_text.h"
#include "core/number_text.h"
#include "store/xml_reading.h"

namespace ropecast {
namespace {

std::optional<double> positiveNumber(std::string_view text) {
  const auto n = parseWholeNumber<double>(trimBlanks(text));
  if (!n || !std::isfinite(*n) || !(*n > 0.0)) return std::nullopt;
  return n;
}

std::optional<uint64_t> count(std::string_view text) {
  const auto n = parseWholeNumber<uint64_t>(trimBlanks(text));
  if (!n || *n == 0) return std::nullopt;
  return n;
}

// The attributes of the first Pixels element of OME-XML, by name, and the names of its Channel elements
// (empty for one without a Name); empty when there is none. A problem stops the parser (exceptions must not
// cross expat's frames).
class OmePixelsReader {
 public:
  std::map<std::string, std::string> read(std::string_view xml) {
    const XmlParser parser = makeXmlParser(*this);
    if (!parser) return {};
    parser_ = parser.get();
    XML_Parse(parser_, xml.data(), int(xml.size()), XML_TRUE);
    return omeRoot_ ? pixels_ : std::map<std::string, std::string>{};
  }
  const std::vector<std::string>& channelNames() const { return channelNames_; }

  void startElement(std::string_view name, const XML_Char** attributes) {
    const int depth = depth_++;
    if (depth == 0) omeRoot_ = name == "OME" || name.ends_with(":OME");
    if (!omeRoot_) return;
    if (pixelsDepth_ < 0 && (name == "Pixels" || name.ends_with(":Pixels"))) {
      pixelsDepth_ = depth;
      for (size_t i = 0; attributes[i]; i += 2) pixels_[attributes[i]] = attributes[i + 1];
    } else if (pixelsDepth_ >= 0 && depth == pixelsDepth_ + 1 &&
               (name == "Channel" || name.ends_with(":Channel"))) {
      channelNames_.emplace_back();
      for (size_t i = 0; attributes[i]; i += 2)
        if (std::string_view(attributes[i]) == "Name") channelNames_.back() = attributes[i + 1];
    }
  }
  void endElement(std::string_view) {
    if (--depth_ == pixelsDepth_) XML_StopParser(parser_, XML_FALSE);  // the first image's Pixels end
  }

 private:
  XML_Parser parser_ = nullptr;
  int depth_ = 0, pixelsDepth_ = -1;
  bool omeRoot_ = false;
  std::map<std::string, std::string> pixels_;
  std::vector<std::string> channelNames_;
};

}  // namespace

std::optional<TiffStackLayout> imageJLayout(std::string_view description, double xResolution,
                                            double yResolution, uint64_t pages) {
  if (!description.starts_with("ImageJ=")) return std::nullopt;
  std::map<std::string, std::string, std::less<>> fields;
  for (std::string_view rest = description; !rest.empty();) {
    const size_t end = rest.find('\n');
    const std::string_view line = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    if (const size_t equals = line.find('='); equals != std::string_view::npos)
      fields[std::string(trimBlanks(line.substr(0, equals)))] =
          std::string(trimBlanks(line.substr(equals + 1)));
  }
  const auto field = [&](const char* name) -> std::string_view {
    const auto it = fields.find(name);
    return it == fields.end() ? std::string_view() : std::string_view(it->second);
  };
  TiffStackLayout layout;
  layout.writer = "ImageJ";
  layout.channels = count(field("channels")).value_or(1);
  layout.frames = count(field("frames")).value_or(1);
  if (layout.channels > pages || layout.frames > pages / layout.channels) return std::nullopt;  // no overflow
  const uint64_t perSlice = layout.channels * layout.frames;
  layout.slices = count(field("slices")).value_or(pages / perSlice);
  if (layout.slices == 0 || layout.slices > pages / perSlice || layout.slices * perSlice != pages)
    return std::nullopt;
  // ImageJ's order: channels, then slices, then frames.
  layout.sliceStride = layout.channels;
  layout.frameStride = layout.channels * layout.slices;
  layout.unit = std::string(field("unit"));
  if (layout.unit == "\\u00B5m") layout.unit = "µm";  // ImageJ escapes the micro sign
  if (xResolution > 0.0 && yResolution > 0.0 && std::isfinite(xResolution) && std::isfinite(yResolution)) {
    const double x = 1.0 / xResolution, y = 1.0 / yResolution;
    layout.spacing = glm::dvec3(x, y, positiveNumber(field("spacing")).value_or(x));
  } else if (const auto z = positiveNumber(field("spacing"))) {
    layout.spacing = glm::dvec3(1.0, 1.0, *z);
  }
  return layout;
}

std::optional<TiffStackLayout> omeLayout(std::string_view description, uint64_t pages) {
  if (description.find("<OME") == std::string_view::npos) return std::nullopt;
  OmePixelsReader reader;
  const std::map<std::string, std::string> pixels = reader.read(description);
  const auto attribute = [&](const char* name) -> std::string_view {
    const auto it = pixels.find(name);
    return it == pixels.end() ? std::string_view() : std::string_view(it->second);
  };
  const auto z = count(attribute("SizeZ")), c = count(attribute("SizeC")), t = count(attribute("SizeT"));
  const std::string_view order = attribute("DimensionOrder");
  if (!z || !c || !t || order.size() != 5 || !order.starts_with("XY") ||
      order.find('Z', 2) == std::string_view::npos)
    return std::nullopt;
  TiffStackLayout layout;
  layout.writer = "OME-TIFF";
  layout.slices = *z, layout.channels = *c, layout.frames = *t;
  const std::vector<std::string>& names = reader.channelNames();
  if (names.size() == layout.channels && std::ranges::none_of(names, &std::string::empty))
    layout.channelNames = names;
  if (layout.slices > pages || layout.channels > pages / layout.slices ||
      layout.frames > pages / (layout.slices * layout.channels) ||
      layout.slices * layout.channels * layout.frames != pages)
    return std::nullopt;  // checked in steps, so that no product overflows
  // Pages follow the dimension order after XY, its first letter fastest: each one's stride is the product of
  // the sizes before it.
  uint64_t stride = 1;
  bool seen[3] = {};
  for (const char dimension : order.substr(2)) {
    const size_t which = dimension == 'Z' ? 0 : dimension == 'C' ? 1 : dimension == 'T' ? 2 : 3;
    if (which == 3 || seen[which]) return std::nullopt;
    seen[which] = true;
    const uint64_t sizes[] = {layout.slices, layout.channels, layout.frames};
    uint64_t* const strides[] = {&layout.sliceStride, &layout.channelStride, &layout.frameStride};
    *strides[which] = stride;
    stride *= sizes[which];
  }
  const auto x = positiveNumber(attribute("PhysicalSizeX")), y = positiveNumber(attribute("PhysicalSizeY"));
  if (x && y) {
    layout.spacing = glm::dvec3(*x, *y, positiveNumber(attribute("PhysicalSizeZ")).value_or(*x));
    const std::string_view unit = attribute("PhysicalSizeXUnit");
    layout.unit = unit.empty() ? "µm" : std::string(unit);  // OME's default unit
  }
  return layout;
}

}  // namespace ropecast
