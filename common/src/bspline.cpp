#include "plumage/common/bspline.h"

#include <algorithm>
#include <string>

#include "plumage/common/error.h"
#include "plumage/common/finite.h"

namespace plumage {
namespace {

// Non-finite control points, or ones whose squared distances overflow, would also
// make the adaptive integration below return NaN.
void require_valid(const BSpline3& c, const char* what) {
  if (!c.valid())
    throw Error(std::string(what) + ": a cubic B-spline needs at least 4 control points, got " +
                std::to_string(c.control_points().size()));
  const auto& p = c.control_points();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || !std::isfinite(p[i].z))
      throw Error(std::string(what) + ": control point " + std::to_string(i) +
                  " is not finite (NaN or Inf)");
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    const glm::dvec3 d = p[i + 1] - p[i];
    if (!std::isfinite(glm::dot(d, d)))
      throw Error(std::string(what) + ": control points " + std::to_string(i) + " and " +
                  std::to_string(i + 1) + " are too far apart for double precision; rescale");
  }
}

// dC/du of one segment as a quadratic in its local u, written with the control-point
// differences d_k = P_{k+1} - P_k (the derivative is a quadratic B-spline of them), so
// a large common offset of the control points cancels before any rounding.
struct SegmentDerivative {
  glm::dvec3 c0, c1, c2;  // dC/du = c0 + c1 u + c2 u^2
  glm::dvec3 at(double u) const { return c0 + u * (c1 + u * c2); }
  // Sum of |d_k|: bounds the segment's length, so it scales the tolerances.
  double polygon_length;
};

SegmentDerivative segment_derivative(const BSpline3& c, std::size_t seg) {
  const auto& p = c.control_points();
  const glm::dvec3 d0 = p[seg + 1] - p[seg], d1 = p[seg + 2] - p[seg + 1],
                   d2 = p[seg + 3] - p[seg + 2];
  return {0.5 * (d0 + d1), d1 - d0, 0.5 * d0 - d1 + 0.5 * d2,
          glm::length(d0) + glm::length(d1) + glm::length(d2)};
}

// 5-point Gauss-Legendre rule on [a,b] of |dC/du| (exact for polynomials of degree 9).
double gauss_legendre5(const SegmentDerivative& d, double a, double b) {
  static constexpr double x[5] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640,
                                  0.9061798459386640};
  static constexpr double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                  0.2369268850561891, 0.2369268850561891};
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  double sum = 0;
  for (int i = 0; i < 5; ++i) sum += w[i] * glm::length(d.at(mid + half * x[i]));
  return half * sum;
}

// Adaptive bisection: |dC/du| is smooth except where the derivative vanishes
// (coincident control points), and only those places get refined.
double adaptive_length(const SegmentDerivative& d, double a, double b, double whole, double tol,
                       int depth) {
  const double m = 0.5 * (a + b);
  const double left = gauss_legendre5(d, a, m), right = gauss_legendre5(d, m, b);
  if (depth == 0 || !std::isfinite(whole) || std::fabs(left + right - whole) <= tol)
    return left + right;
  return adaptive_length(d, a, m, left, 0.5 * tol, depth - 1) +
         adaptive_length(d, m, b, right, 0.5 * tol, depth - 1);
}

constexpr double kRelativeTolerance = 1e-11;
constexpr int kMaxDepth = 40;

// Arc length of one segment between local parameters ua <= ub.
double segment_length(const SegmentDerivative& d, double ua, double ub) {
  if (!(ub > ua) || d.polygon_length == 0) return 0;
  const double tol = kRelativeTolerance * d.polygon_length * (ub - ua);
  return adaptive_length(d, ua, ub, gauss_legendre5(d, ua, ub), tol, kMaxDepth);
}

// Real roots of a u^2 + b u + c in (0,1), with the cancellation-free form of the
// quadratic formula (q = -(b + sign(b) sqrt(disc)) / 2; roots q/a and c/q).
int roots_in_unit_interval(double a, double b, double c, double out[2]) {
  int n = 0;
  auto keep = [&](double u) {
    if (u > 0 && u < 1) out[n++] = u;
  };
  const double scale = std::fmax(std::fabs(a), std::fmax(std::fabs(b), std::fabs(c)));
  if (scale == 0) return 0;
  if (std::fabs(a) <= 1e-14 * scale) {
    if (b != 0) keep(-c / b);
    return n;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) {
    // No real root, or a double root lost to rounding: the vertex is a point of the
    // curve either way, so including it can only make the box tighter-correct.
    keep(-b / (2 * a));
    return n;
  }
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  keep(q / a);
  if (q != 0) keep(c / q);
  return n;
}

glm::dvec3 eval_segment(const BSpline3& c, std::size_t seg, double u) {
  const auto b = CubicBSplineBasis::eval(u);
  const auto& p = c.control_points();
  return p[seg] * b[0] + p[seg + 1] * b[1] + p[seg + 2] * b[2] + p[seg + 3] * b[3];
}

}  // namespace

Bounds3 tight_bounds(const BSpline3& c) {
  require_valid(c, "tight_bounds");
  Bounds3 box;
  const std::size_t n = c.num_segments();
  for (std::size_t seg = 0; seg < n; ++seg) {
    box.extend(eval_segment(c, seg, 0.0));
    const SegmentDerivative d = segment_derivative(c, seg);
    for (int axis = 0; axis < 3; ++axis) {
      double u[2];
      const int k = roots_in_unit_interval(d.c2[axis], d.c1[axis], d.c0[axis], u);
      for (int i = 0; i < k; ++i) box.extend(eval_segment(c, seg, u[i]));
    }
  }
  box.extend(eval_segment(c, n - 1, 1.0));
  return box;
}

double arc_length(const BSpline3& c, double t0, double t1) {
  require_valid(c, "arc_length");
  if (t1 < t0) return -arc_length(c, t1, t0);
  std::size_t s0, s1;
  double u0, u1;
  c.locate(t0, s0, u0);
  c.locate(t1, s1, u1);
  if (s0 == s1) return segment_length(segment_derivative(c, s0), u0, u1);
  double length = segment_length(segment_derivative(c, s0), u0, 1.0);
  for (std::size_t seg = s0 + 1; seg < s1; ++seg)
    length += segment_length(segment_derivative(c, seg), 0.0, 1.0);
  return length + segment_length(segment_derivative(c, s1), 0.0, u1);
}

ArcLengthTable::ArcLengthTable(const BSpline3& c, int samples_per_segment)
    : curve_(c), samples_per_segment_(samples_per_segment) {
  require_valid(c, "ArcLengthTable");
  if (samples_per_segment < 1 || samples_per_segment > 65536)
    throw Error("ArcLengthTable: samples_per_segment must be in [1, 65536], got " +
                std::to_string(samples_per_segment));
  const std::size_t n = c.num_segments(), k = std::size_t(samples_per_segment);
  const double intervals = double(n * k);
  t_.reserve(n * k + 1);
  s_.reserve(n * k + 1);
  t_.push_back(0.0);
  s_.push_back(0.0);
  for (std::size_t seg = 0; seg < n; ++seg) {
    const SegmentDerivative d = segment_derivative(c, seg);
    for (std::size_t i = 0; i < k; ++i) {
      const double ua = double(i) / double(k), ub = double(i + 1) / double(k);
      s_.push_back(s_.back() + segment_length(d, ua, ub));
      t_.push_back(double(seg * k + i + 1) / intervals);
    }
  }
}

// Arc length from t_[interval] to t, both inside one table interval (hence one segment).
double ArcLengthTable::length_within(std::size_t interval, double t) const {
  const std::size_t seg = interval / std::size_t(samples_per_segment_);
  const double n = double(curve_.num_segments());
  return segment_length(segment_derivative(curve_, seg), t_[interval] * n - double(seg),
                        t * n - double(seg));
}

double ArcLengthTable::t_at(double s) const {
  const double total = length();
  if (!(total > 0)) return 0.0;
  s = std::clamp(std::isnan(s) ? 0.0 : s, 0.0, total);
  const std::size_t last = s_.size() - 2;
  const std::size_t i =
      std::min(std::size_t(std::upper_bound(s_.begin(), s_.end(), s) - s_.begin()) - 1, last);
  const double sa = s_[i], sb = s_[i + 1];
  if (!(sb > sa)) return t_[i];
  // Newton on f(t) = s(t) - s with f' = |C'(t)|, kept inside the bracket [lo, hi]
  // by falling back to bisection where the speed vanishes or a step leaves it.
  double lo = t_[i], hi = t_[i + 1];
  double t = lo + (hi - lo) * (s - sa) / (sb - sa);
  for (int iter = 0; iter < 60; ++iter) {
    const double f = sa + length_within(i, t) - s;
    if (std::fabs(f) <= 1e-12 * total) break;
    (f > 0 ? hi : lo) = t;
    if (!(hi > lo)) break;
    const double speed = glm::length(curve_.deriv(t));
    double next = speed > 0 ? t - f / speed : lo - 1;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    t = next;
  }
  return t;
}

double ArcLengthTable::s_at(double t) const {
  t = std::clamp(std::isnan(t) ? 0.0 : t, 0.0, 1.0);
  const std::size_t intervals = s_.size() - 1;
  const std::size_t i = std::min(std::size_t(t * double(intervals)), intervals - 1);
  return s_[i] + length_within(i, std::max(t, t_[i]));
}

// ---------------------------------------------------------------------------
// Least-squares fitting.

namespace {

// Normal equations M x = r of a least-squares problem whose rows touch at most four
// neighbouring unknowns, so M is a band matrix of half-bandwidth 3: a banded
// Cholesky factorisation solves it in O(n) (Golub & Van Loan, Matrix Computations, §4.3).
class BandedNormalEquations {
 public:
  static constexpr std::size_t kBand = 3;
  struct Term {
    std::size_t col;
    double coeff;
  };

  explicit BandedNormalEquations(std::size_t n) : m_(n), r_(n, glm::dvec3(0)) {}

  // Adds the row sqrt(weight) * (sum coeff x_col = target).
  void add_row(const std::vector<Term>& terms, const glm::dvec3& target, double weight) {
    for (const Term& a : terms) {
      r_[a.col] += weight * a.coeff * target;
      for (const Term& b : terms)
        if (b.col >= a.col) m_[a.col][b.col - a.col] += weight * a.coeff * b.coeff;
    }
  }

  double trace() const {
    double t = 0;
    for (const auto& row : m_) t += row[0];
    return t;
  }

  // Returns false when a Cholesky pivot falls below `min_pivot` times its diagonal
  // entry: M is then (numerically) singular.
  bool solve(std::vector<glm::dvec3>& x, double min_pivot) const {
    const std::size_t n = m_.size();
    // l[j][k] = L(j, j-k).
    std::vector<std::array<double, kBand + 1>> l(n, {0, 0, 0, 0});
    auto L = [&](std::size_t row, std::size_t col) -> double& { return l[row][row - col]; };
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t first = j >= kBand ? j - kBand : 0;
      for (std::size_t i = first; i <= j; ++i) {
        double s = m_[i][j - i];
        for (std::size_t p = first; p < i; ++p) s -= L(j, p) * L(i, p);
        if (i == j) {
          if (!(s > min_pivot * m_[j][0])) return false;
          L(j, j) = std::sqrt(s);
        } else {
          L(j, i) = s / L(i, i);
        }
      }
    }
    std::vector<glm::dvec3> y(n);
    for (std::size_t j = 0; j < n; ++j) {
      glm::dvec3 s = r_[j];
      for (std::size_t p = j >= kBand ? j - kBand : 0; p < j; ++p) s -= L(j, p) * y[p];
      y[j] = s / L(j, j);
    }
    x.assign(n, glm::dvec3(0));
    for (std::size_t j = n; j-- > 0;) {
      glm::dvec3 s = y[j];
      for (std::size_t p = j + 1; p < std::min(n, j + kBand + 1); ++p) s -= L(p, j) * x[p];
      x[j] = s / L(j, j);
    }
    return true;
  }

 private:
  std::vector<std::array<double, kBand + 1>> m_;  // m_[i][k] = M(i, i+k)
  std::vector<glm::dvec3> r_;
};


// Chord-length parameters (Lee, "Choosing nodes in parametric curve interpolation",
// CAD 1989): t_j proportional to the polyline length up to point j. Uniform when
// the points do not spread out (all coincident) or the length overflows.
std::vector<double> chord_length_params(std::span<const glm::dvec3> p) {
  std::vector<double> t(p.size(), 0.0);
  for (std::size_t j = 1; j < p.size(); ++j) t[j] = t[j - 1] + glm::length(p[j] - p[j - 1]);
  const double total = t.back();
  for (std::size_t j = 0; j < p.size(); ++j)
    t[j] = total > 0 && std::isfinite(total) ? t[j] / total : double(j) / double(p.size() - 1);
  t.back() = 1.0;
  return t;
}

}  // namespace

BSpline3 fit_bspline(std::span<const glm::dvec3> points, int num_control_points,
                     std::span<const double> params, bool clamp_ends) {
  if (num_control_points < 4)
    throw Error("fit_bspline: a cubic B-spline needs at least 4 control points, asked for " +
                std::to_string(num_control_points));
  const std::size_t n = std::size_t(num_control_points), m = points.size();
  if (m < n)
    throw Error("fit_bspline: " + std::to_string(m) + " points cannot determine " +
                std::to_string(n) + " control points; give at least " + std::to_string(n) +
                " points or ask for fewer control points");
  if (!params.empty() && params.size() != m)
    throw Error("fit_bspline: " + std::to_string(params.size()) + " parameters for " +
                std::to_string(m) + " points; give one parameter per point or none");
  for (std::size_t j = 0; j < m; ++j)
    if (!all_finite(points[j]))
      throw Error("fit_bspline: point " + std::to_string(j) +
                  " is not finite (NaN or Inf); remove it");
  for (std::size_t j = 0; j < params.size(); ++j)
    if (!(params[j] >= 0.0 && params[j] <= 1.0))
      throw Error("fit_bspline: parameter " + std::to_string(j) + " (" + std::to_string(params[j]) +
                  ") is outside [0,1]");

  // Solve in coordinates centred on the first point and scaled to about unit size,
  // so huge offsets and tiny or huge feathers are all conditioned alike.
  const glm::dvec3 origin = points[0];
  double scale = 0;
  for (const glm::dvec3& p : points) {
    const glm::dvec3 d = glm::abs(p - origin);
    scale = std::fmax(scale, std::fmax(d.x, std::fmax(d.y, d.z)));
  }
  if (!std::isfinite(scale))
    throw Error("fit_bspline: the points span more than a double can hold; rescale them");
  if (scale == 0) scale = 1;
  std::vector<glm::dvec3> q(m);
  for (std::size_t j = 0; j < m; ++j) q[j] = (points[j] - origin) / scale;

  const std::vector<double> t =
      params.empty() ? chord_length_params(q) : std::vector<double>(params.begin(), params.end());

  // With clamp_ends, C(0) = (x0 + 4 x1 + x2)/6 = first point and likewise at t = 1:
  // substituting x0 and x_{n-1} keeps the problem an unconstrained, banded one in
  // the inner control points.
  const std::size_t num_free = clamp_ends ? n - 2 : n;
  const glm::dvec3 first = q.front(), last = q.back();
  auto add_term = [&](std::vector<BandedNormalEquations::Term>& terms, glm::dvec3& constant,
                      std::size_t cp, double w) {
    auto add = [&](std::size_t col, double coeff) {
      for (auto& term : terms)
        if (term.col == col) {
          term.coeff += coeff;
          return;
        }
      terms.push_back({col, coeff});
    };
    if (!clamp_ends) return add(cp, w);
    if (cp == 0) {
      constant += 6.0 * w * first;
      add(0, -4 * w);  // x1
      add(1, -w);      // x2
    } else if (cp == n - 1) {
      constant += 6.0 * w * last;
      add(n - 3, -4 * w);  // x_{n-2}
      add(n - 4, -w);      // x_{n-3}
    } else {
      add(cp - 1, w);
    }
  };

  BandedNormalEquations eq(num_free);
  const BSpline3 shape{std::vector<glm::dvec3>(n)};
  std::vector<BandedNormalEquations::Term> terms;
  for (std::size_t j = 0; j < m; ++j) {
    std::size_t seg;
    double u;
    shape.locate(t[j], seg, u);
    const auto b = CubicBSplineBasis::eval(u);
    terms.clear();
    glm::dvec3 constant(0);
    for (std::size_t k = 0; k < 4; ++k) add_term(terms, constant, seg + k, b[k]);
    eq.add_row(terms, q[j] - constant, 1.0);
  }
  // Plain least squares when the points determine every control point; otherwise
  // (duplicates, clustered parameters: Schoenberg-Whitney fails) a small
  // second-difference penalty, as in the P-splines of Eilers & Marx (Stat. Sci.
  // 1996), lets the undetermined control points follow their neighbours smoothly.
  std::vector<glm::dvec3> x;
  if (!eq.solve(x, 1e-10)) {
    // Relative to the data's weight; the data may carry none at all (every point at
    // a clamped end), and then the penalty alone shapes the inner control points.
    double lambda = 1e-6 * eq.trace() / double(num_free);
    if (!(lambda > 1e-12)) lambda = 1.0;
    for (std::size_t i = 0; i + 2 < n; ++i) {
      terms.clear();
      glm::dvec3 constant(0);
      add_term(terms, constant, i, 1.0);
      add_term(terms, constant, i + 1, -2.0);
      add_term(terms, constant, i + 2, 1.0);
      eq.add_row(terms, -constant, lambda);
    }
    if (!eq.solve(x, 1e-14))
      throw Error(
          "fit_bspline: the points do not determine a curve (all at one parameter?); "
          "spread them out or use fewer control points");
  }
  std::vector<glm::dvec3> cp(n);
  if (clamp_ends) {
    for (std::size_t i = 1; i + 1 < n; ++i) cp[i] = x[i - 1];
    cp[0] = 6.0 * first - 4.0 * cp[1] - cp[2];
    cp[n - 1] = 6.0 * last - 4.0 * cp[n - 2] - cp[n - 3];
  } else {
    cp = std::move(x);
  }
  for (glm::dvec3& p : cp) {
    p = origin + scale * p;
    if (!all_finite(p)) throw Error("fit_bspline: the fit diverged (non-finite control point)");
  }
  return BSpline3(std::move(cp));
}

BSpline3 fit_bspline_penalised(std::span<const glm::dvec3> points, std::span<const double> params,
                               std::span<const double> weights, int num_control_points, int order,
                               double lambda) {
  const char* fn = "fit_bspline_penalised: ";
  if (num_control_points < 4)
    throw Error(std::string(fn) + "a cubic B-spline needs at least 4 control points, asked for " +
                std::to_string(num_control_points));
  if (order < 1 || order > int(BandedNormalEquations::kBand))
    throw Error(std::string(fn) + "the penalty's order must be 1 to 3, not " + std::to_string(order));
  if (!(lambda >= 0 && std::isfinite(lambda)))
    throw Error(std::string(fn) + "the penalty's weight must be finite and >= 0");
  const std::size_t n = std::size_t(num_control_points), m = points.size();
  if (params.size() != m || weights.size() != m)
    throw Error(std::string(fn) + "give one parameter and one weight per point");
  for (std::size_t j = 0; j < m; ++j) {
    if (!all_finite(points[j])) throw Error(std::string(fn) + "point " + std::to_string(j) + " is not finite");
    if (!(params[j] >= 0.0 && params[j] <= 1.0))
      throw Error(std::string(fn) + "parameter " + std::to_string(j) + " is outside [0,1]");
    if (!(weights[j] >= 0.0 && std::isfinite(weights[j])))
      throw Error(std::string(fn) + "weight " + std::to_string(j) + " must be finite and >= 0");
  }
  // Centred on the weighted mean and scaled to about unit size, as fit_bspline.
  glm::dvec3 origin(0);
  double total = 0;
  for (std::size_t j = 0; j < m; ++j) origin += weights[j] * points[j], total += weights[j];
  if (!(total > 0)) throw Error(std::string(fn) + "every weight is 0");
  origin /= total;
  double scale = 0;  // over the weighted points: those of weight 0 change nothing
  for (std::size_t j = 0; j < m; ++j) {
    if (weights[j] == 0) continue;
    const glm::dvec3 d = glm::abs(points[j] - origin);
    scale = std::fmax(scale, std::fmax(d.x, std::fmax(d.y, d.z)));
  }
  if (!std::isfinite(scale)) throw Error(std::string(fn) + "the points span more than a double can hold");
  if (scale == 0) scale = 1;

  BandedNormalEquations eq(n);
  const BSpline3 shape{std::vector<glm::dvec3>(n)};
  std::vector<BandedNormalEquations::Term> terms;
  for (std::size_t j = 0; j < m; ++j) {
    if (weights[j] == 0) continue;
    std::size_t seg;
    double u;
    shape.locate(params[j], seg, u);
    const auto b = CubicBSplineBasis::eval(u);
    terms.clear();
    for (std::size_t k = 0; k < 4; ++k) terms.push_back({seg + k, b[k]});
    eq.add_row(terms, (points[j] - origin) / scale, weights[j]);
  }
  // The order-th difference: binomial coefficients with alternating signs.
  std::vector<double> diff{1.0};
  for (int k = 0; k < order; ++k) {
    std::vector<double> next(diff.size() + 1, 0.0);
    for (std::size_t i = 0; i < diff.size(); ++i) next[i] -= diff[i], next[i + 1] += diff[i];
    diff = std::move(next);
  }
  if (lambda > 0)
    for (std::size_t i = 0; i + order < n; ++i) {
      terms.clear();
      for (std::size_t k = 0; k < diff.size(); ++k) terms.push_back({i + k, diff[k]});
      eq.add_row(terms, glm::dvec3(0), lambda);
    }
  std::vector<glm::dvec3> x;
  if (!eq.solve(x, 1e-13))
    throw Error(std::string(fn) + "the weighted points do not determine a curve; give weight to more points");
  for (glm::dvec3& p : x) {
    p = origin + scale * p;
    if (!all_finite(p)) throw Error(std::string(fn) + "the fit diverged (non-finite control point)");
  }
  return BSpline3(std::move(x));
}

}  // namespace plumage
