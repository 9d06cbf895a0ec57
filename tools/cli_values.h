// Parsing of the command line's compound values ("X,Y,Z", "WxH", "512M"), shared by every subcommand.
// Each throws ropecast::Error naming the option and what was expected. Main thread.
#pragma once

#include <cstdint>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace ropecast::tools {

// "1.5,2,3" -> (1.5, 2, 3).
glm::dvec3 parseTriple(const std::string& text, const std::string& option);
// "301,370,316" -> positive integers.
glm::u32vec3 parseDims(const std::string& text, const std::string& option);
// "512x512" -> (512, 512), each in [1, 16384].
glm::u32vec2 parseImageSize(const std::string& text, const std::string& option);
// "1073741824", "512M", "2G", "64K", "1.5G" (binary units, optional "iB"/"B") -> bytes.
uint64_t parseBytes(const std::string& text, const std::string& option);

}  // namespace ropecast::tools
