#include "tools/gl_view_app.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <iterator>
#include <map>
#include <memory>
#include <set>
#include <span>
#include <utility>

#include <epoxy/gl.h>
// epoxy's GL header first: GLFW then includes no GL header of its own.
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <imgui_stdlib.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include "core/camera_path.h"
#include "core/elapsed.h"
#include "core/error.h"
#include "core/file_names.h"
#include "core/input_file.h"
#include "core/orbit_controller.h"
#include "core/orientation.h"
#include "core/temporary_file.h"
#include "loader/io_queue.h"
#include "reference/image_io.h"
#include "render/frame_renderer.h"
#include "render/step_pacer.h"
#include "render/window_context.h"
#include "store/async_voxel_reader.h"
#include "store/extract.h"
#include "store/store.h"
#include "store/value_histogram.h"
#include "tools/cli_values.h"
#include "tools/gl_view_tf_editor.h"
#include "tools/output_guard.h"
#include "tools/stats_writer.h"
#include "tools/temporary_store.h"
#include "tools/view_outline.h"
#include "tools/view_probe.h"
#include "tools/view_series.h"
#include "tools/volume_read_options.h"

namespace ropecast::tools {

namespace {

// The camera counts as moving this long after its last change: frames stay coarse between the events of one
// drag, and refine once the user lets go.
constexpr double kStillAfterSeconds = 0.25;
// Frame times the stats graph shows.
constexpr size_t kFrameHistory = 120;

// The script's events that wait until the shown view has converged: they read or write what it shows.
bool waitsForConvergence(ViewEventKind kind) {
  return kind == ViewEventKind::Screenshot || kind == ViewEventKind::WaitConverged ||
         kind == ViewEventKind::Probe || kind == ViewEventKind::CenterAt || kind == ViewEventKind::Measure;
}

// The mouse as the camera sees it: position in window pixels (y down) and the buttons held.
struct Pointer {
  glm::dvec2 pos{0.0};
  bool left = false, middle = false, shift = false;
};

// Appends the view to a camera-path JSON (core/camera_path.h) that `render --path` reads: an orbit keyframe
// while the camera orbits the volume's center, else eye, target, up.
void appendCameraKeyframe(const std::string& path, const OrbitController& controller) {
  nlohmann::json root = nlohmann::json::array();
  if (std::filesystem::exists(path)) {
    const std::string text = readTextInput(path, "save camera: " + path);
    parseCameraPath(text, path);  // refuses to append to something that is not a camera path
    root = nlohmann::json::parse(text);
  }
  nlohmann::json& list = root.is_object() ? root["keyframes"] : root;
  const Camera c = controller.camera();
  nlohmann::json key;
  if (const auto orbit = controller.renderOrbit())
    key = {{"orbit", {orbit->x, orbit->y, orbit->z}}, {"fov", c.fovYDeg}};
  else
    key = {{"eye", {c.eye.x, c.eye.y, c.eye.z}},
           {"target", {c.target.x, c.target.y, c.target.z}},
           {"up", {c.up.x, c.up.y, c.up.z}},
           {"fov", c.fovYDeg}};
  // A path gives every keyframe a time or none (parseCameraPath), the times increasing: the new keyframe
  // comes a second after the last.
  if (!list.empty() && list.back().contains("time")) key["time"] = list.back()["time"].get<double>() + 1.0;
  list.push_back(key);
  const std::string text = root.dump(2) + '\n';
  writeFileAtomically(path, std::as_bytes(std::span(text)), "save camera");
}

void saveTransferFunction(const std::string& path, const TransferFunction& tf) {
  nlohmann::json points = nlohmann::json::array();
  for (const TfPoint& p : tf.points()) points.push_back({p.value, p.rgba.r, p.rgba.g, p.rgba.b, p.rgba.a});
  const std::string text = nlohmann::json{{"points", points}}.dump() + '\n';
  writeFileAtomically(path, std::as_bytes(std::span(text)), "save transfer function");
}

// The window's default framebuffer, panels included, as an image with row 0 at the top.
FloatImage readWindow(uint32_t width, uint32_t height) {
  std::vector<uint8_t> rgba(size_t(width) * height * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, GLsizei(width), GLsizei(height), GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  FloatImage image;
  image.width = width;
  image.height = height;
  image.channels = 4;
  image.pixels.resize(rgba.size());
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t i = 0; i < width * 4; ++i)
      image.pixels[size_t(y) * width * 4 + i] = rgba[size_t(height - 1 - y) * width * 4 + i] / 255.0f;
  return image;
}

class Viewer {
 public:
  Viewer(const ViewOptions& o, std::optional<ViewScript> script, OutputGuard guard);
  ~Viewer();
  int run();

 private:
  // Scene state the panels and the script change.
  // A preset or file chosen by --tf, the panel or a script; empty: the mode's default, not a choice.
  void setTransferFunction(const std::string& spec);
  void setTransferFunction(TransferFunction function, const std::string& name);
  // A window (--tf-range, the panel, a script): the current function stretched over [lo, hi], and every
  // one chosen later.
  void setTfRange(double lo, double hi);
  void setMode(RenderMode mode);
  void keepSlicePlane();
  void stepPlane(double voxels);
  void wheel(double clicks, bool shift);
  void ensureRenderer(bool moving);
  FrameRequest currentRequest(bool moving);
  bool sameAsLast(const FrameRequest& request) const;
  bool needsFrame(const FrameRequest& request) const {
    return !lastRequest_ || !lastStats_.converged || !sameAsLast(request);
  }
  void renderFrame(const FrameRequest& request);
  void present(uint32_t width, uint32_t height);
  // Input
  void readWindowInput(double dtSeconds);
  void drive(const Pointer& before, const Pointer& now);
  void flyHeld(const std::set<char>& keys, double dtSeconds);
  // Runs the events that are due; `converged` says whether the shown view has converged.
  void runScript(bool converged);
  void runEvent(const ViewEvent& e);
  bool scriptDone() const { return script_ && nextEvent_ >= script_->events.size(); }
  // An output waits for the view to converge: --screenshot once the script is done, or a due screenshot or
  // wait_converged event.
  bool waitingForConvergence() const;
  // Seconds until the script's next event is due (0 when one is due or none is left).
  double secondsToNextEvent() const;
  void screenshot(const std::string& path, bool panels);
  // Throws when a file the panels would write is an input or an output the command line or script names.
  void checkPanelOutput(const std::string& what, const std::string& path) const;
  void reportPanelError(const std::exception& e);
  void drawPanels();
  void drawCropControls(const BrickSourceInfo& info);
  void drawSeriesControls();
  void drawLightingControls();
  void drawCutOutlines(const VolumeInfo& volume);
  // The sides of the patient at the 3D view's edges and the volume's axes at its bottom.
  void drawOrientationMarks();
  // The drawn frame's pixel under the window point `pos`; nullopt before the first frame and outside the
  // view.
  std::optional<glm::u32vec2> pixelAt(glm::dvec2 pos) const;
  // Where that pixel's ray stopped in the drawn frame (view_probe.h), its voxel the file's indices; nullopt
  // where it met nothing.
  std::optional<ProbedVoxel> probedAt(glm::u32vec2 pixel) const;
  // The probe's line for the window point `pos` (view_probe.h); empty before the first frame and outside the
  // view. The voxel's value is read on the probe reader's thread: until it is known the line says so, unless
  // `waitForValue` (a script's probe event).
  std::string probe(glm::dvec2 pos, bool waitForValue = false);
  // What a pointer action did, or why it did nothing, for the panel and the script.
  struct Outcome {
    bool done = false;
    std::string message;
  };
  // A double click, or the script's center_at: the point under `pos` becomes the orbit's center, the camera
  // moved to it (core/camera.h centeredOn).
  Outcome centerAt(glm::dvec2 pos);
  // A right click, or an end of the script's measure: the point under `pos` ends the ruler; after two ends,
  // the next starts a new ruler. Returns what it did, or why it did nothing.
  std::string placeRulerEnd(glm::dvec2 pos);
  void drawRuler(const VolumeInfo& volume);
  void drawClipPlaneControls(const VolumeInfo& volume);
  // --view's camera at the current distance and field of view; "reset camera" still returns to the start.
  void showAnatomicalView(AnatomicalView view);

  const ViewOptions& o_;
  // The inputs and every output of the command line and script, checked before the window opened: what the
  // panels write is checked against them.
  OutputGuard guard_;
  // The input; the volumes of a file of several (time points, channels) each as a source of their own, made
  // as they are asked for.
  std::unique_ptr<BrickSource> source_;
  std::optional<SeriesStores> series_;
  uint32_t timePoints_ = 1, channels_ = 1;  // of the input
  std::vector<std::string> channelNames_;   // where the file names each channel
  struct Pick {
    uint32_t time = 0, channel = 0;
    friend bool operator==(const Pick&, const Pick&) = default;
  };
  uint32_t indexOf(Pick p) const { return p.channel * timePoints_ + p.time; }  // in series_
  BrickSource* shown_ = nullptr;          // source_, or the shown volume's
  std::unique_ptr<BrickSource> delayed_;  // --io-delay-ms over shown_
  const BrickSource& bricks() const { return delayed_ ? *delayed_ : *shown_; }
  Pick shownPick_, wantedPick_;  // of a series: the volume shown, and the one asked for
  bool pickPending() const { return shownPick_ != wantedPick_; }
  Pick nextTimePoint() const { return {(shownPick_.time + 1) % timePoints_, shownPick_.channel}; }
  // "time point 3, channel 1 'GFP'", naming what the input has several of (a channel's name where the file
  // names it).
  std::string pickName(Pick p) const;
  // Playing, the series is shown time point after time point (of the channel shown), each until its view has
  // converged and playSecondsEach_ have passed, the next made while it shows; after the last comes the first.
  bool playing_ = false;
  double playSecondsEach_ = 0.5;
  double shownAtSeconds_ = 0.0;  // script seconds when the shown volume was first drawn
  void setPlaying(bool playing);
  void playOn(bool viewConverged);
  // The panel's and the script's choice: that time point, or channel, of the volume asked for last is shown
  // once it is made.
  void askTimePoint(uint32_t t);
  void askChannel(uint32_t c);
  void askPick(Pick p);
  void checkPickable(const std::string& what, uint32_t index, uint32_t count) const;
  // Shows the wanted volume once it is made (its conversion's failure turns it back to the shown one).
  void followPick();
  // What depends on the shown source: the probe's reader, the value range and histogram, the baked transfer
  // function; the renderer is made again for it at the next frame.
  void attachShownSource();
  std::pair<double, double> valueRange_;
  // The value histogram of the octree's root brick (store/value_histogram.h): log bar heights in [0, 1].
  std::vector<float> histogram_;
  uint32_t histogramLevel_ = 0;
  glm::dvec3 boxMax_{0.0};

  RenderParams params_;
  bool unfoldCutControls_ = false;  // open the crop box and clip plane controls at the next frame
  bool orientationMarks_ = true;
  // The probe's last answer (with a value, or nothing under the pointer), kept while the pointer stays on its
  // pixel and no frame is drawn.
  struct ProbeAnswer {
    glm::u32vec2 pixel{0};
    uint64_t frame = 0;
    std::string text;
  };
  std::optional<ProbeAnswer> probeAnswer_;
  bool probeReading_ = false;  // the last probe line waits for its value
  // The ruler's ends (right clicks on the 3D view, the script's measure); one while it waits for its second.
  std::vector<ProbedVoxel> ruler_;
  double voxelsPerPixel_ = 1.0;
  double targetFrameMs_ = 0.0;
  std::string tfSpec_;
  std::vector<double> tfRange_;  // LO,HI of the window; empty: none
  bool tfChosen_ = false;        // by --tf, the panel or the script; until then each mode shows its default
  TransferFunction tf_;
  std::optional<TfTable> tfTable_;
  uint64_t tfVersion_ = 0;
  TfEditor tfEditor_;

  std::unique_ptr<WindowContext> window_;
  std::unique_ptr<FrameRenderer> renderer_;
  // The probe's values, read off the main thread; gone first (its thread wakes the window, reads the source).
  std::optional<AsyncVoxelReader> probeReader_;
  bool rendererHasGradients_ = false;
  std::optional<OrbitController> controller_;
  StepPacer stepPacer_;
  bool coarser_ = false;  // --target-frame-ms: refining at half --voxels-per-pixel while moving

  // The last rendered frame.
  std::optional<FrameRequest> lastRequest_;
  uint64_t lastTfVersion_ = 0;
  FrameStats lastStats_;
  uint64_t framesRendered_ = 0;
  double lastDrawnMs_ = 0.0;  // the last drawn frame's ms, what the stats panel shows as the frame rate
  // Of the last drawn frame's pixels, those it cast (a still view casts what changed).
  double lastCastShare_ = 0.0;
  FloatImage color_;
  // Frames the next event (or the --screenshot after the script) has waited for the view to converge; at
  // --max-frames it runs anyway, with a warning, so a camera that keeps moving cannot hold the script.
  uint64_t waitedFrames_ = 0;
  std::deque<float> frameMsHistory_;
  std::optional<StatsWriter> stats_;  // --stats, finished when the viewer ends normally
  uint32_t viewTexture_ = 0, viewFramebuffer_ = 0;
  uint32_t viewWidth_ = 0, viewHeight_ = 0;

  // Input state.
  Pointer windowPointer_, scriptPointer_;
  bool windowDragOwned_ = false;  // the button went down over the 3D view, not over a panel
  double wheelClicks_ = 0.0;
  // Scripted fly keys held: they fly on the script's clock, so a key held for S seconds flies S seconds
  // however long the frames take.
  struct ScriptKey {
    double downAt = 0.0, upAt = 0.0;  // script seconds; upAt: its release, or +inf
    double flownSeconds = 0.0;
  };
  std::map<char, ScriptKey> scriptKeys_;
  void flyScriptKeys(double nowSeconds);
  bool resetKeyDown_ = false;
  int pageKeyDown_ = 0;  // Page Up (1) or Page Down (-1) held: one plane step per press
  double lastMoveSeconds_ = -1e9;
  Camera lastCamera_;

  // Script.
  std::optional<ViewScript> script_;
  size_t nextEvent_ = 0;
  SteadyClock::time_point start_;

  // Panel fields.
  std::string screenshotPath_ = "view.png", cameraPath_ = "cameras.json", tfPath_ = "tf.json";
  std::string message_;
  // A screenshot event with panels, taken after this frame's panels are drawn: the events after it wait for
  // the next frame, so the panels show the state the event saw.
  std::optional<ViewEvent> panelShot_;
};

Viewer::Viewer(const ViewOptions& o, std::optional<ViewScript> script, OutputGuard guard)
    : o_(o), guard_(std::move(guard)), stepPacer_(o.targetFrameMs), script_(std::move(script)) {
  if (o.backend == RenderBackend::Brute)
    throw Error(
        "view: --backend brute is render's benchmark baseline; the viewer draws with the octree ray caster "
        "(auto, fragment, compute or multipass)");
  VolumeInfo volume;  // what a volume's source read: the time points and channels of its file
  source_ = openBrickSource(o, "view", &volume);
  shown_ = source_.get();
  if ((volume.timePoints > 1 || volume.channels > 1) && volume.timePoints * volume.channels <= UINT32_MAX) {
    timePoints_ = uint32_t(volume.timePoints);
    channels_ = uint32_t(volume.channels);
    channelNames_ = volume.channelNames;
    shownPick_ = wantedPick_ = {uint32_t(volume.timePoint), uint32_t(volume.channel)};
    const SourceOptions read = sourceOptionsOf(o.read, "view");
    auto convert = [input = o.input, read, brick = o.brick, timePoints = timePoints_](
                       uint32_t v, const std::function<void(double)>& progress) {
      SourceOptions picked = read;
      picked.timePoint = v % timePoints;
      picked.channel = v / timePoints;
      // Quietly: the panel shows the progress, and the first conversion told the source's notes.
      std::unique_ptr<Store> store = openVolumeAsStore(
          input, picked, brick, {.quiet = true, .notes = false, .progress = progress}, "view");
      const uint64_t bytes = store->fileBytes();
      return SeriesStores::Made{std::move(store), bytes};
    };
    // The volumes kept take at most half the temporary folder's free space, and 4 GiB.
    std::error_code ec;
    const uint64_t free = std::filesystem::space(std::filesystem::temp_directory_path(), ec).available;
    const uint64_t keepBytes = std::min<uint64_t>(ec ? 0 : free / 2, uint64_t(4) << 30);
    // A volume's source is a store (tools/temporary_store.h).
    const uint64_t bytes = dynamic_cast<const Store&>(*source_).fileBytes();
    // A volume made wakes the window, which may be waiting for events.
    series_.emplace(timePoints_ * channels_, indexOf(shownPick_),
                    SeriesStores::Made{std::move(source_), bytes}, keepBytes, std::move(convert),
                    [] { glfwPostEmptyEvent(); });
  }
  attachShownSource();
  const BrickSourceInfo& info = bricks().info();
  boxMax_ = info.volume.worldMax();
  params_ = renderParamsOf(o, info, "view");
  unfoldCutControls_ = !o.crop.empty() || !o.clipPlane.empty() || o.mode == RenderMode::Slice;
  voxelsPerPixel_ = o.voxelsPerPixel;
  targetFrameMs_ = o.targetFrameMs;
  tfRange_ = o.tfRange;
  setTransferFunction(o.tf);  // a bad --tf is an error in either mode, as in render

  const Camera initial = chooseCamera(o, info);
  if (!o.eye.empty() || o.view) {
    controller_ = OrbitController::fromCamera(glm::dvec3(0.0), boxMax_, initial);
  } else {
    const glm::dvec3 orbit = orbitFor(o, info.volume);
    controller_.emplace(
        glm::dvec3(0.0), boxMax_,
        OrbitController::orbitAroundBox(glm::dvec3(0.0), boxMax_, orbit.x, orbit.y, orbit.z, o.fov));
  }
  lastCamera_ = controller_->camera();

  WindowContextOptions windowOptions;
  windowOptions.title = "ropecast view " + o.input;
  windowOptions.width = o.size.at(0);
  windowOptions.height = o.size.at(1);
  try {
    window_ = std::make_unique<WindowContext>(windowOptions);
  } catch (const NoDisplayError& e) {
    throw Error(
        std::string("view: ") + e.what() +
        ". The viewer needs an X11 display (DISPLAY); `ropecast render` draws the same images headless");
  } catch (const Error& e) {
    throw Error(std::string("view: ") + e.what() +
                ". The viewer needs OpenGL 4.5 core on the display (Mesa's software driver has it: "
                "LIBGL_ALWAYS_SOFTWARE=1); `ropecast render` draws the same images headless");
  }

  // Opened once the window exists: a run without a display leaves no file behind.
  if (!o.stats.empty()) {
    stats_.emplace(o.stats, "view: --stats");
  }

  glfwSetWindowUserPointer(window_->window(), this);
  // Installed before ImGui's, which calls it after its own.
  glfwSetScrollCallback(window_->window(), [](GLFWwindow* w, double, double dy) {
    static_cast<Viewer*>(glfwGetWindowUserPointer(w))->wheelClicks_ += dy;
  });
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window_->window(), true);
  ImGui_ImplOpenGL3_Init("#version 450");

  glCreateTextures(GL_TEXTURE_2D, 1, &viewTexture_);
  glCreateFramebuffers(1, &viewFramebuffer_);
}

Viewer::~Viewer() {
  // The series' sources outlive what reads them; their thread, which wakes the window, stops first.
  renderer_.reset();
  probeReader_.reset();
  delayed_.reset();
  series_.reset();
  if (!window_) return;
  glDeleteFramebuffers(1, &viewFramebuffer_);
  glDeleteTextures(1, &viewTexture_);
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void Viewer::attachShownSource() {
  renderer_.reset();
  probeReader_.reset();
  probeAnswer_.reset();
  delayed_.reset();
  if (o_.ioDelayMs > 0.0) delayed_ = std::make_unique<DelayedBrickSource>(*shown_, o_.ioDelayMs);
  const BrickSourceInfo& info = bricks().info();
  // An answer read wakes the window, which may be waiting for events.
  probeReader_.emplace(bricks(), [] { glfwPostEmptyEvent(); });
  valueRange_ = valueRangeOf(info);
  const ValueHistogram h = coarseHistogram(bricks(), 64, valueRange_.first, valueRange_.second);
  histogramLevel_ = h.level;
  histogram_.clear();
  double top = 0.0;
  for (uint64_t c : h.counts) top = std::max(top, std::log1p(double(c)));
  for (uint64_t c : h.counts) histogram_.push_back(top > 0.0 ? float(std::log1p(double(c)) / top) : 0.0f);
  // The function stays in data units across volumes; its table follows the store's value mapping.
  if (tfTable_) setTransferFunction(tf_, tfSpec_);
}

// Throws naming `what` ("time point", "channel") when the input holds no `index`-th of them (it holds
// `count`).
void Viewer::checkPickable(const std::string& what, uint32_t index, uint32_t count) const {
  const std::string i = std::to_string(index);
  if (count == 1)
    throw Error("view: the input " + o_.input + " holds one " + what + "; " + what + " " + i +
                " does not exist");
  if (index >= count)
    throw Error("view: " + what + " " + i + ": the input " + o_.input + " holds " + std::to_string(count) +
                " (0 to " + std::to_string(count - 1) + ")");
}

void Viewer::askTimePoint(uint32_t t) {
  checkPickable("time point", t, timePoints_);
  askPick({t, wantedPick_.channel});
}

void Viewer::askChannel(uint32_t c) {
  checkPickable("channel", c, channels_);
  askPick({wantedPick_.time, c});
}

void Viewer::askPick(Pick p) {
  wantedPick_ = p;
  series_->ask(indexOf(p));
}

std::string Viewer::pickName(Pick p) const {
  std::string name;
  if (timePoints_ > 1) name = "time point " + std::to_string(p.time);
  if (channels_ > 1) {
    name += (name.empty() ? "" : ", ") + std::string("channel ") + std::to_string(p.channel);
    if (p.channel < channelNames_.size()) name += " '" + channelNames_[p.channel] + "'";
  }
  return name;
}

void Viewer::followPick() {
  if (!series_) return;
  if (const auto failure = series_->takeFailure(); failure && failure->volume == indexOf(wantedPick_)) {
    message_ = pickName(wantedPick_) + ": " + failure->message;
    wantedPick_ = shownPick_;
    playing_ = false;  // it would fail again at each turn
    std::fprintf(stderr, "ropecast view: %s\n", message_.c_str());
    // A script asked for it: what it does next would not show what it expects.
    if (script_) throw Error("view: " + message_);
  }
  if (!pickPending()) return;
  BrickSource* made = series_->find(indexOf(wantedPick_));
  if (!made) return;
  shown_ = made;
  shownPick_ = wantedPick_;
  attachShownSource();
  lastRequest_.reset();                 // the new volume is drawn, whatever the camera
  series_->shown(indexOf(shownPick_));  // nothing reads the one before now
  shownAtSeconds_ = secondsSince(start_);
  if (playing_) series_->ask(indexOf(nextTimePoint()));  // made while this one shows
}

void Viewer::setPlaying(bool playing) {
  if (timePoints_ == 1)
    throw Error("view: the input " + o_.input + " holds one time point; there is nothing to play");
  playing_ = playing;
  if (playing_ && !pickPending()) series_->ask(indexOf(nextTimePoint()));
}

void Viewer::playOn(bool viewConverged) {
  if (!playing_ || pickPending() || !viewConverged ||
      secondsSince(start_) - shownAtSeconds_ < playSecondsEach_)
    return;
  askPick(nextTimePoint());
}

void Viewer::setTransferFunction(const std::string& spec) {
  // A file shows as its name alone: the panel's combo is narrow.
  setTransferFunction(
      transferFunctionOf(spec, bricks().info(), params_.mode, tfRange_),
      spec.empty() ? defaultTfSpec(params_.mode) : std::filesystem::path(spec).filename().string());
  tfChosen_ = !spec.empty();
}

void Viewer::setTfRange(double lo, double hi) {
  tfRange_ = {lo, hi};
  setTransferFunction(tf_.stretchedOver(lo, hi), tfSpec_);
}

void Viewer::setMode(RenderMode mode) {
  const bool newDefault = !tfChosen_ && defaultTfSpec(mode) != defaultTfSpec(params_.mode);
  params_.mode = mode;
  if (newDefault) setTransferFunction("");
  // A slice shows the clip plane: its controls move it.
  if (mode == RenderMode::Slice) {
    keepSlicePlane();
    unfoldCutControls_ = true;
  }
}

// The farthest the clip plane's point lies from the volume's center along its normal: half the extent's
// diagonal, beyond which it cuts nothing in any direction.
double planeOffsetReach(const VolumeInfo& volume) {
  return 0.5 * glm::length(volume.worldMax());
}

// The wheel: zoom, or with shift the clip plane a voxel per click (stepPlane).
void Viewer::wheel(double clicks, bool shift) {
  if (shift)
    stepPlane(clicks);
  else
    controller_->zoom(clicks);
}

// Shift + wheel, Page Up and Page Down: the clip plane (a slice's plane) moved along its normal by `voxels`
// of the smallest spacing, positive toward the eye, as a radiology viewer scrolls through slices; it stays
// within the reach of the panel's offset slider. Nothing without a plane.
void Viewer::stepPlane(double voxels) {
  ClipPlane& plane = params_.clipPlane;
  if (!plane.enabled()) return;
  const VolumeInfo& volume = bricks().info().volume;
  const glm::dvec3 center = 0.5 * volume.worldMax();
  const double reach = planeOffsetReach(volume);
  const double voxel = std::min({volume.spacing.x, volume.spacing.y, volume.spacing.z});
  const double towardEye = glm::dot(plane.normal, controller_->camera().eye - plane.point) < 0.0 ? -1.0 : 1.0;
  const double offset = glm::dot(plane.normal, plane.point - center) + towardEye * voxels * voxel;
  plane.point = center + std::clamp(offset, -reach, reach) * plane.normal;
  unfoldCutControls_ = true;
}

// A slice needs a plane: the axial one through the center where none is set (as render's default).
void Viewer::keepSlicePlane() {
  if (params_.mode == RenderMode::Slice && !params_.clipPlane.enabled())
    params_.clipPlane = defaultSlicePlane(params_, bricks().info().volume);
}

void Viewer::setTransferFunction(TransferFunction function, const std::string& name) {
  tfTable_ = bakeFor(function, bricks().info());
  tf_ = std::move(function);
  tfSpec_ = name;
  ++tfVersion_;
}

// A renderer for the current parameters. A switch to DVR with stored gradients needs a GradientPool, which a
// FrameRenderer gets at construction: then the renderer is made again (its bricks load again). A new one
// compiles its shaders for the frame's request before that frame, not in its ms (as render does).
void Viewer::ensureRenderer(bool moving) {
  if (renderer_ && (rendererHasGradients_ || !usesStoredGradients(params_))) return;
  renderer_.reset();
  FrameRendererConfig config = frameRendererConfigOf(o_, params_);
  try {
    renderer_ = std::make_unique<FrameRenderer>(window_->info(), bricks(), config);
  } catch (const UsageError& e) {
    if (!config.storedGradients) throw;
    // Stored gradients take 8 more bytes per pool texel: a --gpu-budget too small for a brick with them can
    // still hold one without, its gradients computed per sample. The session goes on.
    params_.gradients = GradientSource::Computed;
    config = frameRendererConfigOf(o_, params_);
    renderer_ = std::make_unique<FrameRenderer>(window_->info(), bricks(), config);
    message_ = std::string(e.what()) + " with stored gradients: computing them per sample instead";
    std::fprintf(stderr, "ropecast view: %s\n", message_.c_str());
  }
  rendererHasGradients_ = config.storedGradients;
  lastRequest_.reset();
  renderer_->prepare(currentRequest(moving));
}

FrameRequest Viewer::currentRequest(bool moving) {
  FrameRequest r;
  r.camera = controller_->camera();
  r.width = viewWidth_;
  r.height = viewHeight_;
  r.params = params_;
  r.voxelsPerPixel = voxelsPerPixel_;
  r.tf = &*tfTable_;
  r.synchronous = false;
  r.keepConvergedImage = true;  // the view shows readColor's image, and idles once converged
  r.recastChangesOnly = true;   // a still view's frames cast only the pixels of the leaves that changed
  // While the camera moves, --target-frame-ms trades quality for frame time: the step first (StepPacer), then
  // a coarser refinement target once the step is at its largest. A still camera gets the full quality.
  if (moving && stepPacer_.enabled()) {
    r.params.stepVoxels *= stepPacer_.scale();
    if (coarser_) r.voxelsPerPixel *= 0.5;  // a voxel may cover twice the pixels: a level coarser
  }
  return r;
}

bool Viewer::sameAsLast(const FrameRequest& r) const {
  if (!lastRequest_) return false;
  const FrameRequest& l = *lastRequest_;
  return l.camera == r.camera && l.width == r.width && l.height == r.height && l.params == r.params &&
         l.voxelsPerPixel == r.voxelsPerPixel &&
         (!usesTransferFunction(r.params.mode) || lastTfVersion_ == tfVersion_);
}

void Viewer::renderFrame(const FrameRequest& request) {
  lastStats_ = renderer_->render(request);
  lastStats_.frame = framesRendered_++;  // one count for the session: a switch to DVR makes a new renderer
  if (lastStats_.drawn) {                // a kept frame takes no drawing time
    lastDrawnMs_ = lastStats_.frameMs;
    lastCastShare_ = double(lastStats_.fragments) / (double(request.width) * request.height);
  }
  lastRequest_ = request;
  lastTfVersion_ = tfVersion_;
  color_ = renderer_->readColor();
  if (stats_) {
    std::string fields;  // which volume of a series the frame drew
    if (timePoints_ > 1) fields = "\"time_point\":" + std::to_string(shownPick_.time);
    if (channels_ > 1)
      fields +=
          (fields.empty() ? "" : ",") + std::string("\"channel\":") + std::to_string(shownPick_.channel);
    stats_->write(lastStats_, fields);
  }
  frameMsHistory_.push_back(float(lastStats_.frameMs));
  if (frameMsHistory_.size() > kFrameHistory) frameMsHistory_.pop_front();

  // The view shows what the PNG holds: 8-bit RGB, round(clamp(v) * 255), opaque. The image goes through the
  // CPU (readColor, FrameRenderer's one way out) and back: a float target cannot be blitted to the window's
  // fixed-point framebuffer, and the copy is what a screenshot writes.
  std::vector<uint8_t> rgba(size_t(color_.width) * color_.height * 4);
  for (size_t i = 0; i < size_t(color_.width) * color_.height; ++i) {
    for (uint32_t c = 0; c < 3; ++c)
      rgba[i * 4 + c] =
          uint8_t(std::lround(std::clamp(color_.pixels[i * color_.channels + c], 0.0f, 1.0f) * 255.0f));
    rgba[i * 4 + 3] = 255;
  }
  glBindTexture(GL_TEXTURE_2D, viewTexture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, GLsizei(color_.width), GLsizei(color_.height), 0, GL_RGBA,
               GL_UNSIGNED_BYTE, rgba.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  glNamedFramebufferTexture(viewFramebuffer_, GL_COLOR_ATTACHMENT0, viewTexture_, 0);
}

// The 3D view fills the window; image row 0 (the top) is texture row 0, so the blit turns it upright.
void Viewer::present(uint32_t width, uint32_t height) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, GLsizei(width), GLsizei(height));
  glDisable(GL_SCISSOR_TEST);
  glClearColor(float(params_.background.r), float(params_.background.g), float(params_.background.b), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  if (!color_.pixels.empty()) {
    glBlitNamedFramebuffer(viewFramebuffer_, 0, 0, 0, GLint(color_.width), GLint(color_.height), 0,
                           GLint(color_.height), GLint(color_.width), 0, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  checkGlError("view: drawing the 3D view");
}

void Viewer::drive(const Pointer& before, const Pointer& now) {
  const glm::dvec2 d = now.pos - before.pos;
  if (d == glm::dvec2(0.0)) return;
  if ((before.middle && now.middle) || (before.left && now.left && now.shift)) {
    // Mouse positions are in window coordinates, which differ from framebuffer pixels on scaled displays.
    int windowWidth = 0, windowHeight = 0;
    glfwGetWindowSize(window_->window(), &windowWidth, &windowHeight);
    controller_->pan(d.x, d.y, uint32_t(std::max(windowHeight, 1)));
  } else if (before.left && now.left) {
    controller_->rotate(d.x, d.y);
  }
}

void Viewer::flyScriptKeys(double nowSeconds) {
  for (auto& [key, held] : scriptKeys_) {
    const double until = std::min(nowSeconds, held.upAt) - held.downAt;
    if (until > held.flownSeconds) flyHeld({key}, until - held.flownSeconds);
    held.flownSeconds = std::max(held.flownSeconds, until);
  }
}

void Viewer::flyHeld(const std::set<char>& keys, double dtSeconds) {
  auto axis = [&](char plus, char minus) { return int(keys.count(plus)) - int(keys.count(minus)); };
  controller_->fly(axis('w', 's'), axis('d', 'a'), axis('e', 'q'), dtSeconds);
}

void Viewer::readWindowInput(double dtSeconds) {
  GLFWwindow* w = window_->window();
  const ImGuiIO& io = ImGui::GetIO();
  Pointer now;
  glfwGetCursorPos(w, &now.pos.x, &now.pos.y);
  now.left = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  now.middle = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  now.shift =
      glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
  const bool wasDown = windowPointer_.left || windowPointer_.middle;
  if ((now.left || now.middle) && !wasDown) windowDragOwned_ = !io.WantCaptureMouse;
  if (windowDragOwned_) drive(windowPointer_, now);
  if (!now.left && !now.middle) windowDragOwned_ = false;
  windowPointer_ = now;
  if (wheelClicks_ != 0.0 && !io.WantCaptureMouse) wheel(wheelClicks_, now.shift);
  if (!io.WantCaptureMouse && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left))
    message_ = centerAt(now.pos).message;
  if (!io.WantCaptureMouse && ImGui::IsMouseClicked(ImGuiMouseButton_Right))
    message_ = placeRulerEnd(now.pos);
  wheelClicks_ = 0.0;
  if (!io.WantCaptureKeyboard) {
    std::set<char> keys;
    for (const auto& [key, name] : {std::pair{GLFW_KEY_W, 'w'},
                                    {GLFW_KEY_A, 'a'},
                                    {GLFW_KEY_S, 's'},
                                    {GLFW_KEY_D, 'd'},
                                    {GLFW_KEY_Q, 'q'},
                                    {GLFW_KEY_E, 'e'}})
      if (glfwGetKey(w, key) == GLFW_PRESS) keys.insert(name);
    flyHeld(keys, dtSeconds);
    const bool reset = glfwGetKey(w, GLFW_KEY_R) == GLFW_PRESS;
    if (reset && !resetKeyDown_) controller_->reset();
    resetKeyDown_ = reset;
    const int page = int(glfwGetKey(w, GLFW_KEY_PAGE_UP) == GLFW_PRESS) -
                     int(glfwGetKey(w, GLFW_KEY_PAGE_DOWN) == GLFW_PRESS);
    if (page != 0 && page != pageKeyDown_) stepPlane(page);
    pageKeyDown_ = page;
  }
}

void Viewer::runScript(bool converged) {
  if (!script_) return;
  const double now = secondsSince(start_);
  bool changedHere = false;  // the shown frame is not of the state the events left
  while (nextEvent_ < script_->events.size()) {
    const ViewEvent& e = script_->events[nextEvent_];
    if (e.atSeconds > now) break;
    if (waitsForConvergence(e.kind) && (!converged || changedHere)) {
      // Frames are counted, not the wait for a time point being made (it draws none).
      if (changedHere || pickPending() || ++waitedFrames_ <= o_.maxFrames) break;
      std::fprintf(stderr, "ropecast view: %s: not converged after %u frames (--max-frames); going on\n",
                   e.where.c_str(), o_.maxFrames);
    }
    // A screenshot with panels shows them settled: not while the probe's line waits for its value (the stats
    // panel takes the size of the last frame's lines).
    if (e.kind == ViewEventKind::Screenshot && e.panels && probeReading_ && ++waitedFrames_ <= o_.maxFrames)
      break;
    try {
      runEvent(e);
    } catch (const Error& error) {
      throw Error(e.where + ": " + error.what());
    }
    ++nextEvent_;
    waitedFrames_ = 0;
    if (e.kind == ViewEventKind::Quit) nextEvent_ = script_->events.size();
    // What the shown frame converged to may have changed: a wait after this event waits for a new frame.
    if (e.kind != ViewEventKind::Screenshot && e.kind != ViewEventKind::SaveCamera &&
        e.kind != ViewEventKind::WaitConverged && e.kind != ViewEventKind::Probe &&
        e.kind != ViewEventKind::Measure)
      changedHere = true;
    // One mouse move per frame, so that a scripted drag is seen moving as a hand-made one is; nothing after a
    // screenshot with panels until its frame is read back.
    if (e.kind == ViewEventKind::MouseMove || panelShot_) break;
  }
}

void Viewer::runEvent(const ViewEvent& e) {
  Pointer next = scriptPointer_;
  next.pos = e.pos;
  next.shift = e.shift;
  switch (e.kind) {
    case ViewEventKind::MouseDown:
      // The right button moves nothing (docs/VIEWER.md "Camera").
      if (e.button == MouseButton::Left) next.left = true;
      if (e.button == MouseButton::Middle) next.middle = true;
      scriptPointer_ = next;
      break;
    case ViewEventKind::MouseMove:
      drive(scriptPointer_, next);
      scriptPointer_ = next;
      break;
    case ViewEventKind::MouseUp:
      drive(scriptPointer_, Pointer{next.pos, scriptPointer_.left, scriptPointer_.middle, next.shift});
      if (e.button == MouseButton::Left) next.left = false;
      if (e.button == MouseButton::Middle) next.middle = false;
      scriptPointer_ = next;
      break;
    case ViewEventKind::Wheel:
      wheel(e.clicks, e.shift);
      break;
    case ViewEventKind::KeyDown:
      if (e.key == 'r') {
        controller_->reset();
      } else {
        ScriptKey held{e.atSeconds, HUGE_VAL, 0.0};
        for (size_t i = nextEvent_ + 1; i < script_->events.size(); ++i)
          if (script_->events[i].kind == ViewEventKind::KeyUp && script_->events[i].key == e.key) {
            held.upAt = script_->events[i].atSeconds;
            break;
          }
        scriptKeys_[e.key] = held;
      }
      break;
    case ViewEventKind::KeyUp:
      flyScriptKeys(e.atSeconds);  // the rest of its flight
      scriptKeys_.erase(e.key);
      break;
    case ViewEventKind::SetIso:
      params_.isoValue = e.value;
      if (!(e.value >= valueRange_.first && e.value <= valueRange_.second))
        std::fprintf(
            stderr,
            "ropecast view: warning: %s: isovalue %g lies outside the volume's value range [%g, %g]: "
            "the isosurface is empty\n",
            e.where.c_str(), e.value, valueRange_.first, valueRange_.second);
      break;
    case ViewEventKind::SetMode:
      setMode(e.mode);
      break;
    case ViewEventKind::SetCrop:
      params_.crop = cropBoxOf(e.crop, bricks().info());
      unfoldCutControls_ = true;
      break;
    case ViewEventKind::SetClipPlane:
      params_.clipPlane = clipPlaneOf(e.plane);
      params_.clipPlane.slab = e.slab;
      keepSlicePlane();
      unfoldCutControls_ = true;
      break;
    case ViewEventKind::SetCaps:
      params_.isoCaps = e.caps;
      unfoldCutControls_ = true;
      break;
    case ViewEventKind::SetTimePoint:
      askTimePoint(e.timePoint);
      break;
    case ViewEventKind::SetChannel:
      askChannel(e.channel);
      break;
    case ViewEventKind::SetLighting:
      if (e.isoColor) params_.lighting.isoBaseColor = *e.isoColor;
      if (e.shading) params_.lighting.dvrShading = *e.shading;
      if (!e.material.empty()) setMaterial(params_.lighting, e.material);
      break;
    case ViewEventKind::Play:
      if (e.secondsEach >= 0.0) playSecondsEach_ = e.secondsEach;
      setPlaying(e.playing);
      break;
    case ViewEventKind::LoadTf:
      setTransferFunction(e.tf);
      break;
    case ViewEventKind::SetTfRange:
      setTfRange(e.range.x, e.range.y);
      break;
    case ViewEventKind::Screenshot:
      if (e.panels)
        panelShot_ = e;  // read back once this frame's panels are drawn
      else
        screenshot(e.file, false);
      break;
    case ViewEventKind::SaveCamera:
      appendCameraKeyframe(e.file, *controller_);
      break;
    case ViewEventKind::ResetCamera:
      controller_->reset();
      break;
    case ViewEventKind::SetView:
      showAnatomicalView(e.view);
      break;
    case ViewEventKind::Probe: {
      const std::string text = probe(e.pos, /*waitForValue=*/true);
      std::printf("ropecast view: probe at %g, %g: %s\n", e.pos.x, e.pos.y,
                  text.empty() ? "outside the 3D view" : text.c_str());
      std::fflush(stdout);
      break;
    }
    case ViewEventKind::Measure: {
      ruler_.clear();
      std::string what = placeRulerEnd(e.pos);
      if (ruler_.size() == 1) what = placeRulerEnd(e.to);
      if (ruler_.size() == 2) {
        std::printf("ropecast view: ruler: %s\n", what.c_str());
        std::fflush(stdout);
      } else {
        ruler_.clear();
        std::fprintf(stderr, "ropecast view: warning: %s: %s; no ruler\n", e.where.c_str(), what.c_str());
      }
      break;
    }
    case ViewEventKind::CenterAt:
      if (const Outcome o = centerAt(e.pos); !o.done)
        std::fprintf(stderr, "ropecast view: warning: %s: %s; the camera stays\n", e.where.c_str(),
                     o.message.c_str());
      break;
    case ViewEventKind::WaitConverged:
    case ViewEventKind::Quit:  // the script ends: runScript skips the rest
      break;
  }
}

void Viewer::checkPanelOutput(const std::string& what, const std::string& path) const {
  OutputGuard guard = guard_;
  guard.addOutput(what, path);
  guard.check();
}

void Viewer::reportPanelError(const std::exception& e) {
  message_ = e.what();
  std::fprintf(stderr, "ropecast %s\n", e.what());
}

void Viewer::screenshot(const std::string& path, bool panels) {
  warnIfPoolLimited(o_, lastStats_, "view");
  const bool exr = hasExtension(path, ".exr");
  if (const std::string problem =
          imageOutputProblem(path, exr ? ImageOutputKind::FloatExr : ImageOutputKind::Color8);
      !problem.empty())
    throw Error("view: screenshot " + path + ": " + problem);
  if (exr) {
    // Float RGBA (alpha = coverage) and, beside it as NAME_depth.exr, the depth, as render --exr --depth.
    if (color_.pixels.empty()) throw Error("view: screenshot " + path + ": nothing rendered yet");
    const std::string depthPath = screenshotDepthPath(path);
    writeExr(path, color_);
    writeDepthExr(depthPath, renderer_->readDepth());
    message_ = "wrote " + path + " and " + depthPath;
    return;
  }
  if (panels) {
    writePng(path, readWindow(viewWidth_, viewHeight_), false);
  } else {
    if (color_.pixels.empty()) throw Error("view: screenshot " + path + ": nothing rendered yet");
    writePng(path, color_, false);
  }
  message_ = "wrote " + path;
}

// --crop's box as one range of voxels per axis, the file's indices as --crop takes them; the rest of the
// volume is neither drawn nor read.
void Viewer::drawCropControls(const BrickSourceInfo& info) {
  ImGui::Text("crop (voxels)");
  const glm::u32vec3 dims = info.volume.dims;
  CropBox crop = fileCropOf(params_.crop, info);
  for (int axis = 0; axis < 3; ++axis) {
    const int n = int(std::min<uint32_t>(dims[axis], INT32_MAX));
    int lo = int(std::clamp(crop.lo[axis], 0.0, double(n)));
    int hi = int(std::clamp(crop.hi[axis], 0.0, double(n)));
    const char label[] = {"xyz"[axis], '\0'};
    if (ImGui::DragIntRange2(label, &lo, &hi, std::max(1.0f, float(n) / 256.0f), 0, n, "%d", "%d",
                             ImGuiSliderFlags_AlwaysClamp)) {
      // At least one voxel: an empty box would show nothing and say nothing.
      lo = std::min(lo, n - 1);
      hi = std::max(hi, lo + 1);
      crop.lo[axis] = lo;
      crop.hi[axis] = hi;
      params_.crop = fileCropOf(crop, info);
    }
  }
  if (ImGui::Button("whole volume")) params_.crop = CropBox{};
}

// A series' time point and channel: a slider each, for what the input has several of, and for time a step
// each way and play. A volume not shown yet is converted first, its progress shown, the view showing the one
// before meanwhile.
void Viewer::drawSeriesControls() {
  const auto slider = [](const char* label, uint32_t value, uint32_t count) -> std::optional<uint32_t> {
    int v = int(value);
    const std::string format = "%d of " + std::to_string(count);
    if (ImGui::SliderInt(label, &v, 0, int(count - 1), format.c_str(), ImGuiSliderFlags_AlwaysClamp) &&
        uint32_t(v) != value)
      return uint32_t(v);
    return std::nullopt;
  };
  if (timePoints_ > 1) {
    std::optional<uint32_t> t = slider("time point", wantedPick_.time, timePoints_);
    ImGui::SameLine();
    if (ImGui::ArrowButton("##earlier", ImGuiDir_Left) && wantedPick_.time > 0) t = wantedPick_.time - 1;
    ImGui::SameLine();
    if (ImGui::ArrowButton("##later", ImGuiDir_Right) && wantedPick_.time + 1 < timePoints_)
      t = wantedPick_.time + 1;
    if (t) askTimePoint(*t);
    ImGui::SameLine();
    bool playing = playing_;
    if (ImGui::Checkbox("play", &playing)) setPlaying(playing);
    if (playing_) {
      float seconds = float(playSecondsEach_);
      if (ImGui::SliderFloat("seconds each", &seconds, 0.0f, 5.0f, "%.1f", ImGuiSliderFlags_AlwaysClamp))
        playSecondsEach_ = seconds;
    }
  }
  if (channels_ > 1) {
    if (const std::optional<uint32_t> c = slider("channel", wantedPick_.channel, channels_)) askChannel(*c);
    if (wantedPick_.channel < channelNames_.size()) {
      ImGui::SameLine();
      ImGui::TextUnformatted(channelNames_[wantedPick_.channel].c_str());
    }
  }
  if (const auto converting = series_->converting())
    ImGui::TextDisabled(
        "converting %s: %.0f%%",
        pickName({converting->volume % timePoints_, converting->volume / timePoints_}).c_str(),
        100.0 * converting->fraction);
  if (pickPending()) ImGui::TextDisabled("showing %s meanwhile", pickName(shownPick_).c_str());
}

// --iso-color, --shading and --material: the headlight's shading of the isosurface and of DVR.
void Viewer::drawLightingControls() {
  LightingParams& l = params_.lighting;
  float color[3] = {float(l.isoBaseColor.r), float(l.isoBaseColor.g), float(l.isoBaseColor.b)};
  if (ImGui::ColorEdit3("isosurface color", color)) l.isoBaseColor = {color[0], color[1], color[2]};
  ImGui::Checkbox("DVR shading", &l.dvrShading);
  const auto weight = [](const char* label, double& value) {
    float v = float(value);
    if (ImGui::SliderFloat(label, &v, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp)) value = v;
  };
  weight("ambient", l.ambient);
  weight("diffuse", l.diffuse);
  weight("specular", l.specular);
  float shininess = float(l.shininess);
  if (ImGui::SliderFloat("shininess", &shininess, 1.0f, 1024.0f, "%.0f",
                         ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic))
    l.shininess = shininess;
  if (ImGui::Button("default lighting")) l = LightingParams{};
}

void Viewer::showAnatomicalView(AnatomicalView view) {
  const OrbitState& s = controller_->state();
  controller_->lookFrom(anatomicalViewCamera(view, s.distance, glm::dvec3(0.0), boxMax_, s.fovYDeg));
}

// --clip-plane as the direction of its normal (azimuth about +z from +x, elevation, degrees, as --orbit's)
// and the plane's distance from the volume's center along it; switched on, it cuts away the half nearer the
// eye.
void Viewer::drawClipPlaneControls(const VolumeInfo& volume) {
  const glm::dvec3 center = 0.5 * volume.worldMax();
  const float reach = float(planeOffsetReach(volume));
  ClipPlane& plane = params_.clipPlane;
  bool on = plane.enabled();
  if (params_.mode == RenderMode::Slice) {
    ImGui::Text("slice plane");  // always on: the slice is drawn where it lies
  } else if (ImGui::Checkbox("clip plane", &on)) {
    plane = on ? ClipPlane{center, cameraFrame(controller_->camera()).forward} : ClipPlane{};
  }
  if (!plane.enabled()) return;
  const glm::dvec3 n = plane.normal;
  float azimuth = float(glm::degrees(std::atan2(n.y, n.x)));
  float elevation = float(glm::degrees(std::asin(std::clamp(n.z, -1.0, 1.0))));
  float offset = float(glm::dot(n, plane.point - center));
  bool changed = ImGui::SliderFloat("azimuth", &azimuth, -180.0f, 180.0f, "%.0f");
  changed |= ImGui::SliderFloat("elevation", &elevation, -90.0f, 90.0f, "%.0f");
  changed |= ImGui::SliderFloat("offset", &offset, -reach, reach, "%.1f");
  // --slab: the slab of that thickness about the plane (0: the half-space); a slice has none.
  float slab = float(plane.slab);
  if (params_.mode != RenderMode::Slice && ImGui::SliderFloat("slab", &slab, 0.0f, 2.0f * reach, "%.1f"))
    plane.slab = std::max(0.0, double(slab));
  if (changed) {
    const double az = glm::radians(double(azimuth)), el = glm::radians(double(elevation));
    plane.normal = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
    plane.point = center + double(offset) * plane.normal;
  }
}

// While the crop box and clip plane are edited, their outlines over the 3D view (behind the panels; the 3D
// view's screenshots do not show them): the crop box where it is not the whole volume, and where the plane
// cuts what is drawn.
void Viewer::drawCutOutlines(const VolumeInfo& volume) {
  const PlacedBox drawn{sampledWorldBox(params_, volume.dims, volume.spacing), volume.axes,
                        0.5 * volume.worldMax()};
  const Camera camera = controller_->camera();
  // In the panels' coordinates: window points, which a high-density display's framebuffer scales.
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  const uint32_t width = uint32_t(std::max(1.0f, display.x)), height = uint32_t(std::max(1.0f, display.y));
  ImDrawList* list = ImGui::GetBackgroundDrawList();
  const auto draw = [list](const std::vector<ScreenSegment>& segments, ImU32 color) {
    for (const ScreenSegment& s : segments)
      list->AddLine(ImVec2(float(s.a.x), float(s.a.y)), ImVec2(float(s.b.x), float(s.b.y)), color, 1.5f);
  };
  if (params_.crop != CropBox{}) draw(boxOutline(camera, width, height, drawn), IM_COL32(255, 200, 60, 220));
  draw(planeOutline(camera, width, height, drawn, params_.clipPlane), IM_COL32(90, 200, 255, 220));
}

void Viewer::drawOrientationMarks() {
  const Camera camera = controller_->camera();
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImDrawList* list = ImGui::GetBackgroundDrawList();
  constexpr float kMargin = 8.0f;
  // Text placed by its anchor: align 0 puts the point at the text's left (top), 1 at its right (bottom).
  const auto text = [list](const std::string& s, ImVec2 at, ImVec2 align, ImU32 color) {
    const ImVec2 size = ImGui::CalcTextSize(s.c_str());
    list->AddText(ImVec2(at.x - align.x * size.x, at.y - align.y * size.y), color, s.c_str());
  };
  const ImU32 letterColor = IM_COL32(235, 235, 235, 230);
  const EdgeLetters letters = edgeLetters(camera);
  text(letters.left, ImVec2(kMargin, 0.5f * display.y), ImVec2(0.0f, 0.5f), letterColor);
  text(letters.right, ImVec2(display.x - kMargin, 0.5f * display.y), ImVec2(1.0f, 0.5f), letterColor);
  text(letters.top, ImVec2(0.5f * display.x, kMargin), ImVec2(0.5f, 0.0f), letterColor);
  text(letters.bottom, ImVec2(0.5f * display.x, display.y - kMargin), ImVec2(0.5f, 1.0f), letterColor);

  // The volume's axes, x red, y green, z blue, the farthest drawn first: left of the bottom letter, where no
  // panel starts (the Volume panel runs down the left side, the stats panel sits at the bottom right).
  constexpr float kLength = 36.0f;
  const ImVec2 origin(std::max(kMargin + kLength + 12.0f, 0.5f * display.x - 2.0f * kLength - 24.0f),
                      display.y - kMargin - kLength - 12.0f);
  const std::array<TriadAxis, 3> triad = axesTriad(camera, bricks().info().volume.axes);
  std::array<int, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return triad[a].towardEye < triad[b].towardEye; });
  constexpr ImU32 kAxisColors[3] = {IM_COL32(235, 90, 80, 255), IM_COL32(90, 210, 90, 255),
                                    IM_COL32(100, 150, 255, 255)};
  for (int a : order) {
    const ImVec2 tip(origin.x + kLength * float(triad[a].screen.x),
                     origin.y + kLength * float(triad[a].screen.y));
    list->AddLine(origin, tip, kAxisColors[a], 2.0f);
    const ImVec2 beyond(origin.x + (kLength + 8.0f) * float(triad[a].screen.x),
                        origin.y + (kLength + 8.0f) * float(triad[a].screen.y));
    text(std::string(1, "xyz"[a]), beyond, ImVec2(0.5f, 0.5f), kAxisColors[a]);
  }
}

std::optional<glm::u32vec2> Viewer::pixelAt(glm::dvec2 pos) const {
  if (!lastRequest_ || !renderer_) return std::nullopt;
  // Window points to framebuffer pixels, which a high-density display scales.
  int windowWidth = 0, windowHeight = 0;
  glfwGetWindowSize(window_->window(), &windowWidth, &windowHeight);
  if (windowWidth <= 0 || windowHeight <= 0) return std::nullopt;
  const FrameRequest& drawn = *lastRequest_;
  const glm::dvec2 p =
      glm::floor(pos * glm::dvec2(double(drawn.width) / windowWidth, double(drawn.height) / windowHeight));
  if (!(p.x >= 0.0 && p.y >= 0.0 && p.x < drawn.width && p.y < drawn.height)) return std::nullopt;
  return glm::u32vec2(p);
}

std::optional<ProbedVoxel> Viewer::probedAt(glm::u32vec2 pixel) const {
  const FrameRequest& drawn = *lastRequest_;
  const BrickSourceInfo& info = bricks().info();
  std::optional<ProbedVoxel> probed = probedVoxel(drawn.camera, drawn.width, drawn.height, pixel,
                                                  renderer_->readDepthAt(pixel.x, pixel.y), info.volume);
  // The voxel as the file counts it, as --crop and extract do.
  if (probed) probed->voxel.x = fileVoxelX(info, probed->voxel.x, info.volume.dims.x);
  return probed;
}

std::string Viewer::probe(glm::dvec2 pos, bool waitForValue) {
  probeReading_ = false;
  const std::optional<glm::u32vec2> pixel = pixelAt(pos);
  if (!pixel) return "";
  if (probeAnswer_ && probeAnswer_->pixel == *pixel && probeAnswer_->frame == framesRendered_)
    return probeAnswer_->text;
  std::string text = "nothing under the pointer";
  if (const std::optional<ProbedVoxel> probed = probedAt(*pixel)) {
    const std::optional<VoxelAnswer> answer =
        waitForValue ? probeReader_->wait(0, probed->voxel) : probeReader_->ask(0, probed->voxel);
    probeReading_ = !answer;
    if (!answer) return probeText(*probed, std::nullopt);  // asked again next frame
    text = answer->error.empty() ? probeText(*probed, answer->value) : answer->error;
  }
  probeAnswer_ = ProbeAnswer{*pixel, framesRendered_, text};
  return text;
}

Viewer::Outcome Viewer::centerAt(glm::dvec2 pos) {
  const std::optional<glm::u32vec2> pixel = pixelAt(pos);
  if (!pixel) return {false, "nothing to center on outside the 3D view"};
  const std::optional<ProbedVoxel> probed = probedAt(*pixel);
  if (!probed) return {false, "nothing under the pointer to center on"};
  controller_->lookFrom(centeredOn(controller_->camera(), probed->world));
  return {true, "centered on " + voxelText(probed->voxel)};
}

std::string Viewer::placeRulerEnd(glm::dvec2 pos) {
  const std::optional<glm::u32vec2> pixel = pixelAt(pos);
  if (!pixel) return "no ruler end outside the 3D view";
  const std::optional<ProbedVoxel> probed = probedAt(*pixel);
  if (!probed) return "nothing under the pointer for an end of the ruler";
  if (ruler_.size() == 2) ruler_.clear();
  ruler_.push_back(*probed);
  return ruler_.size() == 2 ? rulerText(ruler_[0], ruler_[1]) : "ruler from " + voxelText(probed->voxel);
}

// The ruler over the 3D view, behind the panels (never in a screenshot of the view): its ends, the segment
// between them and its length beside the middle.
void Viewer::drawRuler(const VolumeInfo& volume) {
  if (ruler_.empty()) return;
  const PlacedBox placed{WorldBox{glm::dvec3(0.0), volume.worldMax()}, volume.axes, 0.5 * volume.worldMax()};
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  const uint32_t width = uint32_t(std::max(1.0f, display.x)), height = uint32_t(std::max(1.0f, display.y));
  ImDrawList* list = ImGui::GetBackgroundDrawList();
  constexpr ImU32 kColor = IM_COL32(255, 230, 60, 255);
  const glm::dvec3 a = ruler_.front().point, b = ruler_.back().point;
  const std::optional<ScreenSegment> s = segmentOutline(controller_->camera(), width, height, placed, a, b);
  if (!s) return;
  const ImVec2 pa(float(s->a.x), float(s->a.y)), pb(float(s->b.x), float(s->b.y));
  list->AddLine(pa, pb, kColor, 2.0f);
  list->AddCircleFilled(pa, 3.5f, kColor);
  list->AddCircleFilled(pb, 3.5f, kColor);
  if (ruler_.size() == 2) {
    char label[32];
    std::snprintf(label, sizeof label, "%.4g", glm::length(b - a));
    list->AddText(ImVec2(0.5f * (pa.x + pb.x) + 6.0f, 0.5f * (pa.y + pb.y) + 4.0f), kColor, label);
  }
}

void Viewer::drawPanels() {
  const BrickSourceInfo& info = bricks().info();
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.85f);
  if (ImGui::Begin("Volume", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::PushItemWidth(200.0f);
    ImGui::Text("%s", o_.input.c_str());
    ImGui::Text("%u x %u x %u, values %g .. %g", info.volume.dims.x, info.volume.dims.y, info.volume.dims.z,
                valueRange_.first, valueRange_.second);
    if (info.volume.axes != AxisDirections(1.0))  // where a turned volume's axes point (core/orientation.h)
      ImGui::Text("axes %s", orientationCode(info.volume.axes).c_str());
    if (series_) drawSeriesControls();
    int mode = int(params_.mode);
    ImGui::RadioButton("iso", &mode, int(RenderMode::Iso));
    ImGui::SameLine();
    ImGui::RadioButton("DVR", &mode, int(RenderMode::Dvr));
    ImGui::SameLine();
    ImGui::RadioButton("MIP", &mode, int(RenderMode::Mip));
    ImGui::SameLine();
    ImGui::RadioButton("MinIP", &mode, int(RenderMode::MinIp));
    ImGui::SameLine();
    ImGui::RadioButton("AIP", &mode, int(RenderMode::Aip));
    ImGui::SameLine();
    ImGui::RadioButton("slice", &mode, int(RenderMode::Slice));
    if (mode != int(params_.mode)) setMode(RenderMode(mode));
    double iso = params_.isoValue;
    if (ImGui::SliderScalar("isovalue", ImGuiDataType_Double, &iso, &valueRange_.first, &valueRange_.second,
                            "%.4g"))
      params_.isoValue = iso;
    ImGui::PlotHistogram("##histogram", histogram_.data(), int(histogram_.size()), 0, nullptr, 0.0f, 1.0f,
                         ImVec2(200.0f, 40.0f));
    ImGui::SameLine();
    ImGui::TextDisabled("values, level %u\n(log counts)", histogramLevel_);

    ImGui::Separator();
    ImGui::Text("transfer function");
    std::vector<TfPoint> points = tf_.points();
    if (tfEditor_.draw(points, valueRange_.first, valueRange_.second, histogram_)) {
      try {
        setTransferFunction(TransferFunction(std::move(points)), "edited");
        tfChosen_ = true;
      } catch (const Error& e) {
        message_ = e.what();
      }
    }
    if (ImGui::BeginCombo("preset", tfSpec_.c_str())) {
      for (const std::string& name : TransferFunction::presetNames())
        if (ImGui::Selectable(name.c_str(), name == tfSpec_)) {
          setTransferFunction(name);
          tfEditor_.deselect();
        }
      ImGui::EndCombo();
    }
    // The window: where the function's first and last points lie (--tf-range); dragging it stretches the
    // function.
    float window[2] = {float(tf_.points().front().value), float(tf_.points().back().value)};
    const float windowSpeed = float(std::max(valueRange_.second - valueRange_.first, 1e-6) / 500.0);
    if (ImGui::DragFloatRange2("window", &window[0], &window[1], windowSpeed, float(valueRange_.first),
                               float(valueRange_.second), "%g", "%g") &&
        window[0] < window[1])
      setTfRange(window[0], window[1]);
    ImGui::InputText("file##tf", &tfPath_);
    if (ImGui::Button("load")) {
      try {
        setTransferFunction(tfPath_);
        tfEditor_.deselect();
        message_ = "loaded " + tfPath_;
      } catch (const Error& e) {
        message_ = e.what();
      }
    }
    ImGui::SameLine();
    if (ImGui::Button("save")) {
      try {
        checkPanelOutput("the panel's transfer function", tfPath_);
        saveTransferFunction(tfPath_, tf_);
        message_ = "wrote " + tfPath_;
      } catch (const Error& e) {
        reportPanelError(e);
      }
    }
    // Folded unless a cut is set (the options, a script): the panel stays short in a small window.
    if (std::exchange(unfoldCutControls_, false)) ImGui::SetNextItemOpen(true);
    if (ImGui::CollapsingHeader(params_.mode == RenderMode::Slice ? "crop box and slice plane###cuts"
                                                                  : "crop box and clip plane###cuts")) {
      drawCropControls(info);
      drawClipPlaneControls(info.volume);
      // --caps: an isosurface closed where the cuts cut it, or left open to show it from within.
      if (params_.mode == RenderMode::Iso) ImGui::Checkbox("caps on the cuts", &params_.isoCaps);
      drawCutOutlines(info.volume);
    }
    ImGui::PopItemWidth();
  }
  ImGui::End();
  if (orientationMarks_) drawOrientationMarks();
  drawRuler(info.volume);

  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(viewport->WorkPos.x + viewport->WorkSize.x - 8, viewport->WorkPos.y + 8),
                          ImGuiCond_FirstUseEver, ImVec2(1.0f, 0.0f));
  ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.85f);
  if (ImGui::Begin("Rendering", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::PushItemWidth(200.0f);
    float step = float(params_.stepVoxels), vpp = float(voxelsPerPixel_), target = float(targetFrameMs_);
    if (ImGui::SliderFloat("step (voxels)", &step, 0.05f, 4.0f, "%.2f", ImGuiSliderFlags_Logarithmic))
      params_.stepVoxels = step;
    if (ImGui::SliderFloat("voxels per pixel", &vpp, 0.25f, 16.0f, "%.2f", ImGuiSliderFlags_Logarithmic))
      voxelsPerPixel_ = vpp;
    if (ImGui::SliderFloat("target frame ms", &target, 0.0f, 200.0f, "%.0f")) {
      targetFrameMs_ = target;
      stepPacer_ = StepPacer(targetFrameMs_);
    }
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 320.0f);
    ImGui::TextDisabled("budgets (--gpu-budget, --cpu-cache, --upload-*) are set at start");
    ImGui::PopTextWrapPos();
    // In the combo's order; --backend brute never gets here (refused at start).
    constexpr RenderBackend kBackends[] = {RenderBackend::Auto, RenderBackend::Fragment,
                                           RenderBackend::Compute, RenderBackend::Multipass};
    int backend = int(std::find(std::begin(kBackends), std::end(kBackends), params_.backend) - kBackends);
    ImGui::Combo("backend", &backend, "auto\0fragment\0compute\0multipass\0");
    params_.backend = kBackends[std::clamp(backend, 0, int(std::size(kBackends)) - 1)];
    int gradients = params_.gradients == GradientSource::Stored ? 0 : 1;
    ImGui::Combo("DVR gradients", &gradients, "stored\0computed\0");
    params_.gradients = gradients == 0 ? GradientSource::Stored : GradientSource::Computed;

    ImGui::Separator();
    ImGui::Text("camera");
    const OrbitState& s = controller_->state();
    ImGui::Text("orbit %.1f, %.1f, %.2f", s.azimuthDeg, s.elevationDeg, s.distance);
    if (ImGui::Button("reset camera")) controller_->reset();
    // --view's sides of the patient, at the current distance.
    for (const auto& [name, view] : kAnatomicalViewNames) {
      ImGui::SameLine();
      const char label[] = {char(std::toupper(static_cast<unsigned char>(name[0]))), '\0'};
      if (ImGui::Button(label)) showAnatomicalView(view);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s view (--view %s)", name, name);
    }
    ImGui::InputText("path##camera", &cameraPath_);
    if (ImGui::Button("save camera")) {
      try {
        checkPanelOutput("the panel's camera path", cameraPath_);
        appendCameraKeyframe(cameraPath_, *controller_);
        message_ = "appended the view to " + cameraPath_;
      } catch (const std::exception& e) {
        reportPanelError(e);
      }
    }
    ImGui::InputText("png##shot", &screenshotPath_);
    if (ImGui::Button("screenshot")) {
      try {
        checkPanelOutput("the panel's screenshot", screenshotPath_);
        if (hasExtension(screenshotPath_, ".exr"))
          checkPanelOutput("the panel's screenshot (its depth)", screenshotDepthPath(screenshotPath_));
        screenshot(screenshotPath_, false);
      } catch (const Error& e) {
        reportPanelError(e);
      }
    }
    ImGui::Checkbox("orientation marks", &orientationMarks_);
    if (!ruler_.empty()) {
      ImGui::SameLine();
      if (ImGui::Button("clear ruler")) ruler_.clear();
    }
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("the sides of the patient at the view's edges, the volume's axes at the bottom");
    // Last, folded: the buttons above keep their places.
    if (ImGui::CollapsingHeader("lighting")) drawLightingControls();
    if (!message_.empty()) {
      ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 320.0f);
      ImGui::TextUnformatted(message_.c_str());
      ImGui::PopTextWrapPos();
    }
    ImGui::PopItemWidth();
  }
  ImGui::End();

  // Stats overlay, bottom right.
  ImGui::SetNextWindowPos(
      ImVec2(viewport->WorkPos.x + viewport->WorkSize.x - 8, viewport->WorkPos.y + viewport->WorkSize.y - 8),
      ImGuiCond_Always, ImVec2(1.0f, 1.0f));
  ImGui::SetNextWindowBgAlpha(0.6f);
  const ImGuiWindowFlags overlay = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                   ImGuiWindowFlags_NoNav;
  if (ImGui::Begin("Stats", nullptr, overlay)) {
    const FrameStats& st = lastStats_;
    ImGui::Text("%.1f fps  %.1f ms/frame  %s", lastDrawnMs_ > 0 ? 1000.0 / lastDrawnMs_ : 0.0, lastDrawnMs_,
                std::string(renderBackendName(st.backend)).c_str());
    ImGui::Text("leaves %llu  resident %llu  uploads %llu", (unsigned long long)st.leaves,
                (unsigned long long)st.bricksResident, (unsigned long long)st.bricksUploaded);
    if (st.backend == RenderBackend::Multipass)  // its fragments are the blocks', not pixels cast
      ImGui::Text("pending %llu  step %.2f", (unsigned long long)st.requestsPending, st.stepVoxels);
    else
      ImGui::Text("pending %llu  step %.2f  pixels cast %.0f%%", (unsigned long long)st.requestsPending,
                  st.stepVoxels, 100.0 * lastCastShare_);
    ImGui::Text("CPU cache %.1f MiB  GPU pool %.1f MiB", st.cpuCacheBytes / 1048576.0,
                st.gpuPoolUsedBytes / 1048576.0);
    ImGui::Text("visible %llu  occluded %llu  queries %llu", (unsigned long long)st.nodesVisible,
                (unsigned long long)st.nodesOccluded, (unsigned long long)st.occlusionQueries);
    ImGui::Text("feedback: used %llu  requests %llu", (unsigned long long)st.bricksUsed,
                (unsigned long long)st.feedbackRequests);
    ImGui::Text("%s", st.converged ? "converged" : "streaming...");
    // What the pointer points at in the 3D view (not over a panel).
    if (!ImGui::GetIO().WantCaptureMouse)
      if (const std::string probed = probe(windowPointer_.pos); !probed.empty())
        ImGui::Text("probe: %s", probed.c_str());
    if (st.leavesPoolFull > 0)
      ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.3f, 1.0f), "pool full: %llu leaves coarser (--gpu-budget)",
                         (unsigned long long)st.leavesPoolFull);
    std::vector<float> history(frameMsHistory_.begin(), frameMsHistory_.end());
    ImGui::PlotLines("##frame ms", history.data(), int(history.size()), 0, "frame ms", 0.0f, FLT_MAX,
                     ImVec2(220, 40));
  }
  ImGui::End();
}

int Viewer::run() {
  start_ = SteadyClock::now();
  auto lastLoop = SteadyClock::now();
  bool viewConverged = false, converged = false, screenshotWritten = false;
  while (!window_->shouldClose()) {
    const bool scriptActive = script_ && !scriptDone();
    // Nothing to refine: wait for the user, or for the script's next event (or a time point being made: its
    // thread wakes the window when it is, and the panel's progress shows at the wait's timeout).
    const bool still = viewConverged && !windowDragOwned_ && scriptKeys_.empty() && !panelShot_ &&
                       secondsSince(start_) - lastMoveSeconds_ > kStillAfterSeconds;
    const double untilEvent = scriptActive ? secondsToNextEvent() : HUGE_VAL;
    if (still && untilEvent > 0.0)
      glfwWaitEventsTimeout(std::min(0.1, untilEvent));
    else
      glfwPollEvents();
    const double dt = std::min(0.1, secondsSince(lastLoop));
    lastLoop = SteadyClock::now();
    window_->framebufferSize(viewWidth_, viewHeight_);
    if (viewWidth_ == 0 || viewHeight_ == 0) {  // minimized: nothing to draw into
      glfwWaitEventsTimeout(0.1);
      continue;
    }

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    readWindowInput(dt);
    runScript(converged);
    // A screenshot with panels shows the camera its event saw: held keys fly on in the next frame.
    if (!panelShot_) flyScriptKeys(secondsSince(start_));
    drawPanels();
    ImGui::Render();

    const Camera camera = controller_->camera();
    if (camera != lastCamera_) lastMoveSeconds_ = secondsSince(start_);
    lastCamera_ = camera;
    const bool moving = secondsSince(start_) - lastMoveSeconds_ < kStillAfterSeconds;
    if (!moving) coarser_ = false;
    followPick();
    ensureRenderer(moving);  // may fall back to computed gradients (params_)
    const FrameRequest request = currentRequest(moving);
    if (needsFrame(request)) {
      renderFrame(request);
      if (moving && stepPacer_.enabled() && lastStats_.drawn) {
        stepPacer_.record(lastStats_.frameMs, lastStats_.raycastMs);
        coarser_ = stepPacer_.scale() >= StepPacer::kMaxScale && lastStats_.frameMs > targetFrameMs_;
      }
      // An output waiting for convergence on a still view that uploaded nothing: wait (briefly) for the
      // reads, as render --converge does, rather than spend the --max-frames it may wait on frames that
      // could only show the same cut.
      if (!moving && waitingForConvergence() && lastStats_.bricksUploaded == 0 &&
          lastStats_.requestsPending > 0)
        renderer_->waitForReads(std::chrono::milliseconds(100));
    }
    viewConverged = !moving && !needsFrame(currentRequest(false));
    playOn(viewConverged);
    // A time point asked for and still being made: what waits for the view waits for it too.
    converged = viewConverged && !pickPending();

    present(viewWidth_, viewHeight_);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (panelShot_) {
      const ViewEvent shot = *std::exchange(panelShot_, std::nullopt);
      try {
        screenshot(shot.file, true);
      } catch (const Error& e) {
        throw Error(shot.where + ": " + e.what());
      }
    }
    window_->swapBuffers();

    if (scriptDone()) {
      if (o_.screenshot.empty()) break;
      if (converged || (!pickPending() && ++waitedFrames_ > o_.maxFrames)) {
        if (!converged)
          std::fprintf(stderr,
                       "ropecast view: --screenshot: not converged after %u frames (--max-frames); writing "
                       "it anyway\n",
                       o_.maxFrames);
        screenshot(o_.screenshot, false);
        screenshotWritten = true;
        break;
      }
    }
  }
  // The window closed first: an output asked for is missing, which a script waiting on it must hear (and the
  // stats of a run that ends in an error are not kept).
  if (!o_.screenshot.empty() && !screenshotWritten)
    throw Error("view: the window was closed before --screenshot " + o_.screenshot + " was written");
  for (size_t i = script_ ? nextEvent_ : 0; script_ && i < script_->events.size(); ++i) {
    const ViewEvent& e = script_->events[i];
    if (e.kind == ViewEventKind::Screenshot || e.kind == ViewEventKind::SaveCamera)
      throw Error(e.where + ": the window was closed before it wrote " + e.file);
  }
  if (stats_) stats_->finish();
  return 0;
}

bool Viewer::waitingForConvergence() const {
  if (!script_) return false;
  if (scriptDone()) return !o_.screenshot.empty();
  const ViewEvent& e = script_->events[nextEvent_];
  return waitsForConvergence(e.kind) && e.atSeconds <= secondsSince(start_);
}

double Viewer::secondsToNextEvent() const {
  if (!script_ || scriptDone()) return 0.0;
  return std::max(0.0, script_->events[nextEvent_].atSeconds - secondsSince(start_));
}

}  // namespace

std::string screenshotDepthPath(const std::string& exrPath) {
  const std::filesystem::path p(exrPath);
  return (p.parent_path() / (p.stem().string() + "_depth.exr")).string();
}

int runViewer(const ViewOptions& options, std::optional<ViewScript> script, OutputGuard guard) {
  // --screenshot alone: an empty script, so the viewer ends once the screenshot is written.
  if (!script && !options.screenshot.empty()) script = ViewScript{};
  Viewer viewer(options, std::move(script), std::move(guard));
  return viewer.run();
}

}  // namespace ropecast::tools
