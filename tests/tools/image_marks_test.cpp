// render --marks's orientation marks drawn into an image (tools/image_marks.h): a letter's pixels and its
// outline, the sides of the patient at the edges of a view from the front, the volume's axes turned with the
// camera in the bottom-left corner, alpha set only where a mark lies, and the font scaled with the image.
#include "tools/image_marks.h"

#include <gtest/gtest.h>

#include "core/orientation.h"

namespace ropecast::tools {
namespace {

FloatImage blank(uint32_t width, uint32_t height, uint32_t channels = 4) {
  FloatImage image;
  image.width = width;
  image.height = height;
  image.channels = channels;
  image.pixels.assign(size_t(width) * height * channels, 0.0f);
  return image;
}

const float kWhite[3] = {1.0f, 1.0f, 1.0f}, kGray[3] = {0.25f, 0.25f, 0.25f};

TEST(ImageMarks, ALetterIsItsGlyphOnAnOutline) {
  FloatImage image = blank(16, 12);
  drawMarkText(image, "L", 2, 2, 1, kWhite, kGray);
  // L: the left column, rows 2 to 8, and the bottom row, columns 2 to 6.
  for (uint32_t y = 2; y <= 8; ++y) EXPECT_EQ(image.at(2, y, 0), 1.0f) << y;
  for (uint32_t x = 2; x <= 6; ++x) EXPECT_EQ(image.at(x, 8, 1), 1.0f) << x;
  EXPECT_EQ(image.at(3, 4, 0), 0.25f);  // beside the column: the outline
  EXPECT_EQ(image.at(1, 9, 2), 0.25f);  // diagonal to the corner
  EXPECT_EQ(image.at(3, 4, 3), 1.0f);   // opaque where drawn
  EXPECT_EQ(image.at(6, 3, 0), 0.0f);   // the L's open side: untouched
  EXPECT_EQ(image.at(6, 3, 3), 0.0f);
  EXPECT_EQ(image.at(9, 8, 0), 0.0f);  // past the outline
  EXPECT_EQ(markTextWidth("L", 1), 5u);
  EXPECT_EQ(markTextWidth("RA", 2), 22u);  // two glyphs of 5, a column apart, doubled
  EXPECT_EQ(markTextHeight(3), 21u);
  // Parts outside the image are cut away; a character the font lacks is a space.
  drawMarkText(image, "?S", 4, -3, 1, kWhite, kGray);
  EXPECT_EQ(image.at(12, 0, 0), 1.0f);  // S's row 3 (".###.") at x = 4 + 6 + 1..3, its top cut away
  EXPECT_EQ(image.at(10, 0, 0), 0.25f);
}

// From the front (LPS: the eye toward -y), the patient's right lies on the image's left.
TEST(ImageMarks, AViewFromTheFrontIsLetteredAndItsAxesDrawn) {
  const uint32_t width = 400, height = 300, scale = 300 / kMarkScalePixels;  // 1
  const Camera front =
      anatomicalViewCamera(AnatomicalView::Anterior, 3.0, glm::dvec3(0.0), glm::dvec3(10.0), 40.0);
  FloatImage marked = blank(width, height);
  drawOrientationMarks(marked, front, AxisDirections(1.0));

  // Each edge's letter is the one drawn alone at its place.
  const int64_t margin = 4 * scale, textHeight = markTextHeight(scale), glyph = markTextWidth("R", scale);
  const struct {
    const char* letter;
    int64_t x, y;
  } expected[] = {{"R", margin, (height - textHeight) / 2},
                  {"L", width - margin - glyph, (height - textHeight) / 2},
                  {"S", (width - glyph) / 2, margin},
                  {"I", (width - glyph) / 2, height - margin - textHeight}};
  for (const auto& e : expected) {
    FloatImage alone = blank(width, height);
    const float light[3] = {0.92f, 0.92f, 0.92f}, outline[3] = {0.05f, 0.05f, 0.05f};
    drawMarkText(alone, e.letter, e.x, e.y, scale, light, outline);
    for (int64_t y = e.y - 2; y < e.y + textHeight + 2; ++y)
      for (int64_t x = e.x - 2; x < e.x + glyph + 2; ++x)
        for (uint32_t c = 0; c < 4; ++c)
          ASSERT_EQ(marked.at(uint32_t(x), uint32_t(y), c), alone.at(uint32_t(x), uint32_t(y), c))
              << e.letter << " at " << x << "," << y;
  }

  // The axes from the corner: x (red) to the right, z (blue) up, y (green) into the image: a point.
  const double length = 18.0 * scale, gap = 4.0 * scale + 0.5 * textHeight;
  const uint32_t ox = uint32_t(margin + length + gap), oy = uint32_t(height - margin - length - gap);
  const auto isColor = [&](uint32_t x, uint32_t y, float r, float g, float b) {
    return std::abs(marked.at(x, y, 0) - r) < 1e-6 && std::abs(marked.at(x, y, 1) - g) < 1e-6 &&
           std::abs(marked.at(x, y, 2) - b) < 1e-6;
  };
  EXPECT_TRUE(isColor(ox + 12, oy, 0.92f, 0.35f, 0.31f));  // along x
  EXPECT_TRUE(isColor(ox, oy - 12, 0.39f, 0.59f, 1.0f));   // along z
  EXPECT_FALSE(isColor(ox - 12, oy, 0.92f, 0.35f, 0.31f));
  EXPECT_FALSE(isColor(ox, oy + 12, 0.39f, 0.59f, 1.0f));

  // A volume turned a quarter about z: its x points along the world's y (into the image), its y along -x
  // (to the image's left).
  FloatImage turned = blank(width, height);
  drawOrientationMarks(turned, front,
                       AxisDirections(glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1)));
  EXPECT_TRUE(std::abs(turned.at(ox - 12, oy, 1) - 0.82f) < 1e-6);  // green, leftward
  EXPECT_FALSE(std::abs(turned.at(ox + 12, oy, 0) - 0.92f) < 1e-6);

  // Alpha is 1 only where a mark lies: the middle of the image is untouched.
  size_t opaque = 0;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) opaque += marked.at(x, y, 3) == 1.0f ? 1 : 0;
  EXPECT_GT(opaque, 100u);
  EXPECT_LT(opaque, size_t(width) * height / 20);
  EXPECT_EQ(marked.at(width / 2, height / 2, 3), 0.0f);
}

TEST(ImageMarks, TheFontGrowsWithTheImage) {
  const Camera front =
      anatomicalViewCamera(AnatomicalView::Anterior, 3.0, glm::dvec3(0.0), glm::dvec3(10.0), 40.0);
  FloatImage large = blank(3 * kMarkScalePixels, 3 * kMarkScalePixels, 3);
  drawOrientationMarks(large, front, AxisDirections(1.0));
  // The top letter, S, at scale 3: its top row (".####") starts a glyph pixel in, 12 pixels from the top.
  const uint32_t scale = 3, x = (large.width - markTextWidth("S", scale)) / 2;
  EXPECT_EQ(large.at(x + scale, 4 * scale, 0), 0.92f);
  EXPECT_EQ(large.at(x + scale + 2, 4 * scale + 2, 0), 0.92f);  // the same font pixel, 3 wide
  EXPECT_EQ(large.at(x + 1, 4 * scale + 1, 0), 0.05f);          // the first column of that row: outline
}

}  // namespace
}  // namespace ropecast::tools
