// TfEditor: the viewer's transfer-function editor, a Dear ImGui widget over the control points of
// core/transfer_function.h: value (data units) across, opacity up (square-root axis, so the small per-voxel
// opacities DVR uses stay visible), the function's color strip beneath. Left click on empty space adds a
// point with the function's color there, left drag moves one (between its neighbours), right click deletes
// one (the last stays); the selected point's color and opacity have their own fields.
//
// Main thread, between ImGui::NewFrame and ImGui::Render.
#pragma once

#include <vector>

#include "core/transfer_function.h"

namespace ropecast::tools {

class TfEditor {
 public:
  // Draws the editor for `points` over the value range [lo, hi], behind them `histogram` (bar heights in
  // [0, 1] over equal bins of [lo, hi]; empty: none); true when the user changed the points (still sorted by
  // value and non-empty, so TransferFunction accepts them).
  bool draw(std::vector<TfPoint>& points, double lo, double hi, const std::vector<float>& histogram);
  // Forgets the selection (the points were replaced).
  void deselect() { selected_ = -1; }

 private:
  int selected_ = -1;
  bool dragging_ = false;
};

}  // namespace ropecast::tools
