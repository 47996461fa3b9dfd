#pragma once
// Uniform cubic B-splines: the one curve representation of Plumage (shaft, barbs,
// radii, fitted shaft centrelines). n >= 4 control points give n-3 segments; the
// global parameter t in [0,1] maps uniformly onto them, segment i covering
// [i/(n-3), (i+1)/(n-3)]. This matches Embree's RTC_GEOMETRY_TYPE_*_BSPLINE_CURVE
// segments and pbrt's / Mitsuba's "bspline" curves, so control points pass
// through to them unchanged.
//
// Segment basis (local u in [0,1], control points P0..P3 of the segment):
//   B(u) = 1/6 [ (1-u)^3, 3u^3 - 6u^2 + 4, -3u^3 + 3u^2 + 3u + 1, u^3 ]
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/bounds.h"

namespace plumage {

// The four uniform cubic B-spline basis functions and their derivatives at u.
struct CubicBSplineBasis {
  static std::array<double, 4> eval(double u) {
    const double s = 1.0 - u, u2 = u * u, u3 = u2 * u;
    return {s * s * s / 6.0, (3 * u3 - 6 * u2 + 4) / 6.0, (-3 * u3 + 3 * u2 + 3 * u + 1) / 6.0,
            u3 / 6.0};
  }
  static std::array<double, 4> deriv(double u) {
    const double s = 1.0 - u;
    return {-0.5 * s * s, 1.5 * u * u - 2 * u, -1.5 * u * u + u + 0.5, 0.5 * u * u};
  }
  static std::array<double, 4> deriv2(double u) {
    return {1.0 - u, 3 * u - 2, -3 * u + 1, u};
  }
};

// T is float, double, or a glm vector (vec2/vec3/vec4, float or double).
template <class T>
class CubicBSpline {
 public:
  CubicBSpline() = default;
  explicit CubicBSpline(std::vector<T> control_points) : cp_(std::move(control_points)) {}

  const std::vector<T>& control_points() const { return cp_; }
  std::vector<T>& control_points() { return cp_; }
  bool valid() const { return cp_.size() >= 4; }
  std::size_t num_segments() const { return cp_.size() >= 4 ? cp_.size() - 3 : 0; }

  // Global t in [0,1] (clamped; NaN reads as 0) -> segment index and local u in
  // [0,1]. locate/eval/deriv/deriv2/bezier_segment need valid().
  void locate(double t, std::size_t& seg, double& u) const {
    const double n = static_cast<double>(num_segments());
    const double x = std::fmin(std::fmax(t, 0.0), 1.0) * n;
    seg = static_cast<std::size_t>(std::fmin(std::floor(x), n - 1));
    u = x - static_cast<double>(seg);
  }

  T eval(double t) const { return combine(t, CubicBSplineBasis::eval, 1.0); }
  // dC/dt (global parameter), = n_segments * dC/du.
  T deriv(double t) const { return combine(t, CubicBSplineBasis::deriv, double(num_segments())); }
  // d2C/dt2 (global parameter).
  T deriv2(double t) const {
    const double n = double(num_segments());
    return combine(t, CubicBSplineBasis::deriv2, n * n);
  }

  // Bezier control points of segment `seg` (exactly the same cubic).
  std::array<T, 4> bezier_segment(std::size_t seg) const;

 private:
  template <class BasisFn>
  T combine(double t, BasisFn basis, double scale) const {
    std::size_t i;
    double u;
    locate(t, i, u);
    const auto b = basis(u);
    using S = decltype(scalar_of(cp_[0]));
    return cp_[i] * S(b[0] * scale) + cp_[i + 1] * S(b[1] * scale) +
           cp_[i + 2] * S(b[2] * scale) + cp_[i + 3] * S(b[3] * scale);
  }
  static float scalar_of(float);
  static double scalar_of(double);
  template <int N, class S, glm::qualifier Q>
  static S scalar_of(const glm::vec<N, S, Q>&);

  std::vector<T> cp_;
};

template <class T>
std::array<T, 4> CubicBSpline<T>::bezier_segment(std::size_t seg) const {
  using S = decltype(scalar_of(cp_[0]));
  const T& p0 = cp_[seg];
  const T& p1 = cp_[seg + 1];
  const T& p2 = cp_[seg + 2];
  const T& p3 = cp_[seg + 3];
  // B-spline to Bezier change of basis.
  return {(p0 + p1 * S(4) + p2) / S(6), (p1 * S(2) + p2) / S(3), (p1 + p2 * S(2)) / S(3),
          (p1 + p2 * S(4) + p3) / S(6)};
}

using BSpline3 = CubicBSpline<glm::dvec3>;
using BSpline3f = CubicBSpline<glm::vec3>;
using BSpline2 = CubicBSpline<glm::dvec2>;
using BSpline1 = CubicBSpline<double>;

// ---------------------------------------------------------------------------
// Geometry of 3D curves (bspline.cpp).

// The functions below need a valid curve (>= 4 control points) and throw
// plumage::Error otherwise.

// Tight axis-aligned bounds: endpoints plus the extrema where a coordinate's
// derivative vanishes inside a segment.
Bounds3 tight_bounds(const BSpline3& c);

// Arc length between global parameters t0 and t1 (clamped to [0,1]; negative when
// t1 < t0). Gauss-Legendre per segment, adaptive to a relative tolerance of about 1e-9.
double arc_length(const BSpline3& c, double t0 = 0.0, double t1 = 1.0);

// Arc-length reparameterisation: a table built once, then t(s) for s in [0, L].
// The table keeps its own copy of the curve, so it stays valid after the curve
// it was built from changes or goes away.
class ArcLengthTable {
 public:
  explicit ArcLengthTable(const BSpline3& c, int samples_per_segment = 32);
  double length() const { return s_.empty() ? 0.0 : s_.back(); }
  // Global parameter t at arc length s (clamped to [0, length]); refined with
  // Newton steps so |arc_length(0,t) - s| < 1e-9 * length. A curve of zero
  // length gives t = 0.
  double t_at(double s) const;
  // Arc length from t=0 to t (t clamped to [0,1]).
  double s_at(double t) const;
  const BSpline3& curve() const { return curve_; }

 private:
  double length_within(std::size_t interval, double t) const;
  BSpline3 curve_;
  int samples_per_segment_;
  std::vector<double> t_, s_;
};

// Least-squares fit of a uniform cubic B-spline with `num_control_points` (>= 4)
// control points through `points`, at parameters `params` in [0,1] (chord-length
// parameters when `params` is empty). With `clamp_ends`, the curve passes exactly
// through the first and last point. Throws plumage::Error on fewer points than
// control points, fewer than 4 control points, non-finite points or parameters,
// parameters outside [0,1], or `params` of the wrong size. Points that leave some
// control points undetermined (duplicates, clustered parameters) still give a
// finite curve: those control points follow their neighbours smoothly.
BSpline3 fit_bspline(std::span<const glm::dvec3> points, int num_control_points,
                     std::span<const double> params = {}, bool clamp_ends = true);

// Penalised weighted least squares (the P-splines of Eilers & Marx, "Flexible
// smoothing with B-splines and penalties", Stat. Sci. 1996): the uniform cubic
// B-spline with `num_control_points` (>= 4) control points c minimising
//   sum_j weights[j] |C(params[j]) - points[j]|^2 + lambda sum_i |D^order c_i|^2
// where D^order is the order-th difference of consecutive control points
// (order 1..3). Curves whose control points are a polynomial of degree < order
// in their index cost nothing: with order 3, parabolas are free and a bend in
// an S is paid for, so where the weights are small the curve goes on as a
// parabola. Weights >= 0, params in [0,1]; throws plumage::Error on bad input
// or when the weighted points and the penalty leave the curve undetermined.
BSpline3 fit_bspline_penalised(std::span<const glm::dvec3> points, std::span<const double> params,
                               std::span<const double> weights, int num_control_points, int order,
                               double lambda);

// Control points of a uniform cubic B-spline that starts exactly at `points.front()`
// and ends exactly at `points.back()` and passes near the interior points: the
// interior points are taken as control points and a phantom point is added at each
// end (P_-1 = 2 P_0 - P_1), which makes the curve interpolate the end points.
// Needs at least 2 points (4 for the result to be a valid curve).
template <class T>
std::vector<T> with_phantom_ends(const std::vector<T>& points) {
  std::vector<T> cp;
  cp.reserve(points.size() + 2);
  const auto n = points.size();
  cp.push_back(points[0] + (points[0] - points[1]));
  cp.insert(cp.end(), points.begin(), points.end());
  cp.push_back(points[n - 1] + (points[n - 1] - points[n - 2]));
  return cp;
}

}  // namespace plumage
