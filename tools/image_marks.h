// Orientation marks drawn into a rendered image (`ropecast render --marks`), as the viewer draws them over
// its view: at the middle of each edge the sides of the patient that edge faces (edgeLetters,
// tools/view_outline.h), and in the bottom-left corner the volume's x, y and z axes (red, green, blue) as the
// camera turns them (axesTriad). Letters come from a small pixel font of their own, scaled with the image
// (one font pixel per kMarkScalePixels of its smaller side, at least one), light on a dark outline so that
// they read on any background. GL-free; any thread.
#pragma once

#include <cstdint>
#include <string>

#include "core/camera.h"
#include "core/float_image.h"
#include "core/orientation.h"

namespace ropecast::tools {

inline constexpr uint32_t kMarkScalePixels = 200;

// Draws the marks of a view of `camera` (in the world) of a volume whose axes point along `axes` into `image`
// (RGB or RGBA, values in [0, 1]): color set where a mark lies, alpha 1 there.
void drawOrientationMarks(FloatImage& image, const Camera& camera, const AxisDirections& axes);

// The width and height in pixels of `text` as drawMarkText draws it at `scale` (font pixels to image pixels),
// without its outline. Characters the font lacks take a space.
uint32_t markTextWidth(const std::string& text, uint32_t scale);
uint32_t markTextHeight(uint32_t scale);

// Draws `text` with its top-left corner at (x, y) in `color` (RGB), on an outline `scale` pixels wide in
// `outline`; parts outside the image are cut away. The font holds the letters the marks use: A, I, L, P, R, S
// and x, y, z.
void drawMarkText(FloatImage& image, const std::string& text, int64_t x, int64_t y, uint32_t scale,
                  const float color[3], const float outline[3]);

}  // namespace ropecast::tools
