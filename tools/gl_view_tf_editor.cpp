#include "tools/gl_view_tf_editor.h"

#include <algorithm>
#include <cmath>

#include <imgui.h>

namespace ropecast::tools {

namespace {

constexpr float kCanvasWidth = 320.0f, kCanvasHeight = 110.0f, kStripHeight = 14.0f, kHandleRadius = 5.0f;

ImU32 colorOf(const glm::dvec4& rgba, float alpha = 1.0f) {
  return ImGui::GetColorU32(ImVec4(float(rgba.r), float(rgba.g), float(rgba.b), alpha));
}

}  // namespace

bool TfEditor::draw(std::vector<TfPoint>& points, double lo, double hi, const std::vector<float>& histogram) {
  if (hi <= lo) hi = lo + 1.0;
  const TransferFunction function(points);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float width = kCanvasWidth;
  // Screen position of (value, opacity) and back.
  auto toScreen = [&](double value, double alpha) {
    return ImVec2(origin.x + float((value - lo) / (hi - lo)) * width,
                  origin.y + kCanvasHeight * (1.0f - float(std::sqrt(std::clamp(alpha, 0.0, 1.0)))));
  };
  auto valueAt = [&](float x) { return lo + (hi - lo) * std::clamp(double(x - origin.x) / width, 0.0, 1.0); };
  auto alphaAt = [&](float y) {
    const double s = std::clamp(1.0 - double(y - origin.y) / kCanvasHeight, 0.0, 1.0);
    return s * s;
  };

  draw->AddRectFilled(origin, ImVec2(origin.x + width, origin.y + kCanvasHeight), IM_COL32(20, 20, 24, 255));
  for (size_t i = 0; i < histogram.size(); ++i) {
    const float x0 = origin.x + width * float(i) / float(histogram.size());
    const float x1 = origin.x + width * float(i + 1) / float(histogram.size());
    draw->AddRectFilled(ImVec2(x0, origin.y + kCanvasHeight * (1.0f - histogram[i])),
                        ImVec2(x1, origin.y + kCanvasHeight), IM_COL32(50, 50, 60, 255));
  }
  constexpr int kSteps = 96;
  for (int i = 0; i < kSteps; ++i) {
    const double v = lo + (hi - lo) * (i + 0.5) / kSteps;
    const glm::dvec4 c = function.evaluate(v);
    const float x0 = origin.x + width * i / kSteps, x1 = origin.x + width * (i + 1) / kSteps;
    draw->AddRectFilled(ImVec2(x0, origin.y + kCanvasHeight),
                        ImVec2(x1, origin.y + kCanvasHeight + kStripHeight), colorOf(c));
    // The opacity curve, filled in the function's color.
    const ImVec2 top = toScreen(v, c.a);
    draw->AddRectFilled(ImVec2(x0, top.y), ImVec2(x1, origin.y + kCanvasHeight), colorOf(c, 0.35f));
  }
  for (size_t i = 0; i + 1 < points.size(); ++i)
    draw->AddLine(toScreen(points[i].value, points[i].rgba.a),
                  toScreen(points[i + 1].value, points[i + 1].rgba.a), IM_COL32(230, 230, 230, 255), 1.5f);
  for (size_t i = 0; i < points.size(); ++i) {
    const ImVec2 p = toScreen(points[i].value, points[i].rgba.a);
    draw->AddCircleFilled(p, kHandleRadius, colorOf(points[i].rgba));
    draw->AddCircle(p, kHandleRadius,
                    int(i) == selected_ ? IM_COL32(255, 220, 0, 255) : IM_COL32(255, 255, 255, 255), 12,
                    int(i) == selected_ ? 2.5f : 1.0f);
  }

  ImGui::InvisibleButton("##tf canvas", ImVec2(width, kCanvasHeight + kStripHeight),
                         ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  auto handleUnderMouse = [&]() {
    for (size_t i = 0; i < points.size(); ++i) {
      const ImVec2 p = toScreen(points[i].value, points[i].rgba.a);
      if (std::hypot(p.x - mouse.x, p.y - mouse.y) <= kHandleRadius + 2.0f) return int(i);
    }
    return -1;
  };
  bool changed = false;
  if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    selected_ = handleUnderMouse();
    if (selected_ < 0) {
      TfPoint added;
      added.value = valueAt(mouse.x);
      added.rgba = function.evaluate(added.value);
      added.rgba.a = alphaAt(mouse.y);
      const auto at = std::upper_bound(points.begin(), points.end(), added.value,
                                       [](double v, const TfPoint& p) { return v < p.value; });
      selected_ = int(points.insert(at, added) - points.begin());
      changed = true;
    }
    dragging_ = true;
  }
  if (dragging_ && ImGui::IsMouseDown(ImGuiMouseButton_Left) && selected_ >= 0 &&
      (ImGui::GetIO().MouseDelta.x != 0.0f || ImGui::GetIO().MouseDelta.y != 0.0f)) {
    // A point moves between its neighbours, so the points stay sorted.
    const double below = selected_ > 0 ? points[selected_ - 1].value : lo;
    const double above = selected_ + 1 < int(points.size()) ? points[selected_ + 1].value : hi;
    points[selected_].value = std::clamp(valueAt(mouse.x), below, above);
    points[selected_].rgba.a = alphaAt(mouse.y);
    changed = true;
  }
  if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) dragging_ = false;
  if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Right) && points.size() > 1) {
    if (const int i = handleUnderMouse(); i >= 0) {
      points.erase(points.begin() + i);
      selected_ = -1;
      changed = true;
    }
  }

  if (selected_ >= int(points.size())) selected_ = -1;
  if (selected_ >= 0) {
    TfPoint& p = points[selected_];
    float rgb[3] = {float(p.rgba.r), float(p.rgba.g), float(p.rgba.b)};
    if (ImGui::ColorEdit3("color", rgb)) {
      p.rgba.r = rgb[0];
      p.rgba.g = rgb[1];
      p.rgba.b = rgb[2];
      changed = true;
    }
    float alpha = float(p.rgba.a);
    if (ImGui::SliderFloat("opacity", &alpha, 0.0f, 1.0f, "%.3f", ImGuiSliderFlags_Logarithmic)) {
      p.rgba.a = alpha;
      changed = true;
    }
    ImGui::Text("value %.4g", p.value);
  } else {
    ImGui::TextDisabled("click: add, drag: move, right click: delete");
  }
  return changed;
}

}  // namespace ropecast::tools
