#include "tools/regress_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <span>
#include <sstream>

#include "core/error.h"
#include "core/temporary_file.h"

namespace ropecast::tools {
namespace {

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string number(const char* format, double v) {
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

std::string image(const std::string& file, const char* caption, uint32_t width) {
  if (file.empty())
    return "<figure><div class=none>no " + std::string(caption) + "</div><figcaption>" + caption +
           "</figcaption></figure>";
  // Small goldens are shown enlarged, pixel for pixel, so single differing pixels stay visible.
  const uint32_t shown =
      std::clamp<uint32_t>(width * std::max<uint32_t>(1, 256 / std::max<uint32_t>(width, 1)), 64, 512);
  return "<figure><a href=\"" + escape(file) + "\"><img src=\"" + escape(file) +
         "\" width=" + std::to_string(shown) + "></a><figcaption>" + caption + "</figcaption></figure>";
}

}  // namespace

void writeRegressReport(const std::string& directory, const std::string& suitePath,
                        const std::vector<CaseOutcome>& outcomes) {
  std::vector<const CaseOutcome*> order;
  for (const CaseOutcome& outcome : outcomes) order.push_back(&outcome);
  std::stable_sort(order.begin(), order.end(),
                   [](const CaseOutcome* a, const CaseOutcome* b) { return !a->passed && b->passed; });
  const size_t failed =
      size_t(std::count_if(outcomes.begin(), outcomes.end(), [](auto& o) { return !o.passed; }));

  std::ostringstream html;
  html << "<!doctype html>\n<html><head><meta charset=utf-8><title>ropecast regress: " << escape(suitePath)
       << "</title>\n<style>\n"
          "body{font:14px sans-serif;margin:1.5em;background:#fafafa}\n"
          "section{border:1px solid #ccc;border-left:8px solid #3a3;background:#fff;margin:1em "
          "0;padding:.5em 1em}\n"
          "section.fail{border-left-color:#c22}\n"
          "figure{display:inline-block;margin:.3em .6em .3em 0;vertical-align:top}\n"
          "img{image-rendering:pixelated;border:1px solid #888;background:#000}\n"
          ".none{width:256px;height:64px;border:1px dashed "
          "#888;color:#888;text-align:center;line-height:64px}\n"
          ".scale{width:256px;height:12px;background:linear-gradient(to right,#000,#fff);border:1px solid "
          "#888}\n"
          ".ends{width:258px;display:flex;justify-content:space-between;font-size:12px}\n"
          "table{border-collapse:collapse}td{padding:0 1em 0 0}\n"
          "</style></head><body>\n<h1>ropecast regress</h1>\n<p>"
       << escape(suitePath) << ": " << outcomes.size() << " cases, " << failed
       << " failed (listed first).</p>\n";
  for (const CaseOutcome* o : order) {
    const RegressCase& c = *o->regressCase;
    const RegressTolerances& t = c.tolerances;
    html << "<section class=" << (o->passed ? "pass" : "fail") << "><h2>" << (o->passed ? "ok" : "FAIL")
         << " " << escape(c.name) << (o->updated ? " (golden updated)" : "") << "</h2>\n";
    std::string options;
    for (const std::string& option : c.options) options += " " + option;
    // What the case renders: the converged frame, which a plain `render` would not.
    if (o->converges && std::find(c.options.begin(), c.options.end(), "--converge") == c.options.end())
      options += " --converge";
    html << "<p><code>ropecast render " << escape(c.input) << escape(options) << "</code></p>\n";
    for (const std::string& problem : o->problems) html << "<p><b>" << escape(problem) << "</b></p>\n";
    html << "<table>\n";
    if (o->difference) {
      const GoldenDifference& d = *o->difference;
      html << "<tr><td>PSNR</td><td>" << (std::isinf(d.psnrDb) ? "inf" : number("%.2f", d.psnrDb))
           << " dB</td><td>at least " << number("%g", t.minPsnrDb) << " dB</td></tr>\n"
           << "<tr><td>max error</td><td>" << number("%.4f", d.maxError) << "</td><td>at most "
           << number("%g", t.maxPixelError) << "</td></tr>\n"
           << "<tr><td>failing pixels</td><td>" << d.failingPixels << " = "
           << number("%.3f", 100.0 * d.failingShare) << "%</td><td>at most "
           << number("%g", 100.0 * t.maxFailingShare) << "% differing by more than "
           << number("%.4f", t.failingPixelError) << "</td></tr>\n";
    }
    html << "<tr><td>time</td><td>" << number("%.2f", o->seconds) << " s</td><td></td></tr>\n</table>\n";
    const uint32_t width = o->difference ? o->difference->width : 128;
    html << image(o->goldenFile, "golden", width) << image(o->renderFile, "render", width);
    if (o->difference && !o->differenceFile.empty()) {
      const double amplification = o->difference->amplification;
      html << "<figure><a href=\"" << escape(o->differenceFile) << "\"><img src=\""
           << escape(o->differenceFile) << "\" width="
           << std::clamp<uint32_t>(width * std::max<uint32_t>(1, 256 / std::max<uint32_t>(width, 1)), 64, 512)
           << "></a><figcaption>|golden - render| x " << number("%g", amplification)
           << "<div class=scale></div><div class=ends><span>0</span><span>"
           << number("%.4g", 1.0 / amplification) << " or more</span></div></figcaption></figure>";
    }
    html << "\n</section>\n";
  }
  html << "</body></html>\n";

  const std::string text = html.str();
  TemporaryFile file(std::filesystem::path(directory) / "index.html", "regress --report");
  file.writeAt(0, std::as_bytes(std::span(text)));
  file.commit();
}

}  // namespace ropecast::tools
