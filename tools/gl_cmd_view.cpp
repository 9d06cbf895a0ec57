// `ropecast view`: the interactive viewer (docs/VIEWER.md) over the FrameRenderer that `render` uses; the
// options it shares with `render` come from tools/gl_render_options.h. The viewer is tools/gl_view_app.
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/camera_path.h"
#include "core/error.h"
#include "core/file_names.h"
#include "core/temporary_file.h"
#include "core/transfer_function.h"
#include "reference/image_io.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"
#include "tools/command.h"
#include "tools/gl_view_app.h"
#include "tools/output_guard.h"

namespace ropecast::tools {
namespace {

// An image the viewer will write: a writer for it (its folder exists, its extension is known), and, for an
// EXR, the depth image beside it (NAME_depth.exr) as an output too.
void addImageOutput(OutputGuard& guard, const std::string& what, const std::string& path) {
  const bool exr = hasExtension(path, ".exr");
  if (const std::string problem =
          imageOutputProblem(path, exr ? ImageOutputKind::FloatExr : ImageOutputKind::Color8);
      !problem.empty())
    throw Error(what + " " + path + ": " + problem);
  guard.addOutput(what, path);
  if (!exr) return;
  // "--screenshot (its depth)", "a screenshot event of --script S.json (its depth):"
  const bool colon = what.ends_with(':');
  guard.addOutput(what.substr(0, what.size() - colon) + " (its depth)" + (colon ? ":" : ""),
                  screenshotDepthPath(path));
}

// A save_camera event appends to its file: one that exists must be a camera path already (a folder is the
// guard's to refuse).
void checkAppendableCameraPath(const ViewEvent& e) {
  if (!std::filesystem::is_regular_file(e.file)) return;
  try {
    loadCameraPath(e.file);
  } catch (const Error& error) {
    throw Error(e.where + ": " + e.file + " exists and is not a camera path to append to: " + error.what());
  }
}

int runView(const ViewOptions& o) {
  checkSceneOptions(o);
  // No file the viewer writes, from its command line or its script's events, may be one it reads, or
  // another of its outputs: checked before the window opens, the command line's before the script is read.
  OutputGuard guard("view");
  guard.addVolumeInput("the input", o.input);
  if (std::filesystem::is_regular_file(o.tf)) guard.addInput("--tf", o.tf);
  guard.addInput("--script", o.script);
  if (!o.screenshot.empty()) addImageOutput(guard, "--screenshot", o.screenshot);
  guard.addOutput("--stats", o.stats);
  guard.check();
  std::optional<ViewScript> script;
  if (!o.script.empty()) script = loadViewScript(o.script);
  if (script) {
    const std::string of = " event of --script " + o.script;
    // An event may name the file of an earlier one again, under any spelling.
    std::set<std::string> screenshots, cameras, tfs;
    for (const ViewEvent& e : script->events) {
      if (e.kind == ViewEventKind::Screenshot && screenshots.insert(fileIdentity(e.file)).second)
        addImageOutput(guard, "a screenshot" + of + ":", e.file);
      if (e.kind == ViewEventKind::SaveCamera && cameras.insert(fileIdentity(e.file)).second) {
        const std::filesystem::path parent = std::filesystem::path(e.file).parent_path();
        if (!parent.empty() && !std::filesystem::is_directory(parent))
          throw Error("a save_camera" + of + ": " + e.file + ": its folder does not exist");
        checkAppendableCameraPath(e);
        guard.addOutput("a save_camera" + of + ":", e.file);  // appended to: read and written
      }
      if (e.kind == ViewEventKind::LoadTf && tfs.insert(e.tf).second) {
        if (TransferFunction::isPreset(e.tf)) continue;
        if (!std::filesystem::is_regular_file(e.tf))
          throw Error("a load_tf" + of + ": '" + e.tf + "' is neither a preset nor a transfer function file");
        try {
          TransferFunction::fromFile(e.tf);
        } catch (const Error& error) {
          throw Error(e.where + ": " + error.what());
        }
        guard.addInput("a load_tf" + of + ":", e.tf);
      }
    }
  }
  guard.check();
  removeTemporaryFilesOnSignals();  // an interrupted viewer leaves no half-written --stats or screenshot
  return runViewer(o, std::move(script), std::move(guard));
}

const CommandRegistration viewCommand("view", 55, [](CLI::App& app) -> std::function<int()> {
  auto o = std::make_shared<ViewOptions>();
  app.description(
      "view a store, a volume or procedural:NAME:SIZE in a window (X11, OpenGL 4.5): orbit, pan, zoom, fly, "
      "center on a point; probe and ruler; panels for mode, isovalue, transfer function, rendering settings, "
      "lighting, time points and channels, stats");
  app.add_option("input", o->input,
                 "store file (.rcast), a volume as convert reads it (converted to a temporary store first), "
                 "or procedural:NAME:SIZE")
      ->required();
  addSceneOptions(app, *o, SceneCommand::View);
  app.add_option("--script", o->script,
                 "timed input events and UI actions (JSON, docs/VIEWER.md); the viewer exits after the last")
      ->check(notEmpty("a script file"));
  app.add_option(
         "--screenshot", o->screenshot,
         "once the view has converged (after --script, if given), write the 3D view without the panels "
         "as PNG and exit")
      ->check(nonEmptyPath("a file"));
  app.add_option("--stats", o->stats,
                 "write one JSON object per rendered frame, one per line (render's fields)")
      ->check(nonEmptyPath("a file"));
  app.add_option("--max-frames", o->maxFrames,
                 "frames a screenshot or wait_converged waits for the view to converge (then it runs anyway)")
      ->transform(integerRange(1, 1000000))
      ->capture_default_str();
  return [o] { return runView(*o); };
});

}  // namespace
}  // namespace ropecast::tools
