// ProgressBar: a one-line bar with percentage, rate and ETA on stderr, for long commands (convert, verify),
// or a status line where the total is not known (render). Draws only when enabled (stderr is a terminal and
// --quiet was not given), at most ~10 times a second. Owned by the command that runs; update() from one
// thread at a time.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace ropecast::tools {

class ProgressBar {
 public:
  // `unit` names what `done`/`total` count: "B" gives MiB/s, anything else "<unit>/s".
  ProgressBar(std::string label, std::string unit, bool quiet);
  ~ProgressBar();

  void update(uint64_t done, uint64_t total);
  // For work whose total is not known ahead (a render's loading): "label: text  elapsed" in place of the
  // bar, at most ~10 times a second; `now` draws it whatever the time (the last state before finish()).
  void status(const std::string& text, bool now = false);
  void finish();  // ends the line (once)
  bool enabled() const { return enabled_; }

  // True when stderr is a terminal.
  static bool stderrIsTerminal();

 private:
  void draw(uint64_t done, uint64_t total);

  std::string label_, unit_;
  bool enabled_ = false, drawn_ = false, finished_ = false;
  size_t lastStatusWidth_ = 0;  // a shorter status line pads to cover the last one
  std::chrono::steady_clock::time_point start_, lastDraw_;
};

// "1:02:03", "4:05".
std::string formatDuration(double seconds);
// Bytes in MiB, for messages.
inline double mebibytes(uint64_t bytes) {
  return double(bytes) / (1024.0 * 1024.0);
}
// Bytes in the largest unit that keeps a whole number in front: "900 B", "12.3 KiB", "4.5 MiB", "1.2 GiB".
std::string formatBytes(uint64_t bytes);

}  // namespace ropecast::tools
