#pragma once
// Where the overlay's text labels go so that none covers another: on a dense
// sheet (dozens of feathers a few label heights apart) labels put at each
// feather's tip pile up and cannot be read. Free of OpenCV so that it can be
// tested on its own.
#include <utility>
#include <vector>

namespace plumage::analysis {

// An axis-aligned box in image pixels: top-left corner, width and height.
struct LabelBox {
  int x = 0, y = 0, width = 0, height = 0;
};

// Area (pixels) two boxes share; 0 when they only touch.
long overlap_area(const LabelBox& a, const LabelBox& b);

// Greedy placement in call order: each label takes the first of its candidate
// positions whose box, moved inside the image, covers nothing placed or reserved
// before it; when every candidate covers something, the one covering the least
// area (the earliest of equals). Deterministic for the same calls.
class LabelPlacer {
 public:
  LabelPlacer(int image_width, int image_height);

  // Keeps labels off a box that is drawn anyway (the scale bar).
  void reserve(const LabelBox& box);

  // A width x height label whose top-left corner wants to be at one of
  // `candidates` (tried in order; at least one). Returns the box it takes.
  LabelBox place(int width, int height, const std::vector<std::pair<int, int>>& candidates);

 private:
  LabelBox inside(LabelBox b) const;

  int image_width_, image_height_;
  std::vector<LabelBox> taken_;
};

}  // namespace plumage::analysis
