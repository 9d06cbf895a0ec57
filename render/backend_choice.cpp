#include "render/backend_choice.h"

#include <algorithm>
#include <cctype>
#include <string>

namespace ropecast {

bool isSoftwareRenderer(std::string_view glRenderer) {
  std::string lower(glRenderer);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* name : {"llvmpipe", "softpipe", "swrast", "swiftshader", "software"})
    if (lower.find(name) != std::string::npos) return true;
  return false;
}

RenderBackend resolveBackend(RenderBackend requested, std::string_view glRenderer) {
  if (requested != RenderBackend::Auto) return requested;
  return isSoftwareRenderer(glRenderer) ? RenderBackend::Fragment : RenderBackend::Compute;
}

}  // namespace ropecast
