#include "plumage/renderer/ribbon_layers.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/bspline.h"

namespace plumage {

RibbonLayers::RibbonLayers(const Feather& feather) {
  glm::vec2 lo(1e30f), hi(-1e30f);
  float thinnest = 1e30f;
  for (const Curve& c : feather.curves) {
    if (c.kind != CurveKind::Barb) continue;
    for (const ControlPoint& cp : c.points) {
      const float r = render_radius(feather, c, cp);
      lo = glm::min(lo, glm::vec2(cp.p) - r);
      hi = glm::max(hi, glm::vec2(cp.p) + r);
      if (r > 0) thinnest = std::min(thinnest, r);
    }
  }
  if (!(hi.x > lo.x && hi.y > lo.y) || !(thinnest < 1e30f)) return;
  const glm::vec2 size = hi - lo;
  cell_ = std::max(0.25f * thinnest, std::sqrt(size.x * size.y / float(kMaxCells)));
  nx_ = int(std::ceil(size.x / cell_)) + 1;
  ny_ = int(std::ceil(size.y / cell_)) + 1;
  origin_ = lo;
  count_.assign(std::size_t(nx_) * std::size_t(ny_), 0);
  // Which barb last counted a cell, so a barb counts each cell once.
  std::vector<std::uint32_t> last(count_.size(), 0);
  std::uint32_t id = 0;
  for (const Curve& c : feather.curves) {
    if (c.kind != CurveKind::Barb) continue;
    ++id;
    const std::size_t n = c.points.size();
    for (std::size_t s = 0; s + 3 < n; ++s) {
      const ControlPoint* cp = &c.points[s];
      // Samples half a cell apart along the segment (its control polygon bounds its length).
      float polygon = 0;
      for (int i = 0; i < 3; ++i) polygon += glm::length(glm::vec2(cp[i + 1].p - cp[i].p));
      const int steps = std::max(1, int(std::ceil(polygon / (0.5f * cell_))));
      for (int k = 0; k <= steps; ++k) {
        const auto b = CubicBSplineBasis::eval(double(k) / steps);
        glm::vec2 q(0);
        float r = 0;
        for (int i = 0; i < 4; ++i) {
          q += float(b[i]) * glm::vec2(cp[i].p);
          r += float(b[i]) * render_radius(feather, c, cp[i]);
        }
        const glm::vec2 g = (q - origin_) / cell_;
        const int reach = int(std::ceil(r / cell_));
        const int x0 = std::max(0, int(g.x) - reach), x1 = std::min(nx_ - 1, int(g.x) + reach);
        const int y0 = std::max(0, int(g.y) - reach), y1 = std::min(ny_ - 1, int(g.y) + reach);
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) {
            const glm::vec2 centre = origin_ + cell_ * (glm::vec2(float(x), float(y)) + 0.5f);
            const glm::vec2 d = centre - q;
            if (glm::dot(d, d) > r * r) continue;
            const std::size_t i = std::size_t(y) * std::size_t(nx_) + std::size_t(x);
            if (last[i] == id) continue;
            last[i] = id;
            if (count_[i] < 255) ++count_[i];
          }
      }
    }
  }
}

int RibbonLayers::at(const glm::vec2& xy) const {
  if (count_.empty() || !std::isfinite(xy.x) || !std::isfinite(xy.y)) return 1;
  const glm::vec2 g = (xy - origin_) / cell_;
  if (!(g.x >= 0 && g.y >= 0 && g.x < float(nx_) && g.y < float(ny_))) return 1;
  return std::max(1, int(count_[std::size_t(int(g.y)) * std::size_t(nx_) + std::size_t(int(g.x))]));
}

}  // namespace plumage
