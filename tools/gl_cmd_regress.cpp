// `ropecast regress SUITE.json`: renders every case of a regression suite (tools/regress_suite.h,
// docs/REGRESS.md) as `ropecast render --converge` would, compares each with its golden image, reports per
// case, optionally updates goldens and writes an HTML report. Exit 0: all pass; 1: a case failed; 2: the
// suite or the command line cannot be run as written. Main thread; --jobs N renders in child processes of
// this executable (`ropecast render`), each with its own GL context.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <sstream>

#include "core/elapsed.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/temporary_file.h"
#include "reference/image_io.h"
#include "store/procedural.h"
#include "tools/cli_values.h"
#include "tools/command.h"
#include "tools/gl_render_options.h"
#include "tools/output_guard.h"
#include "tools/parse_error_text.h"
#include "tools/regress_images.h"
#include "tools/regress_report.h"
#include "tools/regress_suite.h"
#include "tools/render_command.h"

extern char** environ;

namespace ropecast::tools {
namespace {

namespace fs = std::filesystem;

struct RegressArgs {
  std::string suite, report;
  bool update = false, updateAll = false;
  unsigned jobs = 1;
};

// A case's render options as `ropecast render` parses them; file outputs are regress's business.
RenderOptions parseCaseOptions(const RegressCase& c, const std::string& suitePath) {
  const std::string where = suitePath + ": case '" + c.name + "'";
  RenderOptions o;
  CLI::App app{"ropecast render options of case " + c.name};
  addRenderOptions(app, o);
  app.add_option("-o,--output", o.output);  // render's own, parsed here to be refused below
  std::vector<std::string> args(c.options.rbegin(), c.options.rend());  // CLI11 parses a reversed vector
  // Every case converges (below); said here too, so that --max-frames, which needs it, is taken.
  if (std::find(args.begin(), args.end(), "--converge") == args.end()) args.push_back("--converge");
  try {
    app.parse(args);
  } catch (const CLI::CallForHelp&) {
    throw SuiteError(where +
                     ": options: --help asks for help, which a case cannot show; give render options");
  } catch (const CLI::CallForAllHelp&) {
    throw SuiteError(where +
                     ": options: --help-all asks for help, which a case cannot show; give render options");
  } catch (const CLI::ParseError& e) {
    throw SuiteError(where + ": options: " + parseErrorText(app, e));
  }
  const auto refuse = [&where](bool given, const char* option) {
    if (given)
      throw SuiteError(where + ": options: " + option +
                       " writes a file; regress renders to its report or a temporary folder");
  };
  refuse(app.count("--output") > 0, "-o");
  refuse(!o.exr.empty(), "--exr");
  refuse(!o.depth.empty(), "--depth");
  refuse(!o.stats.empty(), "--stats");
  refuse(o.every > 0, "--every");
  if (o.targetFrameMs > 0.0)  // the step it sets follows the frame times, so the image differs run to run
    throw SuiteError(where +
                     ": options: --target-frame-ms adapts the step to this machine's frame times, so the "
                     "image would differ from run to run; give --step instead");
  o.quiet = true;  // cases render side by side (--jobs): their progress lines would mix
  o.messagePrefix = "case '" + c.name + "': ";  // as the lines of a child process are shown (renderCases)
  o.input = c.input;
  // The converged frame: progressive frames until nothing is pending (docs/REGRESS.md); --reference renders
  // its one image, and refuses --converge as render does.
  if (o.reference && std::find(c.options.begin(), c.options.end(), "--converge") != c.options.end())
    throw SuiteError(where +
                     ": options: --converge has nothing to do with --reference (one CPU render of "
                     "the full-resolution data); leave one of them out");
  o.converge = !o.reference;
  if (!isProceduralSpec(c.input) && !fs::is_regular_file(c.input))
    throw SuiteError(where + ": input " + c.input + ": " +
                     (fs::exists(c.input) ? "not a regular file" : "no such store file"));
  if (isProceduralSpec(c.input)) {
    try {
      parseProceduralField(proceduralNameAndSize(c.input));
    } catch (const UsageError& e) {
      throw SuiteError(where + ": input: " + e.what());
    }
  }
  try {
    checkSceneOptions(o);
  } catch (const UsageError& e) {
    throw SuiteError(where + ": options: " + e.what());
  }
  return o;
}

// The folder for the renders: --report's, else a temporary one, removed at the end (and on Ctrl-C).
class WorkFolder {
 public:
  explicit WorkFolder(const std::string& report) {
    if (report.empty()) {
      temporary_.emplace("ropecast-regress");
      path_ = temporary_->path().string();
    } else {
      path_ = report;
    }
  }
  const std::string& path() const { return path_; }

 private:
  std::optional<TemporaryFolder> temporary_;
  std::string path_;
};

void copyAtomically(const std::string& from, const std::string& to, const char* who) {
  requireRegularFile(from, std::string(who) + ": " + from);  // a FIFO would block
  std::ifstream in(from, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in) throw Error(std::string(who) + ": cannot read " + from);
  const std::string data = bytes.str();
  std::error_code ec;
  if (const fs::path parent = fs::path(to).parent_path(); !parent.empty()) fs::create_directories(parent, ec);
  writeFileAtomically(to, std::as_bytes(std::span(data)), who);
}

// A child that has ended and not been reaped (waitid with WNOWAIT): no longer signalled by the handlers, then
// reaped, so that its pid is never signalled after it can be reused. Its wait status.
int reapEnded(pid_t pid) {
  stopForwardingSignalsToChild(pid);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

// SIGINT, SIGTERM and SIGHUP held back for the object's life (they are delivered when it ends).
struct InterruptsHeld {
  sigset_t previous;
  InterruptsHeld() {
    sigset_t interrupts;
    sigemptyset(&interrupts);
    for (int signal : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&interrupts, signal);
    pthread_sigmask(SIG_BLOCK, &interrupts, &previous);
  }
  ~InterruptsHeld() { pthread_sigmask(SIG_SETMASK, &previous, nullptr); }
  InterruptsHeld(const InterruptsHeld&) = delete;
  InterruptsHeld& operator=(const InterruptsHeld&) = delete;
};

// Renders the cases into `folder`/NAME.render.png: here, one after another, or in up to `jobs` child
// processes running `ropecast render ... --converge -o` (the same code). Sets each outcome's seconds and
// problems; a failed render leaves renderFile empty.
void renderCases(const std::vector<RenderOptions>& options, std::vector<CaseOutcome>& outcomes,
                 const std::string& folder, unsigned jobs) {
  const auto renderFile = [](const CaseOutcome& o) { return o.regressCase->name + ".render.png"; };
  if (jobs <= 1) {
    for (size_t i = 0; i < outcomes.size(); ++i) {
      CaseOutcome& o = outcomes[i];
      const auto start = SteadyClock::now();
      try {
        const RenderedFrame frame = renderFrames(options[i]);
        writePng((fs::path(folder) / renderFile(o)).string(), colorOutputOf(options[i], frame), false);
        o.renderFile = renderFile(o);
      } catch (const std::exception& e) {
        o.problems.push_back(std::string("render failed: ") + e.what());
      }
      o.seconds = secondsSince(start);
    }
    return;
  }
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  std::map<pid_t, std::pair<size_t, SteadyClock::time_point>> running;
  // An error ends the run: the renders still running end with it (they write into `folder`, which goes).
  struct EndRunningRenders {
    std::map<pid_t, std::pair<size_t, SteadyClock::time_point>>& running;
    ~EndRunningRenders() {
      for (const auto& entry : running) ::kill(entry.first, SIGTERM);
      for (const auto& entry : running) {
        siginfo_t ended{};
        ::waitid(P_PID, id_t(entry.first), &ended, WEXITED | WNOWAIT);
        reapEnded(entry.first);
      }
    }
  } endRunningRenders{running};
  size_t next = 0;
  // The renders' output, read back when each ends: in a folder of its own, so that an interrupted run leaves
  // none in the report folder (TemporaryFolder's files go on SIGINT/SIGTERM too).
  const TemporaryFolder logs("ropecast-regress-logs");
  const auto logOf = [&](size_t i) {
    return (logs.path() / (outcomes[i].regressCase->name + ".log")).string();
  };
  while (next < outcomes.size() || !running.empty()) {
    while (next < outcomes.size() && running.size() < jobs) {
      const RegressCase& c = *outcomes[next].regressCase;
      std::vector<std::string> args{self, "render", c.input};
      args.insert(args.end(), c.options.begin(), c.options.end());
      if (outcomes[next].converges &&
          std::find(c.options.begin(), c.options.end(), "--converge") == c.options.end())
        args.push_back("--converge");
      args.push_back("-o");
      args.push_back((fs::path(folder) / renderFile(outcomes[next])).string());
      std::vector<char*> argv;
      for (std::string& arg : args) argv.push_back(arg.data());
      argv.push_back(nullptr);
      posix_spawn_file_actions_t actions;
      posix_spawn_file_actions_init(&actions);
      const std::string log = logOf(next);
      posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      posix_spawn_file_actions_adddup2(&actions, 1, 2);
      // An interrupting signal waits until the child is one the handlers pass it on to; the child starts
      // with the mask regress had before.
      const InterruptsHeld held;
      posix_spawnattr_t attributes;
      posix_spawnattr_init(&attributes);
      posix_spawnattr_setsigmask(&attributes, &held.previous);
      posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
      pid_t pid = 0;
      const int rc = posix_spawn(&pid, self.c_str(), &actions, &attributes, argv.data(), environ);
      posix_spawnattr_destroy(&attributes);
      posix_spawn_file_actions_destroy(&actions);
      if (rc != 0) throw Error("regress: cannot start " + self + " render: " + std::strerror(rc));
      forwardSignalsToChild(pid);
      running[pid] = {next, SteadyClock::now()};
      ++next;
    }
    siginfo_t ended{};
    if (::waitid(P_ALL, 0, &ended, WEXITED | WNOWAIT) != 0) {
      if (errno == EINTR) continue;
      throw Error(std::string("regress: waiting for a render failed: ") + std::strerror(errno));
    }
    const pid_t pid = ended.si_pid;
    const int status = reapEnded(pid);
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const auto [i, start] = it->second;
    running.erase(it);
    CaseOutcome& o = outcomes[i];
    o.seconds = secondsSince(start);
    std::ifstream logFile(logOf(i));
    std::ostringstream log;
    log << logFile.rdbuf();
    std::error_code ec;
    fs::remove(logOf(i), ec);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      o.renderFile = renderFile(o);
      // What the render warned (not converged within --max-frames, an isovalue outside the data), as
      // --jobs 1 shows it, with the case it concerns.
      std::istringstream lines(log.str());
      for (std::string line; std::getline(lines, line);)
        std::fprintf(stderr, "case '%s': %s\n", o.regressCase->name.c_str(), line.c_str());
    } else
      o.problems.push_back("render failed (" +
                           (WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status))
                                              : "signal " + std::to_string(WTERMSIG(status))) +
                           "): " + log.str());
  }
}

std::string describe(const GoldenDifference& d) {
  char text[160];
  std::snprintf(text, sizeof text, "PSNR %s dB, max error %.4f, failing %.3f%% (%llu px)",
                formatNumber(std::isinf(d.psnrDb) ? d.psnrDb : std::round(d.psnrDb * 100.0) / 100.0).c_str(),
                d.maxError, 100.0 * d.failingShare, static_cast<unsigned long long>(d.failingPixels));
  return text;
}

// Compares each rendered case with its golden; writes report copies of the golden and the difference image
// when `report` is set.
void compareCases(std::vector<CaseOutcome>& outcomes, const std::string& folder, const std::string& suitePath,
                  bool report) {
  for (CaseOutcome& o : outcomes) {
    if (o.renderFile.empty()) continue;
    const RegressCase& c = *o.regressCase;
    const RegressTolerances& t = c.tolerances;
    if (!fs::exists(c.golden)) {
      o.problems.push_back("no golden image " + c.golden + ": run `ropecast regress " + suitePath +
                           " --update` to create it from this render (look at it first)");
      continue;
    }
    try {
      if (report) {  // first, so that the report shows a golden that cannot be compared (another size)
        o.goldenFile = c.name + ".golden.png";
        copyAtomically(c.golden, (fs::path(folder) / o.goldenFile).string(), "regress --report");
      }
      FloatImage difference;
      o.difference = compareWithGolden(c.golden, (fs::path(folder) / o.renderFile).string(),
                                       t.failingPixelError, report ? &difference : nullptr);
      if (report) {
        o.differenceFile = c.name + ".difference.png";
        writePng((fs::path(folder) / o.differenceFile).string(), difference, false);
      }
    } catch (const Error& e) {
      o.problems.push_back(e.what());
      continue;
    }
    const GoldenDifference& d = *o.difference;
    if (d.psnrDb < t.minPsnrDb)
      o.problems.push_back("PSNR " + formatNumber(d.psnrDb) + " dB < min_psnr_db " +
                           formatNumber(t.minPsnrDb));
    if (d.maxError > t.maxPixelError)
      o.problems.push_back("max error " + formatNumber(d.maxError) + " > max_pixel_error " +
                           formatNumber(t.maxPixelError));
    if (d.failingShare > t.maxFailingShare)
      o.problems.push_back("failing share " + formatNumber(d.failingShare) + " > max_failing_share " +
                           formatNumber(t.maxFailingShare) + " (pixels differing by more than " +
                           formatNumber(t.failingPixelError) + ")");
  }
  for (CaseOutcome& o : outcomes) o.passed = o.problems.empty();
}

int runRegress(const RegressArgs& a) {
  RegressSuite suite;
  std::vector<RenderOptions> options;
  try {
    suite = loadRegressSuite(a.suite);
    for (const RegressCase& c : suite.cases) options.push_back(parseCaseOptions(c, suite.path));
  } catch (const SuiteError& e) {
    std::fprintf(stderr, "ropecast regress: bad suite: %s\n", e.what());
    return 2;
  }
  const bool updating = a.update || a.updateAll;

  // Nothing regress writes (goldens, report files) may be something it reads, nor two of them one file.
  OutputGuard guard("regress");
  guard.addInput("the suite", suite.path);
  for (size_t i = 0; i < suite.cases.size(); ++i) {
    const RegressCase& c = suite.cases[i];
    guard.addVolumeInput("the input of case '" + c.name + "'", c.input);
    if (fs::is_regular_file(options[i].tf)) guard.addInput("--tf of case '" + c.name + "'", options[i].tf);
    guard.addInput("--path of case '" + c.name + "'", options[i].path);
    if (updating)
      guard.addOutput("the golden of case '" + c.name + "'", c.golden);
    else
      guard.addInput("the golden of case '" + c.name + "'", c.golden);
  }
  if (!a.report.empty()) {
    guard.addOutput("--report", (fs::path(a.report) / "index.html").string());
    for (const RegressCase& c : suite.cases)
      for (const char* suffix : {".render.png", ".golden.png", ".difference.png"})
        guard.addOutput("--report", (fs::path(a.report) / (c.name + suffix)).string());
  }
  if (const std::string problem = guard.problem(); !problem.empty()) {
    std::fprintf(stderr, "ropecast %s\n", problem.c_str());
    return 2;
  }

  if (!a.report.empty()) {
    std::error_code ec;
    fs::create_directories(a.report, ec);
    if (ec) {  // the run cannot be made as asked: exit 2, as for an output the guard refuses
      std::fprintf(stderr, "ropecast regress: --report %s: cannot create the folder: %s\n", a.report.c_str(),
                   ec.message().c_str());
      return 2;
    }
  }
  removeTemporaryFilesOnSignals();  // an interrupted run leaves no temporary behind
  const WorkFolder folder(a.report);
  std::vector<CaseOutcome> outcomes(suite.cases.size());
  for (size_t i = 0; i < suite.cases.size(); ++i) {
    outcomes[i].regressCase = &suite.cases[i];
    outcomes[i].converges = options[i].converge;
  }
  renderCases(options, outcomes, folder.path(), a.jobs);
  compareCases(outcomes, folder.path(), suite.path, !a.report.empty());

  size_t failed = 0, updated = 0;
  for (CaseOutcome& o : outcomes) {
    const RegressCase& c = *o.regressCase;
    if (!o.renderFile.empty() && (a.updateAll || (a.update && !o.passed))) {
      const std::string render = (fs::path(folder.path()) / o.renderFile).string();
      try {  // a render that cannot be read or a golden that cannot be written fails its case, no other
        if (!o.difference) checkRenderImage(render);  // a comparison read it whole already
        copyAtomically(render, c.golden, "regress --update");
        o.updated = true;
        ++updated;
      } catch (const Error& e) {
        o.passed = false;
        if (std::find(o.problems.begin(), o.problems.end(), e.what()) == o.problems.end())
          o.problems.push_back(e.what());  // the comparison may have said it already
      }
    }
    const std::string figures = o.difference ? describe(*o.difference) + ", " : "";
    if (o.passed) {
      std::printf("ok   %-24s %s%.2f s%s\n", c.name.c_str(), figures.c_str(), o.seconds,
                  o.updated ? " (golden rewritten)" : "");
    } else {
      std::string why;
      for (const std::string& problem : o.problems) why += (why.empty() ? "" : "; ") + problem;
      std::printf("%s %-24s %s%.2f s: %s%s\n", o.updated ? "UPD " : "FAIL", c.name.c_str(), figures.c_str(),
                  o.seconds, why.c_str(), o.updated ? " -> golden updated from this render" : "");
      if (!o.updated) ++failed;
    }
  }
  if (!a.report.empty()) {
    writeRegressReport(folder.path(), suite.path, outcomes);
  }
  std::printf("%zu cases, %zu failed%s%s\n", outcomes.size(), failed,
              updated ? (", " + std::to_string(updated) + " goldens updated").c_str() : "",
              a.report.empty() ? "" : (", report " + (fs::path(a.report) / "index.html").string()).c_str());
  std::fflush(stdout);
  return failed == 0 ? 0 : 1;
}

const CommandRegistration regressCommand("regress", 60, [](CLI::App& app) -> std::function<int()> {
  auto a = std::make_shared<RegressArgs>();
  app.description("render a suite of cases (JSON) and compare each with its golden image (docs/REGRESS.md)");
  app.add_option("suite", a->suite, "suite file (JSON): cases of input, render options, golden image")
      ->required();
  app.add_flag("--update", a->update, "write the goldens of failing or missing cases from their renders")
      ->excludes(
          app.add_flag("--update-all", a->updateAll, "write the goldens of all cases from their renders"));
  app.add_option("--report", a->report, "write an HTML report (index.html and its images) into this folder");
  app.add_option("--jobs", a->jobs, "cases rendered at once, each in its own process (`ropecast render`)")
      ->transform(integerRange(1, 64))
      ->capture_default_str();
  return [a] { return runRegress(*a); };
});

}  // namespace
}  // namespace ropecast::tools
