// What the XML readers share (VTK image data headers, store/vti_header.h; BigDataViewer's dataset XML,
// store/bdv_xml.h): an expat parser that calls a handler object's member functions, and an element's
// attributes. Exceptions must not cross expat's C frames: handlers keep a problem and stop the parser. Any
// thread (a parser per call).
#pragma once

#include <expat.h>

#include <memory>
#include <optional>
#include <string_view>

namespace ropecast {

using XmlParser = std::unique_ptr<XML_ParserStruct, decltype(&XML_ParserFree)>;

// A parser that calls handler.startElement(name, attributes) and handler.endElement(name), and
// handler.characters(text) where the handler has it; null where expat cannot make one.
template <typename Handler>
XmlParser makeXmlParser(Handler& handler) {
  XmlParser parser(XML_ParserCreate(nullptr), &XML_ParserFree);
  if (!parser) return parser;
  XML_SetUserData(parser.get(), &handler);
  XML_SetElementHandler(
      parser.get(),
      [](void* self, const XML_Char* name, const XML_Char** attributes) {
        static_cast<Handler*>(self)->startElement(name, attributes);
      },
      [](void* self, const XML_Char* name) { static_cast<Handler*>(self)->endElement(name); });
  if constexpr (requires(Handler & h) { h.characters(std::string_view()); })
    XML_SetCharacterDataHandler(parser.get(), [](void* self, const XML_Char* s, int length) {
      static_cast<Handler*>(self)->characters(std::string_view(s, size_t(length)));
    });
  return parser;
}

// An attribute of an element as expat gives them (name, value, ..., null); nullopt when absent.
inline std::optional<std::string_view> xmlAttribute(const XML_Char** attributes, std::string_view name) {
  for (size_t i = 0; attributes[i]; i += 2)
    if (name == attributes[i]) return std::string_view(attributes[i + 1]);
  return std::nullopt;
}

}  // namespace ropecast
