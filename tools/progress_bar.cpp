#include "tools/progress_bar.h"

#include <unistd.h>

#include <cstdio>
#include <iterator>
#include <string>

#include "core/elapsed.h"

namespace ropecast::tools {

std::string formatBytes(uint64_t bytes) {
  if (bytes < 1024) return std::to_string(bytes) + " B";
  const char* units[] = {"KiB", "MiB", "GiB", "TiB"};
  double value = double(bytes) / 1024.0;
  size_t unit = 0;
  while (value >= 1024.0 && unit + 1 < std::size(units)) value /= 1024.0, ++unit;
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %s", value, units[unit]);
  return text;
}

std::string formatDuration(double seconds) {
  const long s = seconds < 0 ? 0 : long(seconds + 0.5);
  char text[32];
  if (s >= 3600)
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

bool ProgressBar::stderrIsTerminal() {
  return ::isatty(STDERR_FILENO) == 1;
}

ProgressBar::ProgressBar(std::string label, std::string unit, bool quiet)
    : label_(std::move(label)), unit_(std::move(unit)), enabled_(!quiet && stderrIsTerminal()) {
  start_ = std::chrono::steady_clock::now();
}

ProgressBar::~ProgressBar() {
  finish();
}

void ProgressBar::update(uint64_t done, uint64_t total) {
  if (!enabled_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && done < total && now - lastDraw_ < std::chrono::milliseconds(100)) return;
  lastDraw_ = now;
  draw(done, total);
}

void ProgressBar::status(const std::string& text, bool now) {
  if (!enabled_ || finished_) return;
  const auto time = std::chrono::steady_clock::now();
  if (drawn_ && !now && time - lastDraw_ < std::chrono::milliseconds(100)) return;
  lastDraw_ = time;
  std::string line =
      label_ + ": " + text + "  " + formatDuration(std::chrono::duration<double>(time - start_).count());
  const size_t width = line.size();
  if (width < lastStatusWidth_) line.append(lastStatusWidth_ - width, ' ');
  lastStatusWidth_ = width;
  std::fprintf(stderr, "\r%s", line.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::draw(uint64_t done, uint64_t total) {
  constexpr int kWidth = 30;
  const double fraction = total > 0 ? double(done) / double(total) : 1.0;
  const double seconds = secondsSince(start_);
  const double rate = seconds > 0 ? double(done) / seconds : 0.0;
  std::string bar(size_t(fraction * kWidth), '#');
  bar.resize(kWidth, ' ');
  char rateText[48];
  if (unit_ == "B")
    std::snprintf(rateText, sizeof rateText, "%.1f MiB/s", rate / (1024.0 * 1024.0));
  else
    std::snprintf(rateText, sizeof rateText, "%.0f %s/s", rate, unit_.c_str());
  const std::string eta = rate > 0 && done < total ? formatDuration(double(total - done) / rate) : "0:00";
  std::fprintf(stderr, "\r%s [%s] %5.1f%%  %s  ETA %s   ", label_.c_str(), bar.c_str(), 100.0 * fraction,
               rateText, eta.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  if (enabled_ && drawn_) std::fputc('\n', stderr);
}

}  // namespace ropecast::tools
