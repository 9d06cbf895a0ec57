#include "core/camera_path.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/input_file.h"
#include "core/json_keys.h"

namespace ropecast {

namespace {

glm::dvec3 readVec3(const nlohmann::json& j, const char* field, const std::string& where) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw Error(where + ": \"" + field + "\" must be an array of 3 numbers");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

// The distance of a named view keyframe without "distance": --view's.
constexpr double kDefaultViewDistance = 3.0;

Camera keyframeCamera(const CameraKeyframe& k, glm::dvec3 boxMin, glm::dvec3 boxMax) {
  if (k.view) return anatomicalViewCamera(*k.view, k.viewDistance, boxMin, boxMax, k.camera.fovYDeg);
  if (!k.isOrbit) return k.camera;
  return orbitCamera(k.orbit.x, k.orbit.y, k.orbit.z, boxMin, boxMax, k.camera.fovYDeg);
}

}  // namespace

CameraPath parseCameraPath(const std::string& text, const std::string& sourceName) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
    throw Error("camera path " + sourceName + ": not valid JSON: " + e.what());
  }
  if (const std::string key = duplicateJsonKey(text); !key.empty())
    throw Error("camera path " + sourceName + ": the key \"" + key +
                "\" is given twice in one object (only the last would count)");
  if (doc.is_object() && doc.contains("keyframes")) {
    for (const auto& [key, value] : doc.items()) {
      if (key == "description" && value.is_string()) continue;  // for people; ignored
      if (key == "description")
        throw Error("camera path " + sourceName + ": \"description\" must be a string");
      if (key != "keyframes")
        throw Error("camera path " + sourceName + ": unknown key \"" + key +
                    "\" beside \"keyframes\" (expected \"keyframes\" and an optional \"description\")");
    }
    doc = nlohmann::json(doc["keyframes"]);
  }
  if (!doc.is_array() || doc.empty())
    throw Error("camera path " + sourceName + ": expected a non-empty JSON array of keyframes");

  CameraPath path;
  bool anyTime = false, allTime = true;
  for (size_t i = 0; i < doc.size(); ++i) {
    const nlohmann::json& j = doc[i];
    const std::string where = "camera path " + sourceName + ", keyframe " + std::to_string(i);
    if (!j.is_object()) throw Error(where + ": expected an object");
    // As strict as the command-line options: a misspelt key is an error, not a keyframe that ignores it.
    for (const auto& [key, value] : j.items())
      if (key != "orbit" && key != "eye" && key != "target" && key != "up" && key != "fov" && key != "time" &&
          key != "view" && key != "distance")
        throw Error(where + ": unknown key \"" + key +
                    "\" (expected orbit, view and distance, or eye, target and up; fov, time)");
    if (j.contains("orbit") && (j.contains("eye") || j.contains("target") || j.contains("up")))
      throw Error(where +
                  ": \"orbit\" places the camera itself; give it without \"eye\", \"target\" and \"up\"");
    if (j.contains("view") &&
        (j.contains("orbit") || j.contains("eye") || j.contains("target") || j.contains("up")))
      throw Error(where +
                  ": \"view\" places the camera itself; give it without \"orbit\", \"eye\", \"target\" and "
                  "\"up\"");
    if (j.contains("distance") && !j.contains("view"))
      throw Error(where + ": \"distance\" is a named view's; an orbit's is its third number");
    CameraKeyframe k;
    if (j.contains("fov")) {
      if (!j["fov"].is_number() || j["fov"].get<double>() <= 0.0 || j["fov"].get<double>() >= 180.0)
        throw Error(where + ": \"fov\" must be a number of degrees in (0, 180)");
      k.camera.fovYDeg = j["fov"].get<double>();
    }
    if (j.contains("view")) {
      std::string names;
      std::optional<AnatomicalView> view;
      for (const auto& [name, named] : kAnatomicalViewNames) {
        names += std::string(names.empty() ? "" : ", ") + name;
        if (j["view"].is_string() && j["view"].get<std::string>() == name) view = named;
      }
      if (!view) throw Error(where + ": \"view\" must be one of " + names);
      double distance = kDefaultViewDistance;
      if (j.contains("distance")) {
        if (!j["distance"].is_number() || !(j["distance"].get<double>() > 0.0))
          throw Error(where + ": \"distance\" must be a positive number (bounding-sphere radii)");
        distance = j["distance"].get<double>();
      }
      // The sides as orbits (their eyes at elevation 0, z up), so that a path between them turns around
      // the volume; above and below as the cameras --view gives.
      const double azimuth = *view == AnatomicalView::Anterior    ? -90.0
                             : *view == AnatomicalView::Posterior ? 90.0
                             : *view == AnatomicalView::Left      ? 0.0
                                                                  : 180.0;
      if (*view == AnatomicalView::Superior || *view == AnatomicalView::Inferior) {
        k.view = view;
        k.viewDistance = distance;
      } else {
        k.isOrbit = true;
        k.orbit = {azimuth, 0.0, distance};
      }
    } else if (j.contains("orbit")) {
      k.isOrbit = true;
      k.orbit = readVec3(j["orbit"], "orbit", where);
      if (!(k.orbit.z > 0.0))
        throw Error(where + ": \"orbit\" distance must be positive (bounding-sphere radii), got " +
                    std::to_string(k.orbit.z));
    } else if (j.contains("eye") && j.contains("target")) {
      k.camera.eye = readVec3(j["eye"], "eye", where);
      k.camera.target = readVec3(j["target"], "target", where);
      k.camera.up =
          j.contains("up") ? readVec3(j["up"], "up", where) : defaultUp(k.camera.target - k.camera.eye);
      if (const std::string problem = cameraProblem(k.camera); !problem.empty())
        throw Error(where + ": " + problem);
    } else {
      throw Error(where + ": needs \"orbit\", or \"eye\" and \"target\"");
    }
    if (j.contains("time")) {
      if (!j["time"].is_number()) throw Error(where + ": \"time\" must be a number");
      k.time = j["time"].get<double>();
      anyTime = true;
    } else {
      allTime = false;
      k.time = double(i);
    }
    path.keyframes.push_back(k);
  }
  if (anyTime && !allTime)
    throw Error("camera path " + sourceName + ": give \"time\" for every keyframe or none");
  for (size_t i = 1; i < path.keyframes.size(); ++i)
    if (path.keyframes[i].time <= path.keyframes[i - 1].time)
      throw Error("camera path " + sourceName + ": keyframe times must increase (keyframe " +
                  std::to_string(i) + ")");
  if (!std::isfinite(path.keyframes.back().time - path.keyframes.front().time))
    throw Error("camera path " + sourceName + ": the keyframe times span more than the largest number");
  return path;
}

CameraPath loadCameraPath(const std::string& path) {
  return parseCameraPath(readTextInput(path, "camera path " + path), path);
}

Camera sampleCameraPath(const CameraPath& path, uint32_t frame, uint32_t frameCount, glm::dvec3 boxMin,
                        glm::dvec3 boxMax) {
  const auto& keys = path.keyframes;
  if (keys.empty()) throw Error("sampleCameraPath: empty path");
  if (keys.size() == 1 || frameCount <= 1) return keyframeCamera(keys.front(), boxMin, boxMax);
  const double t0 = keys.front().time, t1 = keys.back().time;
  const double t = t0 + (t1 - t0) * double(std::min(frame, frameCount - 1)) / double(frameCount - 1);
  size_t i = 0;
  while (i + 2 < keys.size() && keys[i + 1].time <= t) ++i;
  const CameraKeyframe& a = keys[i];
  const CameraKeyframe& b = keys[i + 1];
  const double s = std::clamp((t - a.time) / (b.time - a.time), 0.0, 1.0);
  const double fov = glm::mix(a.camera.fovYDeg, b.camera.fovYDeg, s);
  if (a.isOrbit && b.isOrbit) {
    const glm::dvec3 o = glm::mix(a.orbit, b.orbit, s);
    return orbitCamera(o.x, o.y, o.z, boxMin, boxMax, fov);
  }
  const Camera ca = keyframeCamera(a, boxMin, boxMax), cb = keyframeCamera(b, boxMin, boxMax);
  Camera c;
  c.eye = glm::mix(ca.eye, cb.eye, s);
  c.target = glm::mix(ca.target, cb.target, s);
  c.up = glm::mix(ca.up, cb.up, s);
  c.fovYDeg = fov;
  return c;
}

}  // namespace ropecast
