// ScreenRect's predicates, and projectBox against the rays the ray caster sends (core/camera.h pixelRay):
// every pixel whose ray meets a box is inside the box's rect, and the rect is within a pixel of the box's
// projection computed the way OpenGL would (lookAt and perspective matrices).
#include "occlusion/screen_rect.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

namespace ropecast {
namespace {

TEST(ScreenRect, MeasuresAndComparesHalfOpenRectangles) {
  const ScreenRect r{2, 3, 10, 7};
  EXPECT_EQ(r.width(), 8);
  EXPECT_EQ(r.height(), 4);
  EXPECT_EQ(r.area(), 32);
  EXPECT_FALSE(r.empty());
  EXPECT_TRUE((ScreenRect{5, 5, 5, 9}).empty());
  EXPECT_EQ((ScreenRect{5, 5, 4, 9}).area(), 0);

  EXPECT_TRUE(r.contains(r));
  EXPECT_TRUE(r.contains({2, 3, 3, 4}));
  EXPECT_FALSE(r.contains({1, 3, 3, 4}));
  EXPECT_FALSE(r.contains({9, 6, 11, 7}));
  EXPECT_FALSE(r.contains({}));  // an empty rect holds no pixel to place

  EXPECT_TRUE(r.overlaps({9, 6, 20, 20}));
  EXPECT_FALSE(r.overlaps({10, 3, 12, 7}));  // touching edges share no pixel
  EXPECT_FALSE(r.overlaps({2, 7, 10, 8}));
  EXPECT_EQ(intersect(r, {0, 0, 4, 4}), (ScreenRect{2, 3, 4, 4}));
  EXPECT_EQ(intersect(r, {10, 0, 14, 4}), ScreenRect{});
}

bool rayMeetsBox(const Ray& ray, glm::dvec3 lo, glm::dvec3 hi) {
  double t0 = 0.0, t1 = 0.0;
  return clipToBox({ray.origin - lo, ray.dir}, hi - lo, t0, t1);
}

// The continuous pixel position (px + 0.5, py + 0.5) of a point in front of the camera, through OpenGL's
// matrices: a derivation independent of projectBox's.
glm::dvec2 glPixel(const Camera& c, uint32_t width, uint32_t height, glm::dvec3 p) {
  const glm::dmat4 view = glm::lookAt(c.eye, c.target, c.up);
  const glm::dmat4 proj = glm::perspective(glm::radians(c.fovYDeg), double(width) / height, 0.01, 100.0);
  const glm::dvec4 clip = proj * view * glm::dvec4(p, 1.0);
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return {(ndc.x + 1.0) * 0.5 * width, (1.0 - ndc.y) * 0.5 * height};
}

double distanceToRay(const Ray& ray, glm::dvec3 p) {
  const glm::dvec3 d = p - ray.origin;
  return glm::length(d - glm::dot(d, ray.dir) * ray.dir);
}

TEST(ProjectBox, HoldsEveryPixelWhoseRayMeetsTheBoxAndLittleMore) {
  std::mt19937 rng(2008);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const uint32_t sizes[][2] = {{1, 1}, {2, 1}, {7, 5}, {33, 17}, {48, 48}, {97, 3}, {4, 61}};
  int tested = 0, nearEye = 0, outside = 0, hitPixels = 0;
  for (int trial = 0; trial < 1400; ++trial) {
    const uint32_t width = sizes[trial % 7][0], height = sizes[trial % 7][1];
    Camera cam;
    cam.eye = 4.0 * glm::dvec3(unit(rng), unit(rng), unit(rng));
    cam.target = 0.5 * glm::dvec3(unit(rng), unit(rng), unit(rng));
    cam.up = {unit(rng), unit(rng), unit(rng)};
    cam.fovYDeg = 15.0 + 60.0 * (unit(rng) + 1.0);
    if (!cameraProblem(cam).empty()) continue;
    const glm::dvec3 lo = 1.5 * glm::dvec3(unit(rng), unit(rng), unit(rng));
    const glm::dvec3 hi = lo + 0.05 + 1.2 * (glm::dvec3(unit(rng), unit(rng), unit(rng)) + 1.0);
    const BoxProjection p = projectBox(lo, hi, cam, width, height);
    if (p.nearEye) {
      ++nearEye;
      EXPECT_EQ(p.rect, viewportRect(width, height));
      continue;
    }
    if (p.rect.empty()) ++outside;
    ++tested;

    for (uint32_t py = 0; py < height; ++py) {
      for (uint32_t px = 0; px < width; ++px) {
        if (!rayMeetsBox(pixelRay(cam, width, height, px, py), lo, hi)) continue;
        ++hitPixels;
        ASSERT_TRUE(p.rect.contains({int32_t(px), int32_t(py), int32_t(px) + 1, int32_t(py) + 1}))
            << "trial " << trial << " pixel " << px << "," << py;
      }
    }

    // Not grossly larger: within a pixel of the corners' bounding rectangle, the corners placed by OpenGL's
    // matrices, and those placements agree with pixelRay (the ray of each corner's position meets it).
    glm::dvec2 lower(INFINITY), upper(-INFINITY);
    for (uint32_t i = 0; i < 8; ++i) {
      const glm::dvec3 corner{(i & 1u) ? hi.x : lo.x, (i & 2u) ? hi.y : lo.y, (i & 4u) ? hi.z : lo.z};
      const glm::dvec2 at = glPixel(cam, width, height, corner);
      lower = glm::min(lower, at), upper = glm::max(upper, at);
      const Ray ray = pixelRay(cam, width, height, at.x - 0.5, at.y - 0.5);
      ASSERT_LT(distanceToRay(ray, corner), 1e-9 * (1.0 + glm::length(corner - cam.eye)))
          << "trial " << trial;
    }
    const ScreenRect slack = intersect(
        {int32_t(std::max(-1.0, std::floor(lower.x) - 1)), int32_t(std::max(-1.0, std::floor(lower.y) - 1)),
         int32_t(std::min(1e6, std::ceil(upper.x) + 1)), int32_t(std::min(1e6, std::ceil(upper.y) + 1))},
        viewportRect(width, height));
    if (!p.rect.empty()) {
      EXPECT_TRUE(slack.contains(p.rect)) << "trial " << trial;
    }
  }
  // The random scenes exercise every case.
  EXPECT_GT(tested, 500);
  EXPECT_GT(nearEye, 20);
  EXPECT_GT(outside, 20);
  EXPECT_GT(hitPixels, 50000);
}

TEST(ProjectBox, CentersABoxOnTheViewAxis) {
  Camera cam;
  cam.eye = {0.0, -5.0, 0.0};
  cam.target = {0.0, 0.0, 0.0};
  cam.up = {0.0, 0.0, 1.0};
  const BoxProjection p = projectBox({-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0}, cam, 64, 48);
  ASSERT_FALSE(p.nearEye);
  ASSERT_FALSE(p.rect.empty());
  EXPECT_EQ(p.rect.x0, 64 - p.rect.x1);
  EXPECT_EQ(p.rect.y0, 48 - p.rect.y1);
}

TEST(ProjectBox, IsNearEyeWhenTheBoxHoldsTheEyeOrReachesBehindIt) {
  Camera cam;
  cam.eye = {0.0, 0.0, 0.0};
  cam.target = {0.0, 1.0, 0.0};
  cam.up = {0.0, 0.0, 1.0};
  const ScreenRect whole = viewportRect(40, 30);
  for (const auto& [lo, hi] :
       {std::pair{glm::dvec3(-1.0), glm::dvec3(1.0)},                            // holds the eye
        std::pair{glm::dvec3(3.0, -1.0, 0.0), glm::dvec3(4.0, 1.0, 1.0)},        // beside it
        std::pair{glm::dvec3(-1.0, -3.0, -1.0), glm::dvec3(1.0, -2.0, 1.0)}}) {  // behind
    const BoxProjection p = projectBox(lo, hi, cam, 40, 30);
    EXPECT_TRUE(p.nearEye);
    EXPECT_EQ(p.rect, whole);
  }
  // In front of the eye but outside the view: an empty rect, and nothing to mark visible.
  const BoxProjection off = projectBox({50.0, 1.0, -1.0}, {51.0, 2.0, 1.0}, cam, 40, 30);
  EXPECT_FALSE(off.nearEye);
  EXPECT_TRUE(off.rect.empty());
  EXPECT_EQ(off.rect, ScreenRect{});
  EXPECT_EQ(projectBox({-1.0, 4.0, -1.0}, {1.0, 5.0, 1.0}, cam, 0, 30).rect, ScreenRect{});
}

}  // namespace
}  // namespace ropecast
