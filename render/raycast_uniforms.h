// What the ray casters over docs/RENDERING.md share on the GL side: the uniforms of the camera (the terms of
// core/camera.h pixelRay), of the volume's spacing and of RenderParams, named as
// shaders/raycast_common.glsl and shading.glsl declare them; the shader defines of a variant; the checks of a
// request; the transfer-function texture; and the float readback of a render target. Used by RaycastPass and
// BruteForcePass. Render thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/float_image.h"
#include "core/render_params.h"
#include "core/sample_type.h"

namespace ropecast {

class ShaderProgram;
class TfTable;

void setVec3Uniform(uint32_t program, int location, glm::dvec3 v);

// "NAME value" with enough digits that the float round-trips.
std::string floatDefine(const char* name, double value);

// The defines of a ray-cast program: docs/RENDERING.md's constants (BRICK_BORDER, ISO_BISECTION_STEPS,
// DVR_SHADE_GRADIENT_THRESHOLD) and the variant of `params` (RAYCAST_MODE_ISO or _DVR, DVR_STORED_GRADIENTS).
std::vector<std::string> raycastDefines(const RenderParams& params);

// Throws ropecast::Error, prefixed by `where`, for a non-positive step, DVR without a baked transfer
// function, or a table of other than TfTable::kDefaultEntries entries.
void checkRaycastInputs(const RenderParams& params, const TfTable* tf, const char* where);

// The transfer-function texture of shading.glsl's uTransferFunction: 1D RGBA32F of TfTable::kDefaultEntries
// texels, LINEAR, CLAMP_TO_EDGE. The caller owns (deletes) it.
uint32_t createTfTexture();
void uploadTf(uint32_t texture, const TfTable& tf);

// uEye, uForward, uRight, uUp, uTanHalfFov, uAspect, uImageSize; uVolumeMax, uSpacing, uMinSpacing;
// uStepVoxels, uErt, uBackground, uIsoValue (normalized stored value), uIsoBaseColor, uAmbient, uDiffuse,
// uSpecular, uShininess.
void setSharedRaycastUniforms(const ShaderProgram& program, const Camera& camera, uint32_t width,
                              uint32_t height, glm::u32vec3 dims, glm::dvec3 spacing,
                              const ValueMapping& mapping, double storedMax, const RenderParams& params);

// A width x height texture with `channels` float channels (1: GL_RED, 4: GL_RGBA), row 0 as GL stores it.
FloatImage readFloatTexture(uint32_t texture, uint32_t width, uint32_t height, uint32_t channels,
                            const char* where);

}  // namespace ropecast
