#include "shaft.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/frame.h"

namespace plumage {

namespace {
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
constexpr int kTableSamplesPerSegment = 64;
}  // namespace

Shaft::Shaft(const ShaftParams& p) {
  // Centreline with constant turning rates: the tangent turns by bend_deg in the
  // XY plane and by arch_deg toward -Z over the whole length.
  const int m = p.control_points;
  const int sub = 32;
  std::vector<glm::dvec3> pts(m);
  const double ds = p.length / ((m - 1) * sub);
  glm::dvec3 x(0);
  pts[0] = x;
  for (int i = 1; i < m; ++i) {
    for (int k = 0; k < sub; ++k) {
      const double s = ((i - 1) * sub + k + 0.5) * ds;  // midpoint rule
      const double phi = p.bend_deg * kDegToRad * s / p.length, psi = p.arch_deg * kDegToRad * s / p.length;
      x += ds * glm::dvec3(std::sin(phi) * std::cos(psi), std::cos(phi) * std::cos(psi), -std::sin(psi));
    }
    pts[i] = x;
  }
  curve_ = BSpline3(with_phantom_ends(pts));

  // Arc-length table by Simpson's rule on each small step.
  const int n = int(curve_.num_segments()) * kTableSamplesPerSegment;
  t_.resize(n + 1);
  s_.resize(n + 1);
  s_[0] = 0;
  for (int i = 0; i <= n; ++i) t_[i] = double(i) / n;
  for (int i = 1; i <= n; ++i) {
    const double a = t_[i - 1], b = t_[i];
    s_[i] = s_[i - 1] + (b - a) / 6 *
                            (glm::length(curve_.deriv(a)) + 4 * glm::length(curve_.deriv(0.5 * (a + b))) +
                             glm::length(curve_.deriv(b)));
  }
}

double Shaft::t_at(double s) const {
  s = std::clamp(s, 0.0, length());
  const auto it = std::lower_bound(s_.begin(), s_.end(), s);
  const std::size_t i = std::clamp<std::size_t>(std::size_t(it - s_.begin()), 1, s_.size() - 1);
  const double f = (s - s_[i - 1]) / std::max(s_[i] - s_[i - 1], 1e-300);
  double t = t_[i - 1] + f * (t_[i] - t_[i - 1]);
  // One Newton step on the local speed removes the linear-interpolation error.
  const double speed = glm::length(curve_.deriv(t));
  if (speed > 0) {
    const double a = t_[i - 1], sa = s_[i - 1];
    const double local = (t - a) / 6 *
                         (glm::length(curve_.deriv(a)) + 4 * glm::length(curve_.deriv(0.5 * (a + t))) + speed);
    t = std::clamp(t - (sa + local - s) / speed, 0.0, 1.0);
  }
  return t;
}

Shaft::Frame Shaft::frame(double s, double twist_rad) const {
  const double t = t_at(s);
  Frame f;
  f.p = curve_.eval(t);
  const glm::dvec3 d = curve_.deriv(t);
  f.t = glm::length(d) > 0 ? glm::normalize(d) : glm::dvec3(0, 1, 0);
  glm::dvec3 lat = glm::cross(f.t, glm::dvec3(0, 0, 1));
  lat = glm::length(lat) > 1e-12 ? glm::normalize(lat) : glm::dvec3(1, 0, 0);
  const glm::dvec3 dor = glm::cross(lat, f.t);
  const double c = std::cos(twist_rad), sn = std::sin(twist_rad);
  f.lateral = c * lat + sn * dor;
  f.dorsal = -sn * lat + c * dor;
  return f;
}

}  // namespace plumage
