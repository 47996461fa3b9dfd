#include "plumage/renderer/ribbon_layers.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/bspline.h"
#include "plumage/common/interrupt.h"

namespace plumage {

RibbonLayers::RibbonLayers(const Feather& feather) {
  glm::vec2 lo(1e30f), hi(-1e30f);
  float thinnest = 1e30f;
  for (const Curve& c : feather.curves) {
    if (c.kind != CurveKind::Barb) continue;
    const std::vector<float> radii = render_radii(feather, c);
    for (std::size_t k = 0; k < c.points.size(); ++k) {
      const ControlPoint& cp = c.points[k];
      const float r = radii[k];
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
  std::vector<glm::vec2> q;
  std::vector<float> r;
  for (const Curve& c : feather.curves) {
    if (c.kind != CurveKind::Barb) continue;
    check_interrupted();  // a few seconds for a large feather (more under a sanitizer): stop here on a signal
    ++id;
    // The barb as a polyline of points about a radius apart, each piece a capsule
    // (a B-spline segment bends little over one radius).
    q.clear(), r.clear();
    const std::vector<float> radii = render_radii(feather, c);
    for (std::size_t s = 0; s + 3 < c.points.size(); ++s) {
      const ControlPoint* cp = &c.points[s];
      float rc[4], polygon = 0, rmin = 1e30f;
      for (int i = 0; i < 4; ++i) {
        rc[i] = radii[s + i];
        rmin = std::min(rmin, rc[i]);
        if (i > 0) polygon += glm::length(glm::vec2(cp[i].p - cp[i - 1].p));
      }
      const int steps = std::max(1, int(std::ceil(polygon / std::max(rmin, cell_))));
      for (int k = s == 0 ? 0 : 1; k <= steps; ++k) {
        const auto b = CubicBSplineBasis::eval(double(k) / steps);
        glm::vec2 p(0);
        float rp = 0;
        for (int i = 0; i < 4; ++i) p += float(b[i]) * glm::vec2(cp[i].p), rp += float(b[i]) * rc[i];
        q.push_back(p), r.push_back(rp);
      }
    }
    for (std::size_t k = 0; k + 1 < q.size(); ++k) {
      const glm::vec2 a = q[k], ab = q[k + 1] - a;
      const float rr = std::max(r[k], r[k + 1]), len2 = glm::dot(ab, ab);
      const glm::vec2 lo_c = (glm::min(a, q[k + 1]) - rr - origin_) / cell_;
      const glm::vec2 hi_c = (glm::max(a, q[k + 1]) + rr - origin_) / cell_;
      const int x0 = std::max(0, int(lo_c.x)), x1 = std::min(nx_ - 1, int(hi_c.x));
      const int y0 = std::max(0, int(lo_c.y)), y1 = std::min(ny_ - 1, int(hi_c.y));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const std::size_t i = std::size_t(y) * std::size_t(nx_) + std::size_t(x);
          if (last[i] == id) continue;
          const glm::vec2 d = origin_ + cell_ * (glm::vec2(float(x), float(y)) + 0.5f) - a;
          const float t = len2 > 0 ? std::clamp(glm::dot(d, ab) / len2, 0.0f, 1.0f) : 0.0f;
          const glm::vec2 e = d - t * ab;
          if (glm::dot(e, e) > rr * rr) continue;
          last[i] = id;
          if (count_[i] < 255) ++count_[i];
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
