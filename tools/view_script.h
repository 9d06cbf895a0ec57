// ViewScript: the timed input events of `ropecast view --script EVENTS.json` (docs/VIEWER.md "Scripts"), for
// tests and demos: mouse presses, moves and releases (and drags made of them), wheel clicks, held keys, and
// named UI actions (set the isovalue, mode, crop box, clip plane, time point, channel or lighting, play a
// series, load a transfer function, take a screenshot, save the camera, probe a point, center on one, measure
// between two, wait until the view has converged, quit). Parsing only: the viewer applies the events. Plain
// data; GL-free; any thread.
//
// File format: a JSON array of events, or {"events": [...]}; each an object with "event" (its kind) and
// "at" (seconds after the first frame; default: the event before's, 0 for the first). Events run in file
// order; an event never runs before its time, and "screenshot", "probe", "center_at", "measure" and
// "wait_converged" hold back the ones after them until the view has converged.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/orientation.h"
#include "core/render_params.h"

namespace ropecast::tools {

enum class ViewEventKind {
  MouseDown,     // button at pos (shift: shift held)
  MouseMove,     // the pointer to pos
  MouseUp,       // button at pos
  Wheel,         // clicks (positive: closer; shift: the clip plane a voxel per click toward the eye)
  KeyDown,       // key
  KeyUp,         // key
  SetIso,        // value (data units)
  SetMode,       // mode
  LoadTf,        // tf: a preset name or a JSON file
  SetTfRange,    // range: LO,HI, a window as --tf-range sets it
  SetCrop,       // crop: --crop's three voxel ranges
  SetClipPlane,  // plane: --clip-plane's six numbers, or none; slab: --slab's thickness (0: none)
  SetCaps,       // caps: isosurface caps at the cuts on or off, as --caps
  SetTimePoint,  // timePoint: a series' time point, as --time picks one; what waits for the view waits for it
  SetChannel,    // channel: a file's channel, as --channel picks one; what waits for the view waits for it
  Play,          // playing: a series played or stopped; secondsEach (-1: as it was)
  SetLighting,   // isoColor, shading, material, as --iso-color, --shading and --material: those given
  Screenshot,    // file; panels: the whole window with its panels, else the 3D view alone
  SaveCamera,    // file: appended to as a camera path `render --path` reads
  ResetCamera,   // back to the starting view
  SetView,       // view: a named side of the patient, as --view (at the current distance)
  Probe,         // pos: prints what the probe finds there (voxel and value) to stdout, once converged
  CenterAt,      // pos: the point there becomes the orbit's center (a double click), once converged
  Measure,       // pos, to: the ruler between the points there (two right clicks), printed; once converged
  WaitConverged,  // nothing but waiting
  Quit,
};

enum class MouseButton { Left, Middle, Right };

struct ViewEvent {
  double atSeconds = 0.0;
  ViewEventKind kind = ViewEventKind::WaitConverged;
  MouseButton button = MouseButton::Left;
  glm::dvec2 pos{0.0};  // window pixels, y down
  glm::dvec2 to{0.0};   // measure: the ruler's second end, as pos
  bool shift = false;
  double clicks = 0.0;
  char key = 0;  // lower case: w a s d q e r
  double value = 0.0;
  RenderMode mode = RenderMode::Iso;
  std::string tf;
  std::vector<std::string> crop;
  std::vector<double> plane;  // X,Y,Z,NX,NY,NZ, or empty
  double slab = 0.0;          // set_clip_plane: --slab's thickness about the plane; 0: the half-space
  bool caps = true;
  uint32_t timePoint = 0;
  uint32_t channel = 0;
  bool playing = false;
  double secondsEach = -1.0;
  std::optional<glm::dvec3> isoColor;
  std::optional<bool> shading;
  std::vector<double> material;  // KA,KD,KS,SHININESS, or empty
  AnatomicalView view = AnatomicalView::Anterior;
  glm::dvec2 range{0.0};  // LO < HI, data units
  std::string file;
  bool panels = false;
  std::string where;  // "--script EVENTS.json: event 3 (drag)": names the event in errors while it runs
};

struct ViewScript {
  std::vector<ViewEvent> events;  // "drag" and "key" with "seconds" are expanded into their parts
};

// Limits that keep every event's arithmetic finite (a drag's moves, a camera turned or panned by them, a time
// plus its seconds): larger values are refused at load.
constexpr double kMaxScriptPixels = 1e6;   // |x|, |y| of a position, in window pixels
constexpr double kMaxScriptSeconds = 1e6;  // "at" and "seconds"

// Parses the JSON text; `sourceName` (a file name) is named in errors (ropecast::Error), with the event's
// index. "drag" {"from": [x, y], "to": [x, y], "button", "shift", "steps" (moves, default 8), "seconds" (the
// moves spread over it, default 0)} becomes a press, `steps` moves and a release; "key" {"key", "seconds"}
// a key press and its release `seconds` later.
ViewScript parseViewScript(const std::string& text, const std::string& sourceName);
ViewScript loadViewScript(const std::string& path);

}  // namespace ropecast::tools
