// FrameStats as `ropecast render --stats` writes it.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "render/frame_stats.h"

namespace ropecast {
namespace {

TEST(FrameStats, WritesOneJsonObjectPerLine) {
  FrameStats s;
  s.frame = 3;
  s.refineMs = 1.5;
  s.cacheHits = 4;
  s.gpuPoolUsedBytes = 1 << 20;
  s.converged = true;
  s.backend = RenderBackend::Brute;
  s.stage = RenderBackend::Compute;
  const std::string line = toJsonLine(s);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(line);
  EXPECT_EQ(j.at("frame"), 3);
  EXPECT_EQ(j.at("refine_ms"), 1.5);
  EXPECT_EQ(j.at("cache_hits"), 4);
  EXPECT_EQ(j.at("gpu_pool_used"), 1 << 20);
  EXPECT_EQ(j.at("converged"), true);
  EXPECT_EQ(j.at("backend"), "brute");
  EXPECT_EQ(j.at("stage"), "compute");
  for (const char* field :
       {"frame_ms", "raycast_ms", "index_ms", "leaves", "bricks_resident", "bricks_uploaded",
        "bytes_uploaded", "requests_pending", "cache_misses", "cpu_cache_bytes"}) {
    EXPECT_TRUE(j.contains(field)) << field;
  }
}

}  // namespace
}  // namespace ropecast
