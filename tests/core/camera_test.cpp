// Cameras from the user: what makes one unusable (cameraProblem), the frame of a degenerate up (cameraFrame),
// and the camera path's keyframe checks built on them.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/camera.h"
#include "core/camera_path.h"
#include "core/error.h"
#include "core/render_params.h"

namespace ropecast {
namespace {

Camera lookAt(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.up = up;
  return c;
}

bool finite(glm::dvec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void expectOrthonormal(const CameraFrame& f) {
  ASSERT_TRUE(finite(f.forward) && finite(f.right) && finite(f.up));
  EXPECT_NEAR(glm::length(f.forward), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(f.right), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(f.up), 1.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.forward, f.right), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.forward, f.up), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.right, f.up), 0.0, 1e-12);
}

TEST(CameraProblem, AnOrdinaryCameraHasNone) {
  EXPECT_EQ(cameraProblem(lookAt({1, 2, 3}, {0, 0, 0}, {0, 0, 1})), "");
  // Up need not be unit length nor perpendicular to the view.
  EXPECT_EQ(cameraProblem(lookAt({5, 0, 0}, {0, 0, 0}, {1, 0, 7})), "");
}

TEST(CameraProblem, NamesEachDefect) {
  EXPECT_EQ(cameraProblem(lookAt({1, 1, 1}, {1, 1, 1}, {0, 0, 1})), "eye and target are the same point");
  EXPECT_EQ(cameraProblem(lookAt({-1e308, 0, 0}, {1e308, 0, 0}, {0, 0, 1})),
            "the view direction (target - eye) is not finite");
  EXPECT_EQ(cameraProblem(lookAt({0, 0, 0}, {1, 1, 1}, {0, 0, 0})), "up is the zero vector");
  EXPECT_EQ(cameraProblem(lookAt({0, 0, 0}, {1, 1, 1}, {std::numeric_limits<double>::quiet_NaN(), 0, 1})),
            "up is not finite");
  EXPECT_EQ(cameraProblem(lookAt({0, 0, 0}, {1, 1, 1}, {2, 2, 2})),
            "up is parallel to the view direction (target - eye)");
  EXPECT_EQ(cameraProblem(lookAt({0, 0, 0}, {1, 1, 1}, {-1, -1, -1})),
            "up is parallel to the view direction (target - eye)");
  Camera wide = lookAt({1, 2, 3}, {0, 0, 0}, {0, 0, 1});
  wide.fovYDeg = 180.0;
  EXPECT_EQ(cameraProblem(wide), "the field of view must be in (0, 180) degrees");
}

TEST(CameraFrame, DegenerateUpFallsBackToDefaultUp) {
  // Parallel and zero ups (a camera path interpolating between opposite ups passes through zero).
  for (glm::dvec3 up : {glm::dvec3(1, 1, 1), glm::dvec3(0, 0, 0)}) {
    const CameraFrame f = cameraFrame(lookAt({0, 0, 0}, {1, 1, 1}, up));
    expectOrthonormal(f);
    const CameraFrame expected = cameraFrame(lookAt({0, 0, 0}, {1, 1, 1}, defaultUp({1, 1, 1})));
    EXPECT_EQ(f.right, expected.right);
    EXPECT_EQ(f.up, expected.up);
  }
  // Looking straight down z with the default +z: +y becomes the up.
  const CameraFrame down = cameraFrame(lookAt({0, 0, 10}, {0, 0, 0}, {0, 0, 1}));
  expectOrthonormal(down);
  EXPECT_NEAR(down.up.y, 1.0, 1e-12);
}

TEST(CameraFrame, UsableUpIsKept) {
  const CameraFrame f = cameraFrame(lookAt({0, -5, 0}, {0, 0, 0}, {0, 0, 3}));
  expectOrthonormal(f);
  EXPECT_NEAR(f.up.z, 1.0, 1e-12);
  EXPECT_NEAR(f.right.x, 1.0, 1e-12);
}

TEST(CenteredOn, MovesTheCameraToLookAtThePointFromItsEyesDistance) {
  Camera c;
  c.eye = {10, -4, 3};
  c.target = {0, 1, 2};
  c.up = {0, 0.2, 1};
  c.fovYDeg = 33;
  const glm::dvec3 point(2, 3, -1);
  const Camera moved = centeredOn(c, point);
  EXPECT_EQ(moved.target, point);
  EXPECT_NEAR(glm::length(moved.eye - point), glm::length(c.eye - point), 1e-12);
  const CameraFrame before = cameraFrame(c), after = cameraFrame(moved);
  EXPECT_NEAR(glm::length(after.forward - before.forward), 0.0, 1e-12);
  EXPECT_NEAR(glm::length(after.up - before.up), 0.0, 1e-12);
  EXPECT_EQ(moved.up, c.up);
  EXPECT_EQ(moved.fovYDeg, c.fovYDeg);
  // The point lies on the middle pixel's ray of an odd-sized image.
  const Ray middle = pixelRay(moved, 101, 81, 50, 40);
  EXPECT_NEAR(glm::dot(middle.dir, glm::normalize(point - moved.eye)), 1.0, 1e-12);
  EXPECT_EQ(centeredOn(c, c.eye).eye, c.eye);
  EXPECT_EQ(centeredOn(c, c.eye).target, c.target);
  EXPECT_EQ(centeredOn(c, {std::nan(""), 0, 0}).target, c.target);
}

TEST(DefaultUp, IsZUnlessLookingAlongZ) {
  EXPECT_EQ(defaultUp({1, 2, 3}), glm::dvec3(0, 0, 1));
  EXPECT_EQ(defaultUp({0, 0, -4}), glm::dvec3(0, 1, 0));
  EXPECT_EQ(defaultUp({0, 0, 1}), glm::dvec3(0, 1, 0));
}

TEST(CameraPathKeyframes, RejectAnUnusableUpNamingTheKeyframe) {
  const std::string text =
      R"([{"orbit": [0, 20, 3]}, {"eye": [0, 0, 0], "target": [1, 1, 1], "up": [1, 1, 1]}])";
  try {
    parseCameraPath(text, "p.json");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("p.json, keyframe 1: up is parallel"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parseCameraPath(R"([{"eye": [1, 2, 3], "target": [1, 2, 3]}])", "q.json"), Error);
}

TEST(CameraPathKeyframes, RejectARepeatedOrUnknownKeyNamingIt) {
  const auto errorOf = [](const std::string& text) {
    try {
      parseCameraPath(text, "p.json");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(errorOf(R"([{"orbit": [0, 20, 3], "orbit": [90, 20, 3]}])"),
            "camera path p.json: the key \"orbit\" is given twice in one object (only the last would count)");
  EXPECT_EQ(errorOf(R"({"keyframes": [{"orbit": [0, 20, 3]}], "fov": 10})"),
            "camera path p.json: unknown key \"fov\" beside \"keyframes\" (expected \"keyframes\" and an "
            "optional \"description\")");
  EXPECT_EQ(errorOf(R"({"keyframes": [{"orbit": [0, 20, 3]}], "description": 1})"),
            "camera path p.json: \"description\" must be a string");
  EXPECT_EQ(errorOf(R"({"description": "a turn", "keyframes": [{"orbit": [0, 20, 3]}]})"), "");
  // The benchmarks' path.
  EXPECT_NO_THROW(loadCameraPath(ROPECAST_SOURCE_DIR "/bench/flyby_path.json"));
  EXPECT_EQ(errorOf(R"([{"orbit": [0, 20, 3], "time": -1e308}, {"orbit": [9, 20, 3], "time": 1e308}])"),
            "camera path p.json: the keyframe times span more than the largest number");
}

TEST(CameraPathKeyframes, RejectANumberOutOfRangeNamingTheFile) {
  try {
    parseCameraPath(R"({"orbit": [0, 20, 1e999]})", "p.json");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("camera path p.json: not valid JSON"), std::string::npos)
        << e.what();
  }
}

TEST(CameraPathKeyframes, RejectUnknownKeysMixedFormsAndANonPositiveOrbitDistance) {
  const auto message = [](const std::string& text) {
    try {
      parseCameraPath(text, "p.json");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(R"([{"orbit": [0, 20, 3]}, {"orbit": [0, 20, 3], "zoom": 2}])")
                .find("p.json, keyframe 1: unknown key \"zoom\""),
            std::string::npos);
  EXPECT_NE(message(R"([{"orbit": [0, 20, 3], "eye": [1, 2, 3], "target": [0, 0, 0]}])")
                .find("keyframe 0: \"orbit\" places the camera itself"),
            std::string::npos);
  EXPECT_NE(message(R"([{"orbit": [0, 20, -3]}])").find("keyframe 0: \"orbit\" distance must be positive"),
            std::string::npos);
  EXPECT_NE(message(R"([{"orbit": [0, 20, 0]}])").find("distance must be positive"), std::string::npos);
  EXPECT_EQ(message(R"([{"orbit": [0, 20, 3], "fov": 30, "time": 0}, {"eye": [1, 2, 3], "target": [0, 0, 0],
                       "up": [0, 0, 1], "time": 1}])"),
            "no error");
}

// Named views, as --view gives them: each keyframe's camera that of anatomicalViewCamera; the sides are
// orbits, so that a path from the front to the left turns around the volume (its middle frame's eye as far
// from the center, between the two); refusals name the keyframe.
TEST(CameraPathKeyframes, NamedViewsAreThoseOfView) {
  const glm::dvec3 lo(0.0), hi(40.0, 20.0, 10.0);
  const CameraPath path = parseCameraPath(
      R"([{"view": "anterior"}, {"view": "left", "distance": 2, "fov": 30}, {"view": "superior"},
          {"view": "inferior", "distance": 4}, {"view": "right"}, {"view": "posterior"}])",
      "v.json");
  const struct {
    AnatomicalView view;
    double distance, fov;
  } expected[] = {{AnatomicalView::Anterior, 3, 40}, {AnatomicalView::Left, 2, 30},
                  {AnatomicalView::Superior, 3, 40}, {AnatomicalView::Inferior, 4, 40},
                  {AnatomicalView::Right, 3, 40},    {AnatomicalView::Posterior, 3, 40}};
  for (uint32_t i = 0; i < 6; ++i) {
    const Camera got = sampleCameraPath(path, i * 2, 11, lo, hi);
    const Camera want = anatomicalViewCamera(expected[i].view, expected[i].distance, lo, hi, expected[i].fov);
    EXPECT_LT(glm::length(got.eye - want.eye), 1e-9) << i;
    EXPECT_LT(glm::length(got.target - want.target), 1e-9) << i;
    EXPECT_LT(glm::length(glm::normalize(got.up) - glm::normalize(want.up)), 1e-9) << i;
    EXPECT_DOUBLE_EQ(got.fovYDeg, want.fovYDeg) << i;
  }
  // Halfway from the front (3 radii) to the left (2): around the volume, at 2.5 radii.
  const Camera half = sampleCameraPath(path, 1, 11, lo, hi);
  const glm::dvec3 center = 0.5 * (lo + hi), from = half.eye - center;
  EXPECT_NEAR(glm::length(from), 2.5 * 0.5 * glm::length(hi - lo), 1e-9);
  EXPECT_GT(from.x, 0.0);
  EXPECT_LT(from.y, 0.0);
  EXPECT_NEAR(from.z, 0.0, 1e-9);

  const auto message = [](const std::string& text) {
    try {
      parseCameraPath(text, "v.json");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(
      message(R"([{"view": "front"}])"),
      "camera path v.json, keyframe 0: \"view\" must be one of anterior, posterior, left, right, superior, "
      "inferior");
  EXPECT_NE(message(R"([{"view": "left", "orbit": [0, 0, 3]}])").find("\"view\" places the camera itself"),
            std::string::npos);
  EXPECT_NE(message(R"([{"view": "left", "distance": 0}])").find("\"distance\" must be a positive number"),
            std::string::npos);
  EXPECT_NE(message(R"([{"orbit": [0, 0, 3], "distance": 2}])").find("\"distance\" is a named view's"),
            std::string::npos);
}

TEST(CameraPathKeyframes, WithoutUpLookingAlongZIsUsable) {
  const CameraPath path = parseCameraPath(R"([{"eye": [0, 0, 9], "target": [0, 0, 0]}])", "p.json");
  const Camera c = sampleCameraPath(path, 0, 1, glm::dvec3(0.0), glm::dvec3(1.0));
  EXPECT_EQ(cameraProblem(c), "");
  EXPECT_EQ(c.up, glm::dvec3(0, 1, 0));
}

TEST(ClipToBox, GivesTheIntervalInsideTheBox) {
  double t0 = 0, t1 = 0;
  // From outside along +x through a 4 x 2 x 1 box.
  ASSERT_TRUE(clipToBox(Ray{{-1, 1, 0.5}, {1, 0, 0}}, {4, 2, 1}, t0, t1));
  EXPECT_DOUBLE_EQ(t0, 1.0);
  EXPECT_DOUBLE_EQ(t1, 5.0);
  // From inside: the interval starts at the eye.
  ASSERT_TRUE(clipToBox(Ray{{2, 1, 0.5}, {0, -1, 0}}, {4, 2, 1}, t0, t1));
  EXPECT_DOUBLE_EQ(t0, 0.0);
  EXPECT_DOUBLE_EQ(t1, 1.0);
  // Misses: parallel to a face outside it, the box behind the eye, passing a corner.
  EXPECT_FALSE(clipToBox(Ray{{-1, 3, 0.5}, {1, 0, 0}}, {4, 2, 1}, t0, t1));
  EXPECT_FALSE(clipToBox(Ray{{-1, 1, 0.5}, {-1, 0, 0}}, {4, 2, 1}, t0, t1));
  EXPECT_FALSE(clipToBox(Ray{{-3, 0, 0.5}, glm::normalize(glm::dvec3(1, 1, 0))}, {4, 2, 1}, t0, t1));
}

// A slice's ray starts where it crosses the plane inside the box, seen from either side of the plane.
TEST(StartAtPlane, MovesTheStartToTheCrossingInsideTheInterval) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(1, 0, 1));
  const double offset = glm::dot(n, glm::dvec3(2, 0, 0));  // the plane x + z = 2
  for (double sign : {1.0, -1.0}) {  // the normal toward the eye or away: the same plane
    double t0 = 1.0;
    ASSERT_TRUE(startAtPlane(Ray{{-1, 1, 0.5}, {1, 0, 0}}, sign * n, sign * offset, t0, 5.0));
    EXPECT_DOUBLE_EQ(t0, 2.5);  // x = 1.5
  }
  double t0 = 1.0;
  EXPECT_FALSE(startAtPlane(Ray{{-1, 1, 0.5}, {1, 0, 0}}, n, offset, t0, 2.0));  // past the interval's end
  EXPECT_FALSE(startAtPlane(Ray{{-1, 1, 0.5}, {1, 0, 0}}, n, offset, t0 = 3.0, 5.0));   // before its start
  EXPECT_FALSE(startAtPlane(Ray{{-1, 1, 0.5}, {1, 0, -1}}, n, offset, t0 = 0.0, 5.0));  // parallel
  EXPECT_FALSE(startAtPlane(Ray{{-1, 1, 0.5}, {1, 0, 0}}, glm::dvec3(0.0), 0.0, t0 = 0.0, 5.0));  // no plane
  EXPECT_EQ(t0, 0.0);  // untouched where it fails
}

// --slab: the part of the ray within half the slab of the plane, entered through the face the ray meets
// first (the near face, where the normal points in, or the far one), whichever way the normal points.
TEST(ClipToPlane, ASlabKeepsWithinHalfItsThicknessOfThePlane) {
  const ClipPlane slab{{3, 0, 0}, {1, 0, 0}, 2.0};  // 2 <= x <= 4
  for (double sign : {1.0, -1.0}) {                 // from -x, then from +x
    const Ray from{{sign > 0 ? -1.0 : 7.0, 1, 0.5}, {sign, 0, 0}};
    double t0 = 0.0, t1 = 100.0;
    int entry = kEntryNone;
    ASSERT_TRUE(clipToPlane(from, slab, t0, t1, &entry)) << sign;
    EXPECT_DOUBLE_EQ(t0, 3.0) << sign;
    EXPECT_DOUBLE_EQ(t1, 5.0) << sign;
    EXPECT_EQ(entry, sign > 0 ? kEntryPlane : kEntryPlaneBack) << sign;
    EXPECT_EQ(boundInwardNormal(entry, slab.normal), glm::dvec3(sign, 0, 0));
  }
  double t0 = 0.0, t1 = 100.0;
  EXPECT_FALSE(clipToPlane(Ray{{-1, 1, 0.5}, {0, 1, 0}}, slab, t0, t1));  // along the slab, outside it
  ClipPlane halfSpace = slab;
  halfSpace.slab = 0.0;  // x >= 3: no far face
  t0 = 0.0, t1 = 100.0;
  ASSERT_TRUE(clipToPlane(Ray{{-1, 1, 0.5}, {1, 0, 0}}, halfSpace, t0, t1));
  EXPECT_DOUBLE_EQ(t0, 4.0);
  EXPECT_DOUBLE_EQ(t1, 100.0);
}

// The bound a ray enters the kept region through, which isosurface caps shade with its inward normal.
TEST(EntryBound, NamesTheFaceOrThePlaneTheRayEntersThrough) {
  const WorldBox box{{0, 0, 0}, {4, 2, 1}};
  const glm::dvec3 none(0.0);
  // Each face of the box, from outside along its inward normal.
  EXPECT_EQ(entryBound(Ray{{-1, 1, 0.5}, {1, 0, 0}}, box, none, 0.0), 0);
  EXPECT_EQ(entryBound(Ray{{2, -1, 0.5}, {0, 1, 0}}, box, none, 0.0), 1);
  EXPECT_EQ(entryBound(Ray{{2, 1, -1}, {0, 0, 1}}, box, none, 0.0), 2);
  EXPECT_EQ(entryBound(Ray{{5, 1, 0.5}, {-1, 0, 0}}, box, none, 0.0), 3);
  EXPECT_EQ(entryBound(Ray{{2, 3, 0.5}, {0, -1, 0}}, box, none, 0.0), 4);
  EXPECT_EQ(entryBound(Ray{{2, 1, 2}, {0, 0, -1}}, box, none, 0.0), 5);
  // Obliquely: the face whose slab is entered last.
  EXPECT_EQ(entryBound(Ray{{-1, -4, 0.5}, glm::normalize(glm::dvec3(1, 2, 0))}, box, none, 0.0), 1);
  // The plane x >= 3 cuts the box: entering from -x, the plane is crossed after the box's face; from +x the
  // box's upper face comes first and the plane is where the ray leaves.
  EXPECT_EQ(entryBound(Ray{{-1, 1, 0.5}, {1, 0, 0}}, box, {1, 0, 0}, 3.0), kEntryPlane);
  EXPECT_EQ(entryBound(Ray{{5, 1, 0.5}, {-1, 0, 0}}, box, {1, 0, 0}, 3.0), 3);
  // A tie between the plane and a face goes to the face; between two faces, to the lower axis.
  EXPECT_EQ(entryBound(Ray{{-1, 1, 0.5}, {1, 0, 0}}, box, {1, 0, 0}, 0.0), 0);
  EXPECT_EQ(entryBound(Ray{{-1, -1, 0.5}, glm::normalize(glm::dvec3(1, 1, 0))}, box, none, 0.0), 0);
  // None from inside (the eye in the region), on a miss, or when the plane leaves nothing.
  EXPECT_EQ(entryBound(Ray{{2, 1, 0.5}, {1, 0, 0}}, box, none, 0.0), kEntryNone);
  EXPECT_EQ(entryBound(Ray{{-1, 3, 0.5}, {1, 0, 0}}, box, none, 0.0), kEntryNone);
  EXPECT_EQ(entryBound(Ray{{-1, 1, 0.5}, {1, 0, 0}}, box, {1, 0, 0}, 5.0), kEntryNone);
  EXPECT_EQ(entryBound(Ray{{-1, 1, 0.5}, {1, 0, 0}}, box, {0, 1, 0}, 1.5), kEntryNone);
  // A still axis along the plane, on its kept side: the box's face.
  EXPECT_EQ(entryBound(Ray{{-1, 1, 0.5}, {1, 0, 0}}, box, {0, 1, 0}, 0.5), 0);
}

TEST(EntryBound, InwardNormalsPointIntoTheRegion) {
  const glm::dvec3 planeNormal = glm::normalize(glm::dvec3(1, -2, 3));
  EXPECT_EQ(boundInwardNormal(0, planeNormal), glm::dvec3(1, 0, 0));
  EXPECT_EQ(boundInwardNormal(1, planeNormal), glm::dvec3(0, 1, 0));
  EXPECT_EQ(boundInwardNormal(2, planeNormal), glm::dvec3(0, 0, 1));
  EXPECT_EQ(boundInwardNormal(3, planeNormal), glm::dvec3(-1, 0, 0));
  EXPECT_EQ(boundInwardNormal(4, planeNormal), glm::dvec3(0, -1, 0));
  EXPECT_EQ(boundInwardNormal(5, planeNormal), glm::dvec3(0, 0, -1));
  EXPECT_EQ(boundInwardNormal(kEntryPlane, planeNormal), planeNormal);
}

// The cuts that cap: crop faces inside the volume and the clip plane, only for an isosurface with caps.
TEST(CapBounds, AreTheCropFacesInsideTheVolumeAndTheClipPlane) {
  const glm::u32vec3 dims{40, 30, 20};
  RenderParams params;
  EXPECT_EQ(capBoundsOf(params, dims), 0u);  // the whole volume: no cut
  params.crop.lo = {0, 5, 0};
  params.crop.hi = {40, 30, 12};
  EXPECT_EQ(capBoundsOf(params, dims), (1u << 1) | (1u << 5));
  params.crop.hi = {40, 31, 12};  // beyond the volume: its own face, no cut
  EXPECT_EQ(capBoundsOf(params, dims), (1u << 1) | (1u << 5));
  params.clipPlane = {glm::dvec3(10), glm::dvec3(0, 0, 1)};
  EXPECT_EQ(capBoundsOf(params, dims), (1u << 1) | (1u << 5) | (1u << kEntryPlane));
  params.isoCaps = false;
  EXPECT_EQ(capBoundsOf(params, dims), 0u);
  params.isoCaps = true;
  params.mode = RenderMode::Dvr;
  EXPECT_EQ(capBoundsOf(params, dims), 0u);
}

TEST(CameraPathKeyframes, InterpolatedOppositeUpsGiveAFiniteFrame) {
  // Rolling half a turn: halfway the interpolated up is zero, and the frame falls back to defaultUp.
  const CameraPath path = parseCameraPath(
      R"([{"eye": [0, -5, 0], "target": [0, 0, 0], "up": [0, 0, 1]},
          {"eye": [0, -5, 0], "target": [0, 0, 0], "up": [0, 0, -1]}])",
      "roll.json");
  const Camera middle = sampleCameraPath(path, 1, 3, glm::dvec3(0.0), glm::dvec3(1.0));
  EXPECT_EQ(middle.up, glm::dvec3(0.0));
  expectOrthonormal(cameraFrame(middle));
}

}  // namespace
}  // namespace ropecast
