// `ropecast compare A B`: PSNR and absolute differences of two images (PNG/EXR, read as floats in [0, 1] for
// 8-bit files), e.g. an adaptive render against `render --reference` (bench/quality_vs_reference.sh).
// Prints one JSON line; with --min-psnr, exits 3 when the PSNR is lower (as verify when a check fails; 1 is
// an image that cannot be read). GL-free (reference/).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "reference/image_compare.h"
#include "reference/image_io.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"
#include "tools/command.h"

namespace ropecast::tools {
namespace {

constexpr int kBelowMinPsnr = 3;  // README.md "Exit status"

struct CompareOptions {
  std::string a, b;
  std::optional<uint32_t> channels;  // default: RGB, or the one channel of two depth images
  std::optional<double> minPsnr;
};

// JSON has no infinity: "inf" and "-inf" as strings, which float() in Python and jq's tonumber read back.
nlohmann::json number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

int runCompare(const CompareOptions& o) {
  const FloatImage a = readImage(o.a), b = readImage(o.b);
  if (a.width != b.width || a.height != b.height)
    throw Error("compare: " + o.a + " is " + std::to_string(a.width) + "x" + std::to_string(a.height) + ", " +
                o.b + " is " + std::to_string(b.width) + "x" + std::to_string(b.height));
  // RGB; one channel when an image has fewer than three (a depth image: gray and alpha are not RGB either).
  uint32_t channels = o.channels.value_or(std::min(a.channels, b.channels) >= 3 ? 3u : 1u);
  if (!o.channels && a.channels != b.channels && channels < 3)
    throw Error("compare: " + o.a + " has " + std::to_string(a.channels) + " channel(s), " + o.b + " has " +
                std::to_string(b.channels) + "; give --channels N to compare the first N");
  for (const auto& [path, image] : {std::pair{&o.a, &a}, std::pair{&o.b, &b}})
    if (channels > image->channels)
      throw UsageError("compare: --channels " + std::to_string(channels) + ": " + *path + " has " +
                       std::to_string(image->channels) + " channel(s)");
  const ImageDifference d = compareImages(a.pixels, a.channels, b.pixels, b.channels, channels);
  nlohmann::json j{{"psnr_db", number(d.psnrDb)},
                   {"max_abs", number(d.maxAbs)},
                   {"mean_abs", number(d.meanAbs)},
                   {"channels", channels},
                   {"pixels", a.width * a.height}};
  std::printf("%s\n", j.dump().c_str());
  return o.minPsnr && d.psnrDb < *o.minPsnr ? kBelowMinPsnr : 0;
}

const CommandRegistration compareCommand("compare", 70, [](CLI::App& app) -> std::function<int()> {
  auto o = std::make_shared<CompareOptions>();
  app.description("PSNR (peak 1) and absolute differences of two images of the same size, as one JSON line");
  app.add_option("a", o->a, "first image (PNG, EXR, ...)")->required();
  app.add_option("b", o->b, "second image")->required();
  app.add_option(
         "--channels", o->channels,
         "channels compared: 3 = RGB, 4 = RGBA, 1 = the first (default: 3; 1 when an image has fewer, "
         "such as a depth EXR)")
      ->transform(integerRange(1, 4));
  app.add_option("--min-psnr", o->minPsnr, "exit with status 3 when the PSNR is below this (dB)")
      ->check(finiteIn(0.0, HUGE_VAL));
  return [o] { return runCompare(*o); };
});

}  // namespace
}  // namespace ropecast::tools
