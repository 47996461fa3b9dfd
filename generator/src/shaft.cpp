#include "shaft.h"

#include <algorithm>
#include <cmath>

#include "plumage/common/constants.h"
#include "plumage/common/frame.h"

namespace plumage {

namespace {

// Centreline with constant turning rates: the tangent turns by bend_deg in the
// XY plane and by arch_deg toward -Z over the whole length. Sampled at
// control_points points, with phantom ends so the curve runs from base to tip.
BSpline3 centreline(const ShaftParams& p) {
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
  return BSpline3(with_phantom_ends(pts));
}

}  // namespace

Shaft::Shaft(const ShaftParams& p) : table_(centreline(p)) {}

Shaft::Frame Shaft::frame(double s, double twist_rad) const {
  const double t = t_at(s);
  Frame f;
  f.p = curve().eval(t);
  const glm::dvec3 d = curve().deriv(t);
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
