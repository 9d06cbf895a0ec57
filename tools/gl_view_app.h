// ViewerApp: the interactive viewer behind `ropecast view` (docs/VIEWER.md): a window
// (render/window_context), the FrameRenderer that `render` uses, drawing asynchronous frames that never wait
// for the disk, the 3D view shown from its color image, Dear ImGui panels, the orbit camera
// (core/orbit_controller) and scripted input (tools/view_script). The command line lives in
// tools/gl_cmd_view.cpp.
//
// Main thread only: GLFW, ImGui and every GL call.
#pragma once

#include <optional>
#include <string>

#include "tools/gl_render_options.h"
#include "tools/view_script.h"

namespace ropecast::tools {

struct ViewOptions : RenderOptions {
  std::string script;         // --script EVENTS.json
  std::string screenshot;     // --screenshot OUT.png: after the script (if any), once converged; then exit
  uint32_t maxFrames = 1000;  // frames a screenshot waits for convergence before it is taken anyway
  std::string stats;          // --stats OUT.jsonl: one JSON line per rendered frame, as render writes
};

// Runs the viewer until its window closes, the script quits or ends, or a --screenshot is written. Returns
// the exit code. Throws ropecast::Error for bad inputs and for a missing display.
int runViewer(const ViewOptions& options, std::optional<ViewScript> script);

}  // namespace ropecast::tools
