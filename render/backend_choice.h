// What `--backend auto` stands for on a GL renderer. Pure functions of the GL_RENDERER string
// (GlContextInfo::renderer), so that a CPU test covers them; any thread.
#pragma once

#include <string_view>

#include "core/render_params.h"

namespace ropecast {

// Whether GL_RENDERER names a software rasterizer: Mesa's llvmpipe, softpipe and swrast, SwiftShader, or any
// renderer that calls itself software.
bool isSoftwareRenderer(std::string_view glRenderer);

// Auto -> Fragment on a software rasterizer (llvmpipe runs the fragment tiles faster than the compute
// dispatch), Compute on hardware GPUs (data-center GPUs run pixel shaders on a few units only;
// docs/BENCHMARKS.md). Any other value is returned as it is.
RenderBackend resolveBackend(RenderBackend requested, std::string_view glRenderer);

}  // namespace ropecast
