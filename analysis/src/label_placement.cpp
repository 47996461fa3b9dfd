#include "label_placement.h"

#include <algorithm>
#include <limits>

namespace plumage::analysis {

long overlap_area(const LabelBox& a, const LabelBox& b) {
  const long w = std::min(long(a.x) + a.width, long(b.x) + b.width) - std::max(a.x, b.x);
  const long h = std::min(long(a.y) + a.height, long(b.y) + b.height) - std::max(a.y, b.y);
  return w > 0 && h > 0 ? w * h : 0;
}

LabelPlacer::LabelPlacer(int image_width, int image_height)
    : image_width_(std::max(0, image_width)), image_height_(std::max(0, image_height)) {}

void LabelPlacer::reserve(const LabelBox& box) { taken_.push_back(box); }

LabelBox LabelPlacer::inside(LabelBox b) const {
  // A label wider or taller than the image keeps its top-left corner at 0.
  b.x = std::clamp(b.x, 0, std::max(0, image_width_ - b.width));
  b.y = std::clamp(b.y, 0, std::max(0, image_height_ - b.height));
  return b;
}

LabelBox LabelPlacer::place(int width, int height, const std::vector<std::pair<int, int>>& candidates) {
  LabelBox best{0, 0, std::max(0, width), std::max(0, height)};
  long least = std::numeric_limits<long>::max();
  for (const auto& [x, y] : candidates) {
    const LabelBox b = inside(LabelBox{x, y, best.width, best.height});
    long covered = 0;
    for (const LabelBox& t : taken_) covered += overlap_area(b, t);
    if (covered < least) least = covered, best = b;
    if (covered == 0) break;
  }
  if (candidates.empty()) best = inside(best);
  taken_.push_back(best);
  return best;
}

}  // namespace plumage::analysis
