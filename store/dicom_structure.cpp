// A walk over a DICOM file's elements that reads their headers and skips their values (PS3.5 Sect. 7):
// lengths and delimiters only, so that a folder of large images is checked at the cost of its headers.
#include "store/dicom_structure.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string_view>

namespace ropecast {
namespace {

constexpr uint32_t kUndefinedLength = 0xFFFFFFFF;
constexpr uint32_t kItem = 0xFFFEE000, kItemEnd = 0xFFFEE00D, kSequenceEnd = 0xFFFEE0DD;
constexpr uint32_t kMetaGroupLength = 0x00020000, kTransferSyntax = 0x00020010;
constexpr int kMaxNesting = 64;

// The value representations of the standard (PS3.5 Sect. 6.2), by the length field they have in explicit VR.
constexpr std::string_view kShortLengthVrs[] = {"AE", "AS", "AT", "CS", "DA", "DS", "DT",
                                                "FL", "FD", "IS", "LO", "LT", "PN", "SH",
                                                "SL", "SS", "ST", "TM", "UI", "UL", "US"};
constexpr std::string_view kLongLengthVrs[] = {"OB", "OD", "OF", "OL", "OV", "OW", "SQ",
                                               "SV", "UC", "UN", "UR", "UT", "UV"};

bool isOneOf(std::string_view vr, const auto& list) {
  return std::find(std::begin(list), std::end(list), vr) != std::end(list);
}

std::string tagText(uint32_t tag) {
  char text[16];
  std::snprintf(text, sizeof text, "(%04X,%04X)", unsigned(tag >> 16), unsigned(tag & 0xFFFF));
  return text;
}

struct Syntax {
  bool explicitVr = true, bigEndian = false;
};

struct ElementHeader {
  uint64_t at = 0;  // the byte where the element begins
  uint32_t tag = 0, length = 0;
  std::string vr;  // "" for items, delimiters and implicit VR
};

class StructureWalker {
 public:
  StructureWalker(std::ifstream& in, uint64_t size) : in_(in), size_(size) {}

  std::string problem;

  bool atEnd() const { return pos_ >= size_; }

  bool skipTo(uint64_t position) {
    in_.seekg(std::streamoff(position));
    pos_ = position;
    return bool(in_);
  }

  // The file meta group (explicit VR little endian), whose Transfer Syntax UID names the data set's syntax.
  bool metaGroup(std::string& transferSyntax) {
    while (pos_ < size_) {
      const uint64_t at = pos_;
      unsigned char group[2] = {};
      if (!bytes(reinterpret_cast<char*>(group), 2) || !skipTo(at))
        return fail(cutShort("an element's header"));
      if ((group[1] << 8 | group[0]) != 0x0002) return true;  // the data set begins
      ElementHeader h;
      if (!header(size_, Syntax{}, h)) return false;
      if (h.length == kUndefinedLength)
        return fail("the file meta element " + tagText(h.tag) + " at byte " + std::to_string(h.at) +
                    " has an undefined length");
      if (h.tag == kMetaGroupLength && h.length == 4) {
        if (size_ - pos_ < 4) return fail(cutShort("the file meta group"));
        const uint64_t groupLength = u32(Syntax{});  // the bytes of the group after this element
        if (pos_ + groupLength > size_) return fail(cutShort("the file meta group"));
      } else if (h.tag == kTransferSyntax && h.length <= 64) {
        std::string value(h.length, '\0');
        if (!bytes(value.data(), value.size())) return fail(cutShort("the Transfer Syntax UID"));
        while (!value.empty() && (value.back() == '\0' || value.back() == ' ')) value.pop_back();
        transferSyntax = value;
      } else if (!skip(h, size_)) {
        return false;
      }
    }
    return true;
  }

  // Whether the data set's first element has an explicit value representation (for files that do not say).
  bool looksExplicit() {
    char head[6] = {};
    const uint64_t at = pos_;
    const bool read = bytes(head, sizeof head);
    skipTo(at);
    const std::string_view vr(head + 4, 2);
    return read && (isOneOf(vr, kShortLengthVrs) || isOneOf(vr, kLongLengthVrs));
  }

  // The elements from here to `end`; when `delimited` (an item of undefined length), up to its delimiter.
  bool elements(uint64_t end, Syntax syntax, bool delimited, int depth) {
    if (depth > kMaxNesting)
      return fail("sequences nest deeper than " + std::to_string(kMaxNesting) + " levels at byte " +
                  std::to_string(pos_));
    while (true) {
      if (pos_ == end) return !delimited || fail(cutShort("an item of undefined length"));
      ElementHeader h;
      if (!header(end, syntax, h)) return false;
      if (delimited && h.tag == kItemEnd) return true;
      if ((h.tag >> 16) == 0xFFFE)
        return fail("the item tag " + tagText(h.tag) + " at byte " + std::to_string(h.at) +
                    " stands among elements");
      if (h.length != kUndefinedLength) {
        if (!skip(h, end)) return false;
      } else if (!items(end, h.vr == "UN" ? Syntax{false, false} : syntax, depth + 1)) {  // UN: implicit VR
        return false;
      }
    }
  }

 private:
  // The items of a sequence of undefined length (or of encapsulated pixel data), to its delimiter.
  bool items(uint64_t end, Syntax syntax, int depth) {
    while (true) {
      if (pos_ == end) return fail(cutShort("a sequence of undefined length"));
      ElementHeader h;
      if (!header(end, syntax, h)) return false;
      if (h.tag == kSequenceEnd) return true;
      if (h.tag != kItem)
        return fail("the element " + tagText(h.tag) + " at byte " + std::to_string(h.at) +
                    " stands where a sequence's item or delimiter belongs");
      if (h.length != kUndefinedLength) {
        if (!skip(h, end)) return false;
      } else if (!elements(end, syntax, true, depth)) {
        return false;
      }
    }
  }

  // Reads an element's tag, value representation and length. Items and delimiters have no value
  // representation in either syntax.
  bool header(uint64_t end, Syntax syntax, ElementHeader& h) {
    h.at = pos_;
    if (end - pos_ < 8) return fail(cutShort("an element's header"));
    const uint32_t group = u16(syntax), element = u16(syntax);
    h.tag = group << 16 | element;
    if (group == 0xFFFE || !syntax.explicitVr) {
      h.length = u32(syntax);
      return bool(in_) || fail(cutShort("an element's header"));
    }
    h.vr.resize(2);
    bytes(h.vr.data(), 2);
    if (isOneOf(h.vr, kLongLengthVrs)) {
      if (end - pos_ < 6) return fail(cutShort("an element's header"));
      u16(syntax);  // reserved
      h.length = u32(syntax);
    } else if (isOneOf(h.vr, kShortLengthVrs)) {
      h.length = u16(syntax);
    } else {
      std::string shown;
      for (const char c : h.vr) shown += c >= 0x20 && c < 0x7f ? c : '?';
      return fail("the element " + tagText(h.tag) + " at byte " + std::to_string(h.at) +
                  " has no value representation the standard defines ('" + shown + "')");
    }
    return bool(in_) || fail(cutShort("an element's header"));
  }

  bool skip(const ElementHeader& h, uint64_t end) {
    if (h.length > end - pos_)
      return fail("the element " + tagText(h.tag) + " at byte " + std::to_string(h.at) + " declares " +
                  std::to_string(h.length) + " bytes, past the end of its " +
                  (end == size_ ? "file" : "item") + " (" + std::to_string(end - pos_) +
                  " bytes left; cut short?)");
    return skipTo(pos_ + h.length) || fail(cutShort("an element's value"));
  }

  bool bytes(char* out, size_t count) {
    in_.read(out, std::streamsize(count));
    pos_ += uint64_t(std::max<std::streamsize>(in_.gcount(), 0));
    return in_.gcount() == std::streamsize(count);
  }
  uint16_t u16(Syntax syntax) {
    unsigned char b[2] = {};
    bytes(reinterpret_cast<char*>(b), 2);
    return syntax.bigEndian ? uint16_t(b[0] << 8 | b[1]) : uint16_t(b[1] << 8 | b[0]);
  }
  uint32_t u32(Syntax syntax) {
    const uint32_t first = u16(syntax), second = u16(syntax);
    return syntax.bigEndian ? first << 16 | second : second << 16 | first;
  }

  std::string cutShort(const std::string& what) const {
    return "the file ends within " + what + " (" + std::to_string(size_) + " bytes; cut short?)";
  }
  bool fail(std::string why) {
    problem = std::move(why);
    return false;
  }

  std::ifstream& in_;
  uint64_t size_;
  uint64_t pos_ = 0;
};

}  // namespace

std::string dicomStructureProblem(const std::string& path) {
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (ec || !in) return "it cannot be read";
  char head[132] = {};
  if (!in.read(head, sizeof head) || std::string_view(head + 128, 4) != "DICM")
    return "it has no DICM signature after a 128-byte preamble";
  StructureWalker walker(in, size);
  walker.skipTo(sizeof head);
  std::string transferSyntax;
  if (!walker.metaGroup(transferSyntax)) return walker.problem;
  if (walker.atEnd()) return "it ends after its file meta group, without a data set (cut short?)";
  if (transferSyntax == "1.2.840.10008.1.2.1.99") return "";  // deflated: GDCM inflates and reads it
  Syntax syntax;
  if (transferSyntax == "1.2.840.10008.1.2") syntax.explicitVr = false;
  if (transferSyntax == "1.2.840.10008.1.2.2") syntax.bigEndian = true;
  if (transferSyntax.empty()) syntax.explicitVr = walker.looksExplicit();
  if (!walker.elements(size, syntax, false, 0)) return walker.problem;
  return "";
}

}  // namespace ropecast
