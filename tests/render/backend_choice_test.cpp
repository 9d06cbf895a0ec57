// What `--backend auto` resolves to for the GL_RENDERER strings of real drivers.
#include "render/backend_choice.h"

#include <gtest/gtest.h>

namespace ropecast {
namespace {

TEST(BackendChoice, AutoIsFragmentOnSoftwareRasterizers) {
  for (const char* renderer :
       {"llvmpipe (LLVM 15.0.6, 256 bits)", "softpipe", "Mesa X11 swrast", "Software Rasterizer",
        "SwiftShader Device (Subzero)", "zink Vulkan 1.3(llvmpipe (LLVM 15.0.6, 256 bits) (MESA_LLVMPIPE))",
        "LLVMPIPE"}) {
    EXPECT_TRUE(isSoftwareRenderer(renderer)) << renderer;
    EXPECT_EQ(resolveBackend(RenderBackend::Auto, renderer), RenderBackend::Fragment) << renderer;
  }
}

TEST(BackendChoice, AutoIsComputeOnHardwareGpus) {
  for (const char* renderer :
       {"NVIDIA H100 80GB HBM3/PCIe/SSE2", "NVIDIA H200/PCIe/SSE2", "NVIDIA GeForce RTX 4090/PCIe/SSE2",
        "AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.6, DRM 3.54, 6.5.0)",
        "Mesa Intel(R) UHD Graphics 630 (CFL GT2)", ""}) {
    EXPECT_FALSE(isSoftwareRenderer(renderer)) << renderer;
    EXPECT_EQ(resolveBackend(RenderBackend::Auto, renderer), RenderBackend::Compute) << renderer;
  }
}

TEST(BackendChoice, ExplicitBackendsStayAsTheyAre) {
  for (const char* renderer : {"llvmpipe (LLVM 15.0.6, 256 bits)", "NVIDIA H100 80GB HBM3/PCIe/SSE2"})
    for (RenderBackend b : {RenderBackend::Fragment, RenderBackend::Compute, RenderBackend::Brute})
      EXPECT_EQ(resolveBackend(b, renderer), b) << renderer << " " << renderBackendName(b);
}

TEST(BackendChoice, NamesRoundTrip) {
  for (const auto& [name, backend] : kRenderBackendNames) EXPECT_EQ(renderBackendName(backend), name);
}

}  // namespace
}  // namespace ropecast
