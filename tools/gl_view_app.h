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
#include "tools/output_guard.h"
#include "tools/view_script.h"

namespace ropecast::tools {

// The scene options of render (addSceneOptions) and the viewer's own; of RenderOptions' other fields the
// viewer reads maxFrames and stats (below), the rest (-o, --exr, --frames, --path, ...) are render's alone.
struct ViewOptions : RenderOptions {
  std::string script;      // --script EVENTS.json
  std::string screenshot;  // --screenshot OUT.png: after the script (if any), once converged; then exit
  // RenderOptions' maxFrames (--max-frames): frames a screenshot or wait_converged waits for convergence
  // before it runs anyway; its stats (--stats): one JSON line per rendered frame, as render writes.
};

// Where an EXR screenshot NAME.exr puts its depth image: NAME_depth.exr beside it.
std::string screenshotDepthPath(const std::string& exrPath);

// Runs the viewer until its window closes, the script quits or ends, or a --screenshot is written. Returns
// the exit code. Throws ropecast::Error for bad inputs, for a missing display, and for a script event that
// fails (naming it). `guard` holds the inputs and every output of the command line and script, already
// checked: a file the panels write is checked against it, and refused in the panel.
int runViewer(const ViewOptions& options, std::optional<ViewScript> script, OutputGuard guard);

}  // namespace ropecast::tools
