// libFuzzer target for the JSON files users write by hand: camera paths (core/camera_path.h, `render --path`,
// the viewer's saved cameras) and transfer functions (core/transfer_function.h, `--tf FILE`). The first byte
// picks the parser, the rest is the file. Any input must either parse into something that keeps the parser's
// promises (keyframes sorted by time; sampled cameras finite, with a finite frame wherever eye and target
// differ; a transfer function whose table holds colors and opacities in [0, 1]) or throw ropecast::Error;
// never crash, hang or throw anything else.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <glm/common.hpp>

#include "core/camera.h"
#include "core/camera_path.h"
#include "core/error.h"
#include "core/sample_type.h"
#include "core/transfer_function.h"

namespace {

bool finite(glm::dvec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void checkCameraPath(const std::string& text) {
  const ropecast::CameraPath path = ropecast::parseCameraPath(text, "fuzz.json");
  if (path.keyframes.empty()) std::abort();
  for (size_t i = 1; i < path.keyframes.size(); ++i)
    if (!(path.keyframes[i - 1].time <= path.keyframes[i].time)) std::abort();
  const glm::dvec3 boxMin(0.0), boxMax(64.0, 48.0, 40.0);
  for (const uint32_t frames : {1u, 2u, 7u}) {
    for (uint32_t f = 0; f < frames; ++f) {
      const ropecast::Camera c = ropecast::sampleCameraPath(path, f, frames, boxMin, boxMax);
      if (!finite(c.eye) || !finite(c.target)) std::abort();
      if (!(c.fovYDeg > 0.0 && c.fovYDeg < 180.0)) std::abort();
      // Eye and target may meet between two keyframes, which `render --path` checks before its first frame;
      // otherwise the frame must be finite (an up that the interpolation turned parallel to the view is
      // replaced).
      if (!ropecast::viewProblem(c.eye, c.target).empty()) continue;
      const ropecast::CameraFrame frame = ropecast::cameraFrame(c);
      if (!finite(frame.forward) || !finite(frame.right) || !finite(frame.up)) std::abort();
    }
  }
}

void checkTransferFunction(const std::string& text) {
  const ropecast::TransferFunction tf = ropecast::TransferFunction::fromJson(text, "fuzz.json");
  const ropecast::ValueMapping mapping = ropecast::valueMappingFor(ropecast::SampleType::Int16, 0.0, 0.0);
  const ropecast::TfTable table = ropecast::TfTable::bake(tf, mapping, 65535, 256);
  for (const glm::vec4& rgba : table.entries())
    for (int i = 0; i < 4; ++i)
      if (!(rgba[i] >= 0.0f && rgba[i] <= 1.0f)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (data[0] % 2 == 0)
      checkCameraPath(text);
    else
      checkTransferFunction(text);
  } catch (const ropecast::Error&) {
    // Malformed input is expected to be rejected this way.
  }
  return 0;
}
