#include "render/upload_pacer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ropecast {

namespace {
// Frames whose uploads took less than this are too short to time (clock resolution, fixed call costs); their
// throughput is counted as if they had taken this long.
constexpr double kMinMeasuredMs = 0.05;
// How fast the estimate follows a faster measurement (a slower one is taken at once).
constexpr double kSpeedUpWeight = 0.25;
}  // namespace

UploadPacer::UploadPacer(double timeBudgetMs, uint64_t brickBytes)
    : timeBudgetMs_(timeBudgetMs), brickBytes_(std::max<uint64_t>(brickBytes, 1)) {}

uint64_t UploadPacer::allowanceBytes() const {
  if (!enabled()) return std::numeric_limits<uint64_t>::max();
  if (bytesPerMs_ <= 0.0) return brickBytes_;
  const double bytes = std::floor(bytesPerMs_ * timeBudgetMs_);
  if (bytes >= double(std::numeric_limits<uint64_t>::max() / 2))
    return std::numeric_limits<uint64_t>::max() / 2;
  return std::max<uint64_t>(uint64_t(bytes), brickBytes_);
}

void UploadPacer::record(uint64_t bytes, double ms) {
  if (bytes == 0) return;
  const double rate = double(bytes) / std::max(ms, kMinMeasuredMs);
  if (bytesPerMs_ <= 0.0 || rate < bytesPerMs_)
    bytesPerMs_ = rate;
  else
    bytesPerMs_ += kSpeedUpWeight * (rate - bytesPerMs_);
}

}  // namespace ropecast
