#include "tools/image_marks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "tools/view_outline.h"

namespace ropecast::tools {
namespace {

constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

// The font: each glyph's rows, top first, '#' a pixel.
struct Glyph {
  char c;
  std::array<std::string_view, kGlyphHeight> rows;
};
constexpr Glyph kGlyphs[] = {
    {'A', {".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
    {'I', {"#####", "..#..", "..#..", "..#..", "..#..", "..#..", "#####"}},
    {'L', {"#....", "#....", "#....", "#....", "#....", "#....", "#####"}},
    {'P', {"####.", "#...#", "#...#", "####.", "#....", "#....", "#...."}},
    {'R', {"####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#"}},
    {'S', {".####", "#....", "#....", ".###.", "....#", "....#", "####."}},
    {'x', {".....", ".....", "#...#", ".#.#.", "..#..", ".#.#.", "#...#"}},
    {'y', {".....", ".....", "#...#", "#...#", ".####", "....#", ".###."}},
    {'z', {".....", ".....", "#####", "...#.", "..#..", ".#...", "#####"}},
};

const Glyph* glyphOf(char c) {
  for (const Glyph& g : kGlyphs)
    if (g.c == c) return &g;
  return nullptr;
}

// Sets pixel (x, y) to `color` with alpha 1, where it lies in the image.
void setPixel(FloatImage& image, int64_t x, int64_t y, const float color[3]) {
  if (x < 0 || y < 0 || x >= int64_t(image.width) || y >= int64_t(image.height)) return;
  for (uint32_t c = 0; c < 3; ++c) image.at(uint32_t(x), uint32_t(y), c) = color[c];
  if (image.channels > 3) image.at(uint32_t(x), uint32_t(y), 3) = 1.0f;
}

// Calls f(x, y) for every image pixel a glyph pixel of `text` covers, drawn from (x, y) at `scale`.
template <typename F>
void forTextPixels(const std::string& text, int64_t x, int64_t y, uint32_t scale, F&& f) {
  for (size_t i = 0; i < text.size(); ++i) {
    const Glyph* glyph = glyphOf(text[i]);
    if (!glyph) continue;
    const int64_t left = x + int64_t(i) * kGlyphAdvance * scale;
    for (int row = 0; row < kGlyphHeight; ++row)
      for (int column = 0; column < kGlyphWidth; ++column)
        if (glyph->rows[size_t(row)][size_t(column)] == '#')
          for (uint32_t dy = 0; dy < scale; ++dy)
            for (uint32_t dx = 0; dx < scale; ++dx) f(left + column * scale + dx, y + row * scale + dy);
  }
}

// A segment from a to b `width` pixels wide (pixel centers within half the width of it), in `color`.
void drawSegment(FloatImage& image, glm::dvec2 a, glm::dvec2 b, double width, const float color[3]) {
  const double reach = 0.5 * width;
  const int64_t x0 = int64_t(std::floor(std::min(a.x, b.x) - reach)),
                x1 = int64_t(std::ceil(std::max(a.x, b.x) + reach));
  const int64_t y0 = int64_t(std::floor(std::min(a.y, b.y) - reach)),
                y1 = int64_t(std::ceil(std::max(a.y, b.y) + reach));
  const glm::dvec2 d = b - a;
  const double lengthSquared = glm::dot(d, d);
  for (int64_t y = y0; y <= y1; ++y)
    for (int64_t x = x0; x <= x1; ++x) {
      const glm::dvec2 p(double(x) + 0.5, double(y) + 0.5);
      const double t = lengthSquared > 0.0 ? std::clamp(glm::dot(p - a, d) / lengthSquared, 0.0, 1.0) : 0.0;
      if (glm::length(p - (a + t * d)) <= reach) setPixel(image, x, y, color);
    }
}

}  // namespace

uint32_t markTextWidth(const std::string& text, uint32_t scale) {
  return text.empty() ? 0 : uint32_t((text.size() - 1) * kGlyphAdvance + kGlyphWidth) * scale;
}

uint32_t markTextHeight(uint32_t scale) {
  return kGlyphHeight * scale;
}

void drawMarkText(FloatImage& image, const std::string& text, int64_t x, int64_t y, uint32_t scale,
                  const float color[3], const float outline[3]) {
  const int64_t ring = scale;
  forTextPixels(text, x, y, scale, [&](int64_t px, int64_t py) {
    for (int64_t dy = -ring; dy <= ring; ++dy)
      for (int64_t dx = -ring; dx <= ring; ++dx) setPixel(image, px + dx, py + dy, outline);
  });
  forTextPixels(text, x, y, scale, [&](int64_t px, int64_t py) { setPixel(image, px, py, color); });
}

void drawOrientationMarks(FloatImage& image, const Camera& camera, const AxisDirections& axes) {
  if (image.channels < 3) throw Error("orientation marks: the image has no color channels");
  const uint32_t scale = std::max(1u, std::min(image.width, image.height) / kMarkScalePixels);
  const int64_t width = image.width, height = image.height, margin = 4 * scale;
  const float letterColor[3] = {0.92f, 0.92f, 0.92f}, outline[3] = {0.05f, 0.05f, 0.05f};
  const int64_t textHeight = markTextHeight(scale);
  const auto textWidth = [&](const std::string& s) { return int64_t(markTextWidth(s, scale)); };

  const EdgeLetters letters = edgeLetters(camera);
  drawMarkText(image, letters.left, margin, (height - textHeight) / 2, scale, letterColor, outline);
  drawMarkText(image, letters.right, width - margin - textWidth(letters.right), (height - textHeight) / 2,
               scale, letterColor, outline);
  drawMarkText(image, letters.top, (width - textWidth(letters.top)) / 2, margin, scale, letterColor, outline);
  drawMarkText(image, letters.bottom, (width - textWidth(letters.bottom)) / 2, height - margin - textHeight,
               scale, letterColor, outline);

  // The volume's axes, the farthest first, in the bottom-left corner (the letters hold the edges' middles).
  const double length = 18.0 * scale, labelGap = 4.0 * scale + 0.5 * textHeight;
  const glm::dvec2 origin(double(margin) + length + labelGap, double(height - margin) - length - labelGap);
  const std::array<TriadAxis, 3> triad = axesTriad(camera, axes);
  std::array<int, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return triad[a].towardEye < triad[b].towardEye; });
  static constexpr float kAxisColors[3][3] = {
      {0.92f, 0.35f, 0.31f}, {0.35f, 0.82f, 0.35f}, {0.39f, 0.59f, 1.0f}};
  for (const int a : order) {
    const glm::dvec2 tip = origin + length * triad[size_t(a)].screen;
    drawSegment(image, origin, tip, double(scale), kAxisColors[a]);
    const glm::dvec2 label = origin + (length + labelGap) * triad[size_t(a)].screen;
    const std::string name(1, "xyz"[a]);
    drawMarkText(image, name, int64_t(std::lround(label.x - 0.5 * textWidth(name))),
                 int64_t(std::lround(label.y - 0.5 * textHeight)), scale, kAxisColors[a], outline);
  }
}

}  // namespace ropecast::tools
