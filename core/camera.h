// Camera: a pinhole camera in world units, as docs/ARCHITECTURE.md fixes it: eye, target, up and a vertical
// field of view in degrees; pixel row 0 is the top of the image. Plain data plus pure functions; any thread.
// Shared by refinement (projected voxel size, frustum), the CPU reference renderer and the GL ray caster, so
// that every path generates exactly the same rays.
#pragma once

#include <cstdint>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/world_box.h"

namespace ropecast {

struct Camera {
  glm::dvec3 eye{0.0, 0.0, 1.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double fovYDeg = 40.0;

  friend bool operator==(const Camera&, const Camera&) = default;
};

struct Ray {
  glm::dvec3 origin{0.0};
  glm::dvec3 dir{0.0, 0.0, -1.0};  // unit length, world units
};

// The eye orbiting the center of the box [boxMin, boxMax]: azimuth around +z from +x, elevation above the xy
// plane (degrees), distance in units of the box's bounding-sphere radius; up is +z.
Camera orbitCamera(double azimuthDeg, double elevationDeg, double distance, glm::dvec3 boxMin,
                   glm::dvec3 boxMax, double fovYDeg = 40.0);

// The up vector a camera gets when the user gives none: +z, or +y when looking (nearly) along z.
glm::dvec3 defaultUp(glm::dvec3 viewDirection);

// What makes a camera unusable, in words ("" when it is usable). viewProblem: eye and target at the same
// point, or a view direction that overflows; no frame exists then. cameraProblem adds an up vector that is
// zero or parallel to the view direction and a field of view outside (0, 180) degrees. Callers that take a
// camera from the user (command line, camera path) check cameraProblem and name the option or keyframe;
// whatever draws checks viewProblem, since rays from such a camera are not finite and a ray caster fed NaN
// rays can spin.
std::string viewProblem(glm::dvec3 eye, glm::dvec3 target);
std::string cameraProblem(const Camera& c);

// Orthonormal camera frame: forward (eye -> target), right, and the true up. An up vector that is zero or
// parallel to forward (an interpolated camera path can pass through one) is replaced by defaultUp, so the
// frame is finite whenever eye and target are distinct finite points.
struct CameraFrame {
  glm::dvec3 forward, right, up;
};
CameraFrame cameraFrame(const Camera& c);

// The ray through the center of pixel (px, py) of a width x height image (row 0 at the top).
Ray pixelRay(const Camera& c, uint32_t width, uint32_t height, double px, double py);

// The camera moved, not turned, to look at `point` from as far as its eye was: the point comes to the image's
// center at the size it had, and an orbit about the new target turns about it. Up and field of view stay. A
// point at the eye, or not finite, leaves the camera as it was.
Camera centeredOn(const Camera& c, glm::dvec3 point);

// The bounds of a box and a half-space a ray may enter their common part through (entryBound).
inline constexpr int kEntryPlane = 6;
// A slab's far face (--slab): its inward normal is minus the plane's.
inline constexpr int kEntryPlaneBack = 7;
inline constexpr int kEntryNone = -1;

// The ray's parameter interval [t0, t1] inside the box (slab test), t0 clamped to 0 (the eye may be inside);
// false on a miss. Whatever draws the volume clips its rays with the box its samples lie in: the volume box
// [0, n s] cut to --crop (sampledWorldBox, core/render_params.h).
// With `entry`, notes the bound the ray enters through (entryBound's numbers; kEntryNone from inside).
bool clipToBox(const Ray& ray, const WorldBox& box, double& t0, double& t1, int* entry = nullptr);
inline bool clipToBox(const Ray& ray, glm::dvec3 boxMax, double& t0, double& t1) {
  return clipToBox(ray, WorldBox{glm::dvec3(0.0), boxMax}, t0, t1);
}
// Narrows [t0, t1] to the part of the ray where dot(normal, x) >= offset (--clip-plane); false when nothing
// is left. A zero normal keeps everything. With `entry`, notes `bound` where the plane moves t0 up.
bool clipToHalfSpace(const Ray& ray, glm::dvec3 normal, double offset, double& t0, double& t1,
                     int* entry = nullptr, int bound = kEntryPlane);

// --mode slice: where the ray, clipped to [t0, t1) (clipToBox), crosses the plane dot(normal, x) = offset:
// t0 moves to the crossing, t1 stays. False where it crosses outside [t0, t1), runs parallel to the plane, or
// the normal is zero.
bool startAtPlane(const Ray& ray, glm::dvec3 normal, double offset, double& t0, double t1);

// The bound of the region clipToBox and clipToHalfSpace keep that a ray enters it through: 0, 1, 2 the box's
// lower face on that axis, 3, 4, 5 its upper face, kEntryPlane the half-space's plane (kEntryPlaneBack is a
// slab's far face, core/render_params.h clipToPlane); kEntryNone when the
// ray starts inside the region (t0 clamped to 0) or misses it. A tie goes to the box, and among its faces to
// the lower axis, as shaders/sampling.glsl cameraRay decides.
int entryBound(const Ray& ray, const WorldBox& box, glm::dvec3 normal, double offset);
// The unit normal of bound `bound` (not kEntryNone) pointing into the region; `planeNormal` is the
// half-space's (minus it for kEntryPlaneBack).
glm::dvec3 boundInwardNormal(int bound, glm::dvec3 planeNormal);

}  // namespace ropecast
