// Helpers of the GL test tier (tests/render/*_gltest.cpp): one headless GL context shared by every test of
// the process (EGL displays are per process, see render/gl_context.h), image comparison, temporary folders.
// Test thread only.
#pragma once

#include <filesystem>
#include <string>

#include "render/gl_context.h"
#include "render/image_io.h"

namespace ropecast::test {

// The process-wide context, created on first use and current on the calling (test) thread.
GlContext& sharedGlContext();

// Peak signal-to-noise ratio in dB over the first `channels` channels (peak 1.0); +inf for identical images.
double psnrDb(const FloatImage& a, const FloatImage& b, uint32_t channels = 3);
// Largest absolute difference over the first `channels` channels (inf == inf counts as 0).
double maxAbsDifference(const FloatImage& a, const FloatImage& b, uint32_t channels);

// A fresh empty folder under the system temporary folder, named after the running test.
std::filesystem::path freshTempDir();

}  // namespace ropecast::test
