// `ropecast view`: the interactive viewer (docs/VIEWER.md) over the FrameRenderer that `render` uses; the
// options it shares with `render` come from tools/gl_render_options.h. The viewer is tools/gl_view_app.
#include <filesystem>
#include <memory>

#include "core/error.h"
#include "reference/image_io.h"
#include "tools/command.h"
#include "tools/gl_view_app.h"
#include "tools/output_guard.h"

namespace ropecast::tools {
namespace {

int runView(const ViewOptions& o) {
  const bool exr = std::filesystem::path(o.screenshot).extension() == ".exr";
  if (!o.screenshot.empty())
    if (const std::string problem =
            imageOutputProblem(o.screenshot, exr ? ImageOutputKind::FloatExr : ImageOutputKind::Color8);
        !problem.empty())
      throw Error("--screenshot " + o.screenshot + ": " + problem);
  // No file the viewer writes from its command line may be one it reads, or another of its outputs.
  OutputGuard guard("view");
  guard.addInput("the input", o.input);
  if (std::filesystem::is_regular_file(o.tf)) guard.addInput("--tf", o.tf);
  guard.addInput("--script", o.script);
  guard.addOutput("--screenshot", o.screenshot);
  if (exr) {
    const std::filesystem::path p(o.screenshot);
    guard.addOutput("--screenshot (its depth)",
                    (p.parent_path() / (p.stem().string() + "_depth.exr")).string());
  }
  guard.addOutput("--stats", o.stats);
  guard.check();
  std::optional<ViewScript> script;
  if (!o.script.empty()) script = loadViewScript(o.script);
  return runViewer(o, std::move(script));
}

const CommandRegistration viewCommand("view", 55, [](CLI::App& app) -> std::function<int()> {
  auto o = std::make_shared<ViewOptions>();
  app.description(
      "view a store or procedural:NAME:SIZE in a window (X11, OpenGL 4.5): orbit, pan, zoom, fly; panels for "
      "mode, isovalue, transfer function, rendering settings, stats");
  app.add_option("input", o->input, "store file (.rcast) or procedural:NAME:SIZE")->required();
  addSceneOptions(app, *o);
  app.add_option("--script", o->script,
                 "timed input events and UI actions (JSON, docs/VIEWER.md); the viewer exits after the last");
  app.add_option(
      "--screenshot", o->screenshot,
      "once the view has converged (after --script, if given), write the 3D view without the panels "
      "as PNG and exit");
  app.add_option("--stats", o->stats,
                 "write one JSON object per rendered frame, one per line (render's fields)");
  app.add_option("--max-frames", o->maxFrames, "frames a screenshot waits for the view to converge")
      ->check(CLI::Range(1u, 1000000u))
      ->capture_default_str();
  return [o] { return runView(*o); };
});

}  // namespace
}  // namespace ropecast::tools
