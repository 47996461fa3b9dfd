#include "plumage/generator/shaft_pose.h"

#include <cmath>
#include <limits>
#include <vector>

#include "plumage/common/error.h"

namespace plumage {

namespace {

constexpr int kSamples = 1024;  // polyline samples per shaft: chords under 0.1 % of its length

// A shaft as a dense polyline with its cumulative arc length.
struct Polyline {
  std::vector<glm::dvec2> p;
  std::vector<double> s;  // arc length at p[i]
  double length() const { return s.back(); }
  glm::dvec2 tangent(std::size_t i) const { return glm::normalize(p[i + 1] - p[i]); }
};

template <class Eval>
Polyline sample(Eval eval, const char* what) {
  Polyline L;
  for (int i = 0; i <= kSamples; ++i) {
    L.p.push_back(eval(double(i) / kSamples));
    L.s.push_back(i == 0 ? 0.0 : L.s.back() + glm::length(L.p[i] - L.p[i - 1]));
  }
  // A chord of zero length has no tangent: drop repeated samples.
  Polyline out;
  for (std::size_t i = 0; i < L.p.size(); ++i)
    if (out.p.empty() || L.s[i] > out.s.back() + 1e-12) out.p.push_back(L.p[i]), out.s.push_back(L.s[i]);
  if (out.p.size() < 2 || !(out.length() > 0) || !std::isfinite(out.length()))
    throw Error(std::string("the ") + what + " has no length");
  return out;
}

// Lateral unit vector: toward the right vane (+X when the shaft runs +Y).
glm::dvec2 lateral(const glm::dvec2& t) { return {t.y, -t.x}; }

// (arc length along, signed lateral offset, chord index) of q against the polyline;
// the end chords extend past the ends.
struct Along {
  double s, d;
  std::size_t i;
};
Along project(const Polyline& L, const glm::dvec2& q) {
  const std::size_t n = L.p.size() - 1;
  const auto on_chord = [&](std::size_t i, double* d2) {
    const glm::dvec2 a = L.p[i], ab = L.p[i + 1] - a;
    double t = glm::dot(q - a, ab) / glm::dot(ab, ab);
    if (i > 0) t = std::max(t, 0.0);
    if (i + 1 < n) t = std::min(t, 1.0);
    const glm::dvec2 on = a + t * ab;
    *d2 = glm::dot(q - on, q - on);
    return t;
  };
  // The nearest of every kStride-th chord first, then every chord around it: the
  // distance along a shaft whose radius of curvature is far above L / kSamples *
  // kStride has one minimum near a point beside it.
  constexpr std::size_t kStride = 16;
  std::size_t coarse = 0;
  double best_d2 = std::numeric_limits<double>::infinity(), d2 = 0;
  for (std::size_t i = 0; i < n; i += kStride) {
    on_chord(i, &d2);
    if (d2 < best_d2) best_d2 = d2, coarse = i;
  }
  if (n - 1 > coarse) {
    on_chord(n - 1, &d2);
    if (d2 < best_d2) best_d2 = d2, coarse = n - 1;
  }
  Along best{0, 0, 0};
  best_d2 = std::numeric_limits<double>::infinity();
  const std::size_t lo = coarse > 2 * kStride ? coarse - 2 * kStride : 0, hi = std::min(n, coarse + 2 * kStride + 1);
  for (std::size_t i = lo; i < hi; ++i) {
    const double t = on_chord(i, &d2);
    if (d2 < best_d2) {
      best_d2 = d2;
      const glm::dvec2 on = L.p[i] + t * (L.p[i + 1] - L.p[i]);
      best = {L.s[i] + t * (L.s[i + 1] - L.s[i]), glm::dot(q - on, lateral(L.tangent(i))), i};
    }
  }
  return best;
}

// The chord holding arc length s (the first or last one beyond the ends).
std::size_t chord_at(const Polyline& L, double s) {
  std::size_t lo = 0, hi = L.p.size() - 2;
  while (lo < hi) {
    const std::size_t mid = (lo + hi + 1) / 2;
    if (L.s[mid] <= s) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

}  // namespace

void lay_along_shaft(Feather& feather, const BSpline2& shaft_mm) {
  const Curve* shaft = feather.shaft();
  if (!shaft || shaft->points.size() < 4) throw Error("the feather has no shaft curve");
  if (!shaft_mm.valid()) throw Error("the measured shaft needs at least 4 control points");
  BSpline3 built3;
  for (const ControlPoint& cp : shaft->points) built3.control_points().push_back(glm::dvec3(cp.p));
  const Polyline from = sample([&](double t) { return glm::dvec2(built3.eval(t)); }, "built shaft");
  const Polyline to = sample([&](double t) { return shaft_mm.eval(t); }, "measured shaft");
  const double scale = to.length() / from.length();
  for (Curve& c : feather.curves)
    for (ControlPoint& cp : c.points) {
      const Along a = project(from, glm::dvec2(cp.p));
      const double s = a.s * scale;
      const std::size_t j = chord_at(to, s);
      const glm::dvec2 tj = to.tangent(j), ti = from.tangent(a.i);
      const glm::dvec2 on = to.p[j] + (s - to.s[j]) * tj;
      const glm::dvec2 q = on + a.d * lateral(tj);
      // The turn from the built tangent to the measured one, applied to the normal.
      const double cs = glm::dot(ti, tj), sn = ti.x * tj.y - ti.y * tj.x;
      const glm::dvec2 n(cp.n);
      cp.p = glm::vec3(float(q.x), float(q.y), cp.p.z);
      cp.n = glm::vec3(float(cs * n.x - sn * n.y), float(sn * n.x + cs * n.y), cp.n.z);
    }
}

}  // namespace plumage
