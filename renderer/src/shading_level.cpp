#include "plumage/renderer/shading_level.h"

#include <algorithm>
#include <vector>

namespace plumage {

float barbule_period(const Feather& feather) {
  std::vector<double> periods;
  for (const Curve& c : feather.curves) {
    if (c.kind != CurveKind::Barb) continue;
    const int n = feather.substructure(c.side).barbules_per_side;
    if (n <= 0) continue;
    double length = 0;
    for (std::size_t i = 1; i < c.points.size(); ++i) length += double(glm::length(c.points[i].p - c.points[i - 1].p));
    periods.push_back(length / n);
  }
  if (periods.empty()) return 0;
  const auto mid = periods.begin() + std::ptrdiff_t(periods.size() / 2);
  std::nth_element(periods.begin(), mid, periods.end());
  return float(*mid);
}

ShadingMode shading_for_footprint(float footprint, float period) {
  return period > 0 && !(footprint < period) ? ShadingMode::Farfield : ShadingMode::Substructure;
}

ShadingMode shading_by_footprint(const Feather& feather, float scale, const Bounds3f& box, const Camera& camera) {
  return shading_for_footprint(camera.pixel_footprint(box), scale * barbule_period(feather));
}

}  // namespace plumage
