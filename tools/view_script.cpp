#include "tools/view_script.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/file_names.h"
#include "core/input_file.h"
#include "core/json_keys.h"
#include "reference/image_io.h"
#include "tools/cli_values.h"

namespace ropecast::tools {

namespace {

using nlohmann::json;

struct EventReader {
  const json& j;
  std::string where;                                  // "EVENTS.json: event 3 (drag)"
  mutable std::set<std::string> read{"event", "at"};  // the keys this kind of event takes

  // A key the event's kind does not read is refused: a misspelt one would silently do nothing.
  void refuseOtherKeys() const {
    for (const auto& [key, value] : j.items())
      if (!read.contains(key)) {
        std::string known;
        for (const std::string& k : read) known += (known.empty() ? "\"" : ", \"") + k + "\"";
        fail("unknown key \"" + key + "\"; this event takes " + known);
      }
  }

  [[noreturn]] void fail(const std::string& what) const { throw Error(where + ": " + what); }

  double number(const char* name, double fallback, bool required = false) const {
    read.insert(name);
    if (!j.contains(name)) {
      if (required) fail(std::string("\"") + name + "\" is required");
      return fallback;
    }
    if (!j[name].is_number() || !std::isfinite(j[name].get<double>()))
      fail(std::string("\"") + name + "\" must be a finite number");
    return j[name].get<double>();
  }
  std::string text(const char* name, bool required = true) const {
    read.insert(name);
    if (!j.contains(name)) {
      if (required) fail(std::string("\"") + name + "\" is required");
      return "";
    }
    if (!j[name].is_string() || j[name].get<std::string>().empty())
      fail(std::string("\"") + name + "\" must be a non-empty string");
    return j[name].get<std::string>();
  }
  bool flag(const char* name) const {
    read.insert(name);
    if (!j.contains(name)) return false;
    if (!j[name].is_boolean()) fail(std::string("\"") + name + "\" must be true or false");
    return j[name].get<bool>();
  }
  glm::dvec2 point(const char* name) const {
    read.insert(name);
    if (!j.contains(name)) fail(std::string("\"") + name + "\" is required");
    const json& p = j[name];
    auto inRange = [](const json& v) {
      return v.is_number() && std::abs(v.get<double>()) <= kMaxScriptPixels;  // NaN compares false
    };
    if (!p.is_array() || p.size() != 2 || !inRange(p[0]) || !inRange(p[1]))
      fail(std::string("\"") + name + "\" must be [x, y] in window pixels, each within +-1e6");
    return {p[0].get<double>(), p[1].get<double>()};
  }
  // A window as --tf-range takes it: [lo, hi], finite, lo < hi.
  glm::dvec2 range(const char* name) const {
    read.insert(name);
    if (!j.contains(name)) fail(std::string("\"") + name + "\" is required");
    const json& p = j[name];
    const auto finite = [](const json& v) { return v.is_number() && std::isfinite(v.get<double>()); };
    if (!p.is_array() || p.size() != 2 || !finite(p[0]) || !finite(p[1]) ||
        !(p[0].get<double>() < p[1].get<double>()))
      fail(std::string("\"") + name + "\" must be [lo, hi] in data units, lo < hi, as --tf-range takes them");
    return {p[0].get<double>(), p[1].get<double>()};
  }
  // A plane as --clip-plane takes it, [x, y, z, nx, ny, nz] (finite numbers), or [] for none.
  std::vector<double> plane(const char* name) const {
    read.insert(name);
    if (!j.contains(name)) fail(std::string("\"") + name + "\" is required");
    const json& p = j[name];
    const auto finite = [](const json& v) { return v.is_number() && std::isfinite(v.get<double>()); };
    if (!p.is_array() || (p.size() != 6 && p.size() != 0) || !std::all_of(p.begin(), p.end(), finite))
      fail(std::string("\"") + name +
           "\" must be [x, y, z, nx, ny, nz] (a point and the normal of the side drawn), or [] for none");
    std::vector<double> values;
    for (const json& v : p) values.push_back(v.get<double>());
    return values;
  }
  // One of a table's names ({name, value} pairs: kRenderModeNames, kAnatomicalViewNames): its value.
  template <typename Table>
  auto named(const char* name, const Table& table) const {
    const std::string given = text(name);
    std::vector<std::string> names;
    for (const auto& [known, value] : table) {
      if (given == known) return value;
      names.emplace_back(known);
    }
    fail(std::string("\"") + name + "\" must be " + alternatives(names) + ", got \"" + given + "\"");
  }
  // Seconds: "at" or "seconds", in [0, kMaxScriptSeconds].
  double seconds(const char* name, double fallback) const {
    const double s = number(name, fallback);
    if (s < 0.0) fail(std::string("\"") + name + "\" must not be negative");
    if (s > kMaxScriptSeconds) fail(std::string("\"") + name + "\" must be at most 1e6 seconds");
    return s;
  }
  MouseButton button() const {
    read.insert("button");
    const std::string b = j.contains("button") ? text("button") : "left";
    if (b == "left") return MouseButton::Left;
    if (b == "middle") return MouseButton::Middle;
    if (b == "right") return MouseButton::Right;
    fail("\"button\" must be left, middle or right, got \"" + b + "\"");
  }
  char key() const {
    const std::string k = text("key");
    if (k.size() == 1 && std::string("wasdqer").find(char(std::tolower(k[0]))) != std::string::npos)
      return char(std::tolower(k[0]));
    fail("\"key\" must be one of w a s d q e r, got \"" + k + "\"");
  }
};

}  // namespace

ViewScript parseViewScript(const std::string& text, const std::string& sourceName) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
    throw Error(sourceName + ": not JSON: " + e.what());
  }
  if (const std::string key = duplicateJsonKey(text); !key.empty())
    throw Error(sourceName + ": the key \"" + key +
                "\" is given twice in one object (only the last would count)");
  const json* list = &root;
  if (root.is_object() && root.contains("events")) {
    list = &root["events"];
    for (const auto& [key, value] : root.items())
      if (key != "events")
        throw Error(sourceName + ": unknown key \"" + key + "\"; expected {\"events\": [...]}");
  }
  if (!list->is_array()) throw Error(sourceName + ": expected an array of events or {\"events\": [...]}");

  ViewScript script;
  double lastAt = 0.0;
  for (size_t i = 0; i < list->size(); ++i) {
    const json& j = (*list)[i];
    if (!j.is_object() || !j.contains("event") || !j["event"].is_string())
      throw Error(sourceName + ": event " + std::to_string(i) + ": an object with \"event\" naming its kind");
    const std::string kind = j["event"].get<std::string>();
    EventReader r{j, sourceName + ": event " + std::to_string(i) + " (" + kind + ")"};
    ViewEvent e;
    e.where = r.where;
    e.atSeconds = r.seconds("at", lastAt);
    lastAt = e.atSeconds;
    auto add = [&](ViewEvent event) { script.events.push_back(std::move(event)); };
    if (kind == "mouse_down" || kind == "mouse_up") {
      e.kind = kind == "mouse_down" ? ViewEventKind::MouseDown : ViewEventKind::MouseUp;
      e.pos = r.point("pos");
      e.button = r.button();
      e.shift = r.flag("shift");
      add(e);
    } else if (kind == "mouse_move") {
      // No "button": a move drags with the buttons mouse_down left held.
      e.kind = ViewEventKind::MouseMove;
      e.pos = r.point("pos");
      e.shift = r.flag("shift");
      add(e);
    } else if (kind == "drag") {
      const glm::dvec2 from = r.point("from"), to = r.point("to");
      const double steps = r.number("steps", 8.0);
      const double seconds = r.seconds("seconds", 0.0);
      if (steps < 1.0 || steps > 10000.0 || steps != std::floor(steps))
        r.fail("\"steps\" must be in [1, 10000]");
      e.button = r.button();
      e.shift = r.flag("shift");
      e.kind = ViewEventKind::MouseDown;
      e.pos = from;
      add(e);
      for (int s = 1; s <= int(steps); ++s) {
        ViewEvent move = e;
        move.kind = ViewEventKind::MouseMove;
        move.atSeconds = e.atSeconds + seconds * s / steps;
        move.pos = from + (to - from) * (double(s) / steps);
        add(move);
      }
      ViewEvent up = e;
      up.kind = ViewEventKind::MouseUp;
      up.atSeconds = e.atSeconds + seconds;
      up.pos = to;
      add(up);
      lastAt = up.atSeconds;
    } else if (kind == "wheel") {
      e.kind = ViewEventKind::Wheel;
      e.clicks = r.number("clicks", 0.0, true);
      e.shift = r.flag("shift");
      add(e);
    } else if (kind == "key" || kind == "key_down" || kind == "key_up") {
      e.key = r.key();
      e.kind = kind == "key_up" ? ViewEventKind::KeyUp : ViewEventKind::KeyDown;
      add(e);
      if (kind == "key") {
        const double seconds = r.seconds("seconds", 0.0);
        ViewEvent up = e;
        up.kind = ViewEventKind::KeyUp;
        up.atSeconds = e.atSeconds + seconds;
        add(up);
        lastAt = up.atSeconds;
      }
    } else if (kind == "set_iso") {
      e.kind = ViewEventKind::SetIso;
      e.value = r.number("value", 0.0, true);
      add(e);
    } else if (kind == "set_mode") {
      e.kind = ViewEventKind::SetMode;
      e.mode = r.named("mode", kRenderModeNames);
      add(e);
    } else if (kind == "set_crop") {
      e.kind = ViewEventKind::SetCrop;
      const std::string ranges = r.text("crop");
      const std::optional<std::vector<std::string>> split = splitVoxelRanges(ranges);
      if (!split)
        r.fail("\"crop\" must be three voxel ranges X0:X1,Y0:Y1,Z0:Z1 as --crop takes them, got \"" + ranges +
               "\"");
      e.crop = *split;
      add(e);
    } else if (kind == "set_clip_plane") {
      e.kind = ViewEventKind::SetClipPlane;
      e.plane = r.plane("plane");
      e.slab = r.number("slab", 0.0);
      if (!(e.slab >= 0.0 && e.slab <= 1e15))
        r.fail("\"slab\" must be a thickness from 0 (none) to 1e15, as --slab takes it");
      if (e.slab > 0.0 && e.plane.empty()) r.fail("\"slab\" is about a plane: give \"plane\" too");
      add(e);
    } else if (kind == "set_caps") {
      e.kind = ViewEventKind::SetCaps;
      if (!r.j.contains("caps")) r.fail("\"caps\" is required");
      e.caps = r.flag("caps");
      add(e);
    } else if (kind == "set_time_point" || kind == "set_channel") {
      const bool time = kind == "set_time_point";
      e.kind = time ? ViewEventKind::SetTimePoint : ViewEventKind::SetChannel;
      const char* key = time ? "time_point" : "channel";
      const double index = r.number(key, 0.0, true);
      if (!(index >= 0.0 && index <= double(UINT32_MAX) && index == std::floor(index)))
        r.fail(std::string("\"") + key + "\" must be a whole number from 0, counted as " +
               (time ? "--time" : "--channel") + " counts them");
      (time ? e.timePoint : e.channel) = uint32_t(index);
      add(e);
    } else if (kind == "set_lighting") {
      e.kind = ViewEventKind::SetLighting;
      if (r.j.contains("iso_color")) {
        const json& c = r.j["iso_color"];
        const auto unit = [](const json& v) {
          return v.is_number() && v.get<double>() >= 0.0 && v.get<double>() <= 1.0;  // NaN compares false
        };
        if (!c.is_array() || c.size() != 3 || !unit(c[0]) || !unit(c[1]) || !unit(c[2]))
          r.fail("\"iso_color\" must be [r, g, b], each in [0, 1], as --iso-color takes it");
        e.isoColor = glm::dvec3(c[0].get<double>(), c[1].get<double>(), c[2].get<double>());
      }
      r.read.insert("iso_color");
      if (r.j.contains("shading")) e.shading = r.flag("shading");
      r.read.insert("shading");
      if (r.j.contains("material")) {
        const json& m = r.j["material"];
        if (m.is_array() && m.size() == 4)
          for (const json& v : m)
            if (v.is_number()) e.material.push_back(v.get<double>());
        const std::string problem = e.material.size() == 4 ? materialProblem("\"material\"", e.material)
                                                           : "\"material\" must be [ka, kd, ks, shininess]";
        if (!problem.empty()) r.fail(problem + ", as --material takes them");
      }
      r.read.insert("material");
      if (!e.isoColor && !e.shading && e.material.empty())
        r.fail("give \"iso_color\", \"shading\" or \"material\"");
      add(e);
    } else if (kind == "play") {
      e.kind = ViewEventKind::Play;
      if (!r.j.contains("playing")) r.fail("\"playing\" is required");
      e.playing = r.flag("playing");
      e.secondsEach = r.number("seconds_each", -1.0);
      if (r.j.contains("seconds_each") && !(e.secondsEach >= 0.0 && e.secondsEach <= kMaxScriptSeconds))
        r.fail("\"seconds_each\" must be seconds from 0 to 1e6");
      add(e);
    } else if (kind == "load_tf") {
      e.kind = ViewEventKind::LoadTf;
      e.tf = r.text("tf");
      add(e);
    } else if (kind == "set_tf_range") {
      e.kind = ViewEventKind::SetTfRange;
      e.range = r.range("range");
      add(e);
    } else if (kind == "screenshot") {
      e.kind = ViewEventKind::Screenshot;
      e.file = r.text("file");
      e.panels = r.flag("panels");
      // The window is 8-bit: a float EXR of it would hold no more than a PNG, and no depth.
      if (e.panels && hasExtension(e.file, ".exr"))
        r.fail("\"panels\": true writes a PNG of the window; an EXR screenshot is the 3D view alone");
      add(e);
    } else if (kind == "save_camera") {
      e.kind = ViewEventKind::SaveCamera;
      e.file = r.text("file");
      add(e);
    } else if (kind == "set_view") {
      e.kind = ViewEventKind::SetView;
      e.view = r.named("view", kAnatomicalViewNames);
      add(e);
    } else if (kind == "probe" || kind == "center_at") {
      e.kind = kind == "probe" ? ViewEventKind::Probe : ViewEventKind::CenterAt;
      e.pos = r.point("pos");
      add(e);
    } else if (kind == "measure") {
      e.kind = ViewEventKind::Measure;
      e.pos = r.point("from");
      e.to = r.point("to");
      add(e);
    } else if (kind == "reset_camera") {
      e.kind = ViewEventKind::ResetCamera;
      add(e);
    } else if (kind == "wait_converged") {
      e.kind = ViewEventKind::WaitConverged;
      add(e);
    } else if (kind == "quit") {
      e.kind = ViewEventKind::Quit;
      add(e);
    } else {
      r.fail(
          "unknown event; expected mouse_down, mouse_move, mouse_up, drag, wheel, key, key_down, key_up, "
          "set_iso, set_mode, set_crop, set_clip_plane, set_caps, set_time_point, set_channel, play, "
          "set_lighting, load_tf, set_tf_range, screenshot, save_camera, set_view, probe, center_at, "
          "measure, "
          "reset_camera, wait_converged or quit");
    }
    r.refuseOtherKeys();
  }
  return script;
}

ViewScript loadViewScript(const std::string& path) {
  return parseViewScript(readTextInput(path, "--script " + path), "--script " + path);
}

}  // namespace ropecast::tools
