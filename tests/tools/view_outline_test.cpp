// The viewer's outlines (tools/view_outline.h): a box's corners land where the camera's rays through them
// leave the eye, for a turned box too; edges behind the eye are cut away; the clip plane's polygon closes.
// Its orientation marks: the sides of the patient at the edges of the named views and an oblique one, and the
// triad of a volume's axes, turned with it.
#include "tools/view_outline.h"

#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace ropecast::tools {
namespace {

constexpr uint32_t kWidth = 320, kHeight = 200;

Camera lookingAt(glm::dvec3 eye, glm::dvec3 target) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.up = {0, 0, 1};
  c.fovYDeg = 45;
  return c;
}

// The ray through window point p (pixelRay takes pixel indices, whose centers lie at + 0.5) points at
// `world`.
void expectOnRayTo(const Camera& c, glm::dvec2 p, glm::dvec3 world) {
  const Ray ray = pixelRay(c, kWidth, kHeight, p.x - 0.5, p.y - 0.5);
  EXPECT_NEAR(glm::dot(ray.dir, glm::normalize(world - c.eye)), 1.0, 1e-9)
      << "window point " << p.x << "," << p.y;
}

bool near(glm::dvec2 a, glm::dvec2 b) {
  return glm::length(a - b) < 1e-6;
}

TEST(ViewOutline, ABoxsCornersLieOnTheRaysThroughTheirPoints) {
  const double a = glm::radians(40.0);
  const AxisDirections turned(glm::dvec3(std::cos(a), std::sin(a), 0),
                              glm::dvec3(-std::sin(a), std::cos(a), 0), glm::dvec3(0, 0, 1));
  for (const AxisDirections& axes : {AxisDirections(1.0), turned}) {
    const PlacedBox box{{glm::dvec3(1, 2, 3), glm::dvec3(5, 4, 9)}, axes, glm::dvec3(3, 3, 5)};
    const Camera c = lookingAt({20, -15, 12}, {3, 3, 5});
    const std::vector<ScreenSegment> edges = boxOutline(c, kWidth, kHeight, box);
    ASSERT_EQ(edges.size(), 12u);
    // Every corner is the end of three edges; each end lies on the ray to a corner placed in the world.
    for (const ScreenSegment& e : edges)
      for (const glm::dvec2 end : {e.a, e.b}) {
        bool found = false;
        for (int i = 0; i < 8 && !found; ++i) {
          const glm::dvec3 corner(i & 1 ? 5 : 1, i & 2 ? 4 : 2, i & 4 ? 9 : 3);
          const glm::dvec3 world = box.center + axes * (corner - box.center);
          const Ray ray = pixelRay(c, kWidth, kHeight, end.x - 0.5, end.y - 0.5);
          found = glm::dot(ray.dir, glm::normalize(world - c.eye)) > 1.0 - 1e-9;
        }
        EXPECT_TRUE(found) << "an edge ends at " << end.x << "," << end.y << ", on no corner's ray";
      }
  }
}

TEST(ViewOutline, EdgesBehindTheEyeAreCutAway) {
  const PlacedBox box{{glm::dvec3(0), glm::dvec3(10)}, AxisDirections(1.0), glm::dvec3(5)};
  // Inside the box, looking along +x: the edges at x = 0 lie behind, those along x are cut at the eye's
  // plane, those at x = 10 are whole.
  const Camera inside = lookingAt({5, 5, 5}, {6, 5, 5});
  const std::vector<ScreenSegment> edges = boxOutline(inside, kWidth, kHeight, box);
  EXPECT_EQ(edges.size(), 8u);
  for (const ScreenSegment& e : edges)
    EXPECT_TRUE(std::isfinite(e.a.x) && std::isfinite(e.a.y) && std::isfinite(e.b.x) && std::isfinite(e.b.y));
  const Camera above = lookingAt({5, 5, 30}, {5, 5, 5});
  const std::vector<ScreenSegment> whole = boxOutline(above, kWidth, kHeight, box);
  ASSERT_EQ(whole.size(), 12u);
  expectOnRayTo(above, whole.front().a, glm::dvec3(0, 0, 0));  // the first edge starts at the first corner
  EXPECT_TRUE(boxOutline(lookingAt({5, 5, 30}, {5, 5, 40}), kWidth, kHeight, box).empty());
}

TEST(ViewOutline, TheClipPlanesPolygonClosesOnTheBoxsFaces) {
  const PlacedBox box{{glm::dvec3(0), glm::dvec3(4, 6, 8)}, AxisDirections(1.0), glm::dvec3(2, 3, 4)};
  const Camera c = lookingAt({15, -12, 20}, {2, 3, 4});
  // z = 5: a rectangle of four sides; a slanted plane through the center: a hexagon at most.
  const std::vector<ScreenSegment> square = planeOutline(c, kWidth, kHeight, box, {{2, 3, 5}, {0, 0, 1}});
  ASSERT_EQ(square.size(), 4u);
  for (size_t k = 0; k < square.size(); ++k) EXPECT_TRUE(near(square[k].b, square[(k + 1) % 4].a)) << k;
  for (const ScreenSegment& s : square) {
    bool onCorner = false;
    for (const glm::dvec3 corner :
         {glm::dvec3(0, 0, 5), glm::dvec3(4, 0, 5), glm::dvec3(0, 6, 5), glm::dvec3(4, 6, 5)}) {
      const Ray ray = pixelRay(c, kWidth, kHeight, s.a.x - 0.5, s.a.y - 0.5);
      onCorner = onCorner || glm::dot(ray.dir, glm::normalize(corner - c.eye)) > 1.0 - 1e-9;
    }
    EXPECT_TRUE(onCorner);
  }
  const std::vector<ScreenSegment> slanted =
      planeOutline(c, kWidth, kHeight, box, {{2, 3, 4}, glm::normalize(glm::dvec3(1, 1, 1))});
  EXPECT_GE(slanted.size(), 3u);
  EXPECT_LE(slanted.size(), 6u);
  EXPECT_TRUE(planeOutline(c, kWidth, kHeight, box, {}).empty());                       // off
  EXPECT_TRUE(planeOutline(c, kWidth, kHeight, box, {{2, 3, 20}, {0, 0, 1}}).empty());  // above the box
  // Through a corner and an edge only: it touches, nothing to outline.
  EXPECT_TRUE(
      planeOutline(c, kWidth, kHeight, box, {{0, 0, 0}, glm::normalize(glm::dvec3(1, 1, 1))}).empty());
}

TEST(ViewOutline, TheRulersEndsLieOnTheRaysToItsPoints) {
  const double a = glm::radians(25.0);
  const AxisDirections turned(glm::dvec3(1, 0, 0), glm::dvec3(0, std::cos(a), std::sin(a)),
                              glm::dvec3(0, -std::sin(a), std::cos(a)));
  const PlacedBox box{{glm::dvec3(0), glm::dvec3(8, 6, 4)}, turned, glm::dvec3(4, 3, 2)};
  const Camera c = lookingAt({20, -15, 12}, {4, 3, 2});
  const glm::dvec3 p(1, 2, 3), q(7, 5, 0.5);  // in the volume's own axes
  const auto s = segmentOutline(c, kWidth, kHeight, box, p, q);
  ASSERT_TRUE(s.has_value());
  expectOnRayTo(c, s->a, box.center + turned * (p - box.center));
  expectOnRayTo(c, s->b, box.center + turned * (q - box.center));
  // Behind the eye: nothing to draw.
  const Camera away = lookingAt({20, -15, 12}, {40, -30, 24});
  EXPECT_FALSE(segmentOutline(away, kWidth, kHeight, box, p, q).has_value());
}

TEST(ViewOrientationMarks, TheEdgesOfTheNamedViewsFaceTheirSidesOfThePatient) {
  const glm::dvec3 lo(0.0), hi(40, 30, 20);
  // left, right, top, bottom: from the front and from below the patient's right lies on the image's left.
  const struct {
    AnatomicalView view;
    EdgeLetters letters;
  } cases[] = {
      {AnatomicalView::Anterior, {"R", "L", "S", "I"}}, {AnatomicalView::Posterior, {"L", "R", "S", "I"}},
      {AnatomicalView::Left, {"A", "P", "S", "I"}},     {AnatomicalView::Right, {"P", "A", "S", "I"}},
      {AnatomicalView::Superior, {"L", "R", "A", "P"}}, {AnatomicalView::Inferior, {"R", "L", "A", "P"}}};
  for (const auto& c : cases) {
    const EdgeLetters got = edgeLetters(anatomicalViewCamera(c.view, 3.0, lo, hi, 40.0));
    EXPECT_EQ(got.left, c.letters.left) << int(c.view);
    EXPECT_EQ(got.right, c.letters.right) << int(c.view);
    EXPECT_EQ(got.top, c.letters.top) << int(c.view);
    EXPECT_EQ(got.bottom, c.letters.bottom) << int(c.view);
  }
  // From the left-anterior diagonal: the right edge faces right-posterior (equal parts: x first).
  const EdgeLetters oblique = edgeLetters(lookingAt({10, -10, 0}, {0, 0, 0}));
  EXPECT_EQ(oblique.right, "LP");
  EXPECT_EQ(oblique.left, "RA");
  EXPECT_EQ(oblique.top, "S");
}

TEST(ViewOrientationMarks, TheTriadTurnsWithTheVolumesAxes) {
  const Camera fromFront = lookingAt({0, -10, 0}, {0, 0, 0});  // forward +y, right +x, up +z
  const auto expectAxis = [](const TriadAxis& got, glm::dvec2 screen, double towardEye, const char* what) {
    EXPECT_TRUE(near(got.screen, screen)) << what << ": " << got.screen.x << "," << got.screen.y;
    EXPECT_NEAR(got.towardEye, towardEye, 1e-12) << what;
  };
  const std::array<TriadAxis, 3> world = axesTriad(fromFront, AxisDirections(1.0));
  expectAxis(world[0], {1, 0}, 0, "x");
  expectAxis(world[1], {0, 0}, -1, "y");  // away from the eye
  expectAxis(world[2], {0, -1}, 0, "z");  // up: y down on the screen
  // x turned to +y, y to -x: x now points away, y left.
  const AxisDirections turned(glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1));
  const std::array<TriadAxis, 3> t = axesTriad(fromFront, turned);
  expectAxis(t[0], {0, 0}, -1, "turned x");
  expectAxis(t[1], {-1, 0}, 0, "turned y");
  expectAxis(t[2], {0, -1}, 0, "turned z");
}

}  // namespace
}  // namespace ropecast::tools
