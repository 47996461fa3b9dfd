// Uniform cubic B-splines (bspline.h): each property is checked against a method
// that shares no code with the implementation.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "plumage/common/bspline.h"
#include "plumage/common/error.h"
#include "plumage/common/finite.h"

using namespace plumage;

namespace {

std::vector<glm::dvec3> random_points(std::mt19937& rng, std::size_t n, double scale = 1.0,
                                      glm::dvec3 offset = glm::dvec3(0)) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<glm::dvec3> p(n);
  for (auto& q : p) q = offset + scale * glm::dvec3(u(rng), u(rng), u(rng));
  return p;
}

// Cox-de Boor recursion (de Boor, "On calculating with B-splines", 1972) over the
// uniform knot vector k_i = i - 3, i = 0..n+3, whose valid span [k_3, k_n] = [0, n-3]
// is the global t in [0,1] scaled by the number of segments.
double cox_de_boor(int i, int degree, double x, int n) {
  const double ki = i - 3.0;
  if (degree == 0) {
    // Half-open spans [k_i, k_i+1), except that the last valid span (i = n-1) also
    // owns its right end.
    const int span = std::min(int(std::floor(x)), n - 4) + 3;
    return i == span ? 1.0 : 0.0;
  }
  return (x - ki) / degree * cox_de_boor(i, degree - 1, x, n) +
         (ki + degree + 1 - x) / degree * cox_de_boor(i + 1, degree - 1, x, n);
}

glm::dvec3 eval_cox_de_boor(const std::vector<glm::dvec3>& cp, double t) {
  const int n = int(cp.size());
  const double x = t * (n - 3);
  glm::dvec3 sum(0);
  for (int i = 0; i < n; ++i) sum += cox_de_boor(i, 3, x, n) * cp[i];
  return sum;
}

glm::dvec3 de_casteljau(const std::array<glm::dvec3, 4>& b, double u) {
  std::array<glm::dvec3, 4> p = b;
  for (int level = 3; level > 0; --level)
    for (int i = 0; i < level; ++i) p[i] = (1 - u) * p[i] + u * p[i + 1];
  return p[0];
}

double polyline_length(const BSpline3& c, double t0, double t1, int steps) {
  double len = 0;
  glm::dvec3 prev = c.eval(t0);
  for (int i = 1; i <= steps; ++i) {
    const glm::dvec3 p = c.eval(t0 + (t1 - t0) * i / steps);
    len += glm::length(p - prev);
    prev = p;
  }
  return len;
}

}  // namespace

TEST(BSpline, EvalMatchesCoxDeBoor) {
  std::mt19937 rng(1);
  for (int n : {4, 5, 7, 12, 30}) {
    const auto cp = random_points(rng, n);
    const BSpline3 c(cp);
    for (int i = 0; i <= 1000; ++i) {
      const double t = i / 1000.0;
      const glm::dvec3 a = c.eval(t), b = eval_cox_de_boor(cp, t);
      EXPECT_NEAR(glm::length(a - b), 0.0, 1e-12) << "n=" << n << " t=" << t;
    }
  }
}

TEST(BSpline, ScalarAndFloatInstancesAgreeWithDouble3) {
  std::mt19937 rng(2);
  const auto cp = random_points(rng, 8);
  std::vector<double> xs;
  std::vector<glm::vec3> fs;
  std::vector<glm::dvec2> ds2;
  for (const auto& p : cp) {
    xs.push_back(p.x);
    fs.push_back(glm::vec3(p));
    ds2.push_back(glm::dvec2(p));
  }
  const BSpline3 c(cp);
  const BSpline1 c1(xs);
  const BSpline3f cf(fs);
  const BSpline2 c2(ds2);
  for (int i = 0; i <= 100; ++i) {
    const double t = i / 100.0;
    EXPECT_NEAR(c1.eval(t), c.eval(t).x, 1e-14);
    EXPECT_NEAR(c2.eval(t).y, c.eval(t).y, 1e-14);
    EXPECT_NEAR(glm::length(glm::dvec3(cf.eval(t)) - c.eval(t)), 0.0, 1e-5);
  }
}

TEST(BSpline, ParameterIsClampedAndNaNSafe) {
  std::mt19937 rng(3);
  const BSpline3 c(random_points(rng, 6));
  EXPECT_EQ(c.eval(-5.0), c.eval(0.0));
  EXPECT_EQ(c.eval(7.0), c.eval(1.0));
  const glm::dvec3 p = c.eval(std::nan(""));
  EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
}

TEST(BSpline, DerivativesMatchCentralDifferences) {
  std::mt19937 rng(4);
  for (int n : {4, 6, 11}) {
    const BSpline3 c(random_points(rng, n));
    const double h = 1e-5;
    for (int i = 1; i < 200; ++i) {
      const double t = i / 200.0;
      std::size_t seg_lo, seg_hi;
      double u;
      c.locate(t - h, seg_lo, u);
      c.locate(t + h, seg_hi, u);
      // C'' jumps at segment joins, so its difference quotient is only tested inside one.
      const glm::dvec3 d1 = (c.eval(t + h) - c.eval(t - h)) / (2 * h);
      const glm::dvec3 d2 = (c.deriv(t + h) - c.deriv(t - h)) / (2 * h);
      const double scale1 = 1 + glm::length(c.deriv(t)), scale2 = 1 + glm::length(c.deriv2(t));
      EXPECT_NEAR(glm::length(c.deriv(t) - d1) / scale1, 0.0, 1e-7) << "t=" << t;
      if (seg_lo == seg_hi) {
        EXPECT_NEAR(glm::length(c.deriv2(t) - d2) / scale2, 0.0, 1e-7) << "t=" << t;
      }
      // The second difference of positions checks deriv2 without going through deriv.
      const glm::dvec3 dd = (c.eval(t + h) - 2.0 * c.eval(t) + c.eval(t - h)) / (h * h);
      if (seg_lo == seg_hi) {
        EXPECT_NEAR(glm::length(c.deriv2(t) - dd) / scale2, 0.0, 1e-3);
      }
    }
  }
}

TEST(BSpline, BezierSegmentsReproduceTheCurve) {
  std::mt19937 rng(5);
  const auto cp = random_points(rng, 9);
  const BSpline3 c(cp);
  const double n = double(c.num_segments());
  for (std::size_t seg = 0; seg < c.num_segments(); ++seg) {
    const auto b = c.bezier_segment(seg);
    for (int i = 0; i <= 50; ++i) {
      const double u = i / 50.0;
      EXPECT_NEAR(glm::length(de_casteljau(b, u) - c.eval((double(seg) + u) / n)), 0.0, 1e-13);
    }
  }
  // Adjacent Bezier segments meet: C0 continuity survives the change of basis.
  for (std::size_t seg = 0; seg + 1 < c.num_segments(); ++seg)
    EXPECT_NEAR(glm::length(c.bezier_segment(seg)[3] - c.bezier_segment(seg + 1)[0]), 0.0, 1e-14);
}

TEST(BSpline, PhantomEndsInterpolateTheEndPoints) {
  const std::vector<glm::dvec3> pts = {{0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 4, 2}};
  const BSpline3 c(with_phantom_ends(pts));
  EXPECT_EQ(c.control_points().size(), pts.size() + 2);
  EXPECT_NEAR(glm::length(c.eval(0.0) - pts.front()), 0.0, 1e-14);
  EXPECT_NEAR(glm::length(c.eval(1.0) - pts.back()), 0.0, 1e-14);
}

// --- tight bounds -----------------------------------------------------------

// Dense samples lie inside the box, and every face of the box is reached by some
// sample: the box is neither too small nor loose. At 40000 samples per segment a
// sample lies within |C''| du^2 / 8 ~ 1e-10 of any extremum.
void expect_tight(const BSpline3& c, int samples_per_segment = 40000) {
  const int samples = samples_per_segment * int(c.num_segments());
  const Bounds3 box = tight_bounds(c);
  ASSERT_FALSE(box.empty());
  const double size = std::fmax(glm::length(box.hi - box.lo), 1e-300);
  const double slack = 1e-12 * size + 1e-15 * glm::length(box.hi);
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (int i = 0; i <= samples; ++i) {
    const glm::dvec3 p = c.eval(double(i) / samples);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  // The samples' own box: inside the computed one, and touching each of its faces.
  for (int a = 0; a < 3; ++a) {
    EXPECT_GE(lo[a], box.lo[a] - slack) << "axis " << a;
    EXPECT_LE(hi[a], box.hi[a] + slack) << "axis " << a;
    EXPECT_NEAR(lo[a], box.lo[a], 1e-9 * size + slack) << "axis " << a;
    EXPECT_NEAR(hi[a], box.hi[a], 1e-9 * size + slack) << "axis " << a;
  }
}

TEST(BSplineBounds, ContainDenseSamplesAndTouchEveryFace) {
  std::mt19937 rng(6);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 4 + trial % 5;
    expect_tight(BSpline3(random_points(rng, n)));
  }
}

TEST(BSplineBounds, ExtremaInsideASegmentAreFound) {
  // A symmetric arch: the top is at the middle of the only segment, above every
  // control point's average and far from both endpoints.
  const BSpline3 c({{0, 0, 0}, {1, 3, 0}, {2, 3, 0}, {3, 0, 0}});
  const Bounds3 box = tight_bounds(c);
  EXPECT_NEAR(box.hi.y, c.eval(0.5).y, 1e-15);
  EXPECT_GT(box.hi.y, std::fmax(c.eval(0).y, c.eval(1).y) + 0.3);
}

TEST(BSplineBounds, RejectsInvalidCurve) {
  EXPECT_THROW(tight_bounds(BSpline3({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}})), Error);
  EXPECT_THROW(arc_length(BSpline3()), Error);
  EXPECT_THROW(ArcLengthTable(BSpline3({{0, 0, 0}})), Error);
}

// --- arc length ---------------------------------------------------------------

TEST(BSplineArcLength, MatchesDensePolyline) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 10; ++trial) {
    const BSpline3 c(random_points(rng, 4 + trial));
    // A polyline with N chords under-estimates by O(1/N^2); N = 2e5 leaves ~1e-10.
    const double reference = polyline_length(c, 0, 1, 200000);
    EXPECT_NEAR(arc_length(c), reference, 1e-8 * reference);
    const double part = polyline_length(c, 0.13, 0.71, 200000);
    EXPECT_NEAR(arc_length(c, 0.13, 0.71), part, 1e-8 * part);
  }
}

TEST(BSplineArcLength, StraightLineAndCircle) {
  // Collinear, evenly spaced control points: a straight segment from P1 to P_{n-2},
  // traversed at constant speed.
  const BSpline3 line({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4}});
  EXPECT_NEAR(arc_length(line), std::sqrt(3.0) * 2.0, 1e-12);
  EXPECT_NEAR(arc_length(line, 0.25, 0.75), std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(arc_length(line, 0.75, 0.25), -std::sqrt(3.0), 1e-12);
  EXPECT_EQ(arc_length(line, 0.4, 0.4), 0.0);
}

TEST(BSplineArcLength, IsAdditive) {
  std::mt19937 rng(8);
  const BSpline3 c(random_points(rng, 9));
  const double whole = arc_length(c);
  for (double m : {0.1, 1.0 / 6, 0.5, 0.9999}) {
    EXPECT_NEAR(arc_length(c, 0, m) + arc_length(c, m, 1), whole, 1e-10 * whole);
  }
}

TEST(ArcLengthTable, RoundTrips) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 5; ++trial) {
    const BSpline3 c(random_points(rng, 5 + 3 * trial));
    const ArcLengthTable table(c, 8 + trial * 8);
    const double L = table.length();
    EXPECT_NEAR(L, arc_length(c), 1e-9 * L);
    for (int i = 0; i <= 500; ++i) {
      const double s = L * i / 500.0;
      const double t = table.t_at(s);
      ASSERT_GE(t, 0.0);
      ASSERT_LE(t, 1.0);
      // Against the independent global integration, not the table's own sums.
      EXPECT_NEAR(arc_length(c, 0, t), s, 1e-9 * L) << "s=" << s;
      EXPECT_NEAR(table.s_at(t), s, 1e-9 * L);
    }
    for (int i = 0; i <= 200; ++i) {
      const double t = i / 200.0;
      EXPECT_NEAR(table.s_at(t), arc_length(c, 0, t), 1e-9 * L);
      EXPECT_NEAR(table.t_at(table.s_at(t)), t, 1e-7);
    }
    EXPECT_EQ(table.t_at(-1.0), 0.0);
    EXPECT_EQ(table.t_at(2 * L), 1.0);
    EXPECT_EQ(table.s_at(-3.0), 0.0);
  }
}

TEST(ArcLengthTable, OutlivesItsCurve) {
  std::mt19937 rng(10);
  auto curve = std::make_unique<BSpline3>(random_points(rng, 6));
  const double expected = arc_length(*curve);
  const double t_half = [&] {
    ArcLengthTable probe(*curve);
    return probe.t_at(0.5 * probe.length());
  }();
  const ArcLengthTable table(*curve);
  curve.reset();
  EXPECT_NEAR(table.length(), expected, 1e-9 * expected);
  EXPECT_NEAR(table.t_at(0.5 * expected), t_half, 1e-12);
}

TEST(ArcLengthTable, SingularParameterisation) {
  // Tripled control points make the speed vanish at a parameter inside the curve:
  // Newton must fall back and t(s) must stay monotone and finite.
  const BSpline3 c({{0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {2, 1, 0}, {2, 1, 0}, {3, 3, 0}, {4, 3, 1}});
  const ArcLengthTable table(c, 4);
  const double L = table.length();
  EXPECT_NEAR(L, polyline_length(c, 0, 1, 400000), 1e-8 * L);
  double prev = -1;
  for (int i = 0; i <= 1000; ++i) {
    const double s = L * i / 1000.0, t = table.t_at(s);
    ASSERT_TRUE(std::isfinite(t));
    EXPECT_GE(t, prev);
    EXPECT_NEAR(arc_length(c, 0, t), s, 1e-9 * L);
    prev = t;
  }
}

TEST(ArcLengthTable, ZeroLengthCurve) {
  const BSpline3 c(std::vector<glm::dvec3>(5, glm::dvec3(1, 2, 3)));
  const ArcLengthTable table(c);
  EXPECT_EQ(table.length(), 0.0);
  EXPECT_EQ(table.t_at(0.0), 0.0);
  EXPECT_EQ(table.t_at(1.0), 0.0);
  EXPECT_EQ(table.s_at(0.5), 0.0);
  EXPECT_THROW(ArcLengthTable(c, 0), Error);
  EXPECT_THROW(ArcLengthTable(c, 1 << 30), Error);  // would allocate gigabytes
}

// --- fitting ------------------------------------------------------------------

double max_residual(const BSpline3& c, const std::vector<glm::dvec3>& pts,
                    const std::vector<double>& params) {
  double r = 0;
  for (std::size_t j = 0; j < pts.size(); ++j)
    r = std::fmax(r, glm::length(c.eval(params[j]) - pts[j]));
  return r;
}

// Distance from the fitted curve to a known curve: nearest sample of the known
// curve, refined by golden-section search on its parameter. Independent of the
// fit's own parameters.
template <class F>
double max_distance_to(const BSpline3& fit, F&& truth) {
  const int samples = 2000;
  std::vector<glm::dvec3> dense(samples + 1);
  for (int i = 0; i <= samples; ++i) dense[i] = truth(double(i) / samples);
  double worst = 0;
  for (int k = 0; k <= 400; ++k) {
    const glm::dvec3 p = fit.eval(k / 400.0);
    int best = 0;
    for (int i = 1; i <= samples; ++i)
      if (glm::length(p - dense[i]) < glm::length(p - dense[best])) best = i;
    double a = std::max(0, best - 1) / double(samples),
           b = std::min(samples, best + 1) / double(samples);
    const double g = (std::sqrt(5.0) - 1) / 2;
    auto dist = [&](double t) { return glm::length(truth(t) - p); };
    for (int it = 0; it < 80; ++it) {
      const double c = b - g * (b - a), d = a + g * (b - a);
      if (dist(c) < dist(d))
        b = d;
      else
        a = c;
    }
    worst = std::fmax(worst, dist(0.5 * (a + b)));
  }
  return worst;
}

TEST(BSplineFit, RecoversASampledBSplineExactly) {
  std::mt19937 rng(11);
  for (bool clamp : {false, true}) {
    for (int n : {4, 5, 9, 16}) {
      const auto cp = random_points(rng, n, 10.0, {100, -50, 3});
      const BSpline3 truth(cp);
      std::vector<glm::dvec3> pts;
      std::vector<double> params;
      for (int j = 0; j <= 20 * n; ++j) {
        params.push_back(double(j) / (20 * n));
        pts.push_back(truth.eval(params.back()));
      }
      const BSpline3 fit = fit_bspline(pts, n, params, clamp);
      ASSERT_EQ(fit.control_points().size(), std::size_t(n));
      for (int i = 0; i < n; ++i)
        EXPECT_NEAR(glm::length(fit.control_points()[i] - cp[i]), 0.0, 1e-7)
            << "n=" << n << " clamp=" << clamp << " i=" << i;
    }
  }
}

TEST(BSplineFit, CircleArcAndHelixResidualsShrinkWithMoreControlPoints) {
  const double pi = std::numbers::pi;
  // Both curves have constant speed, so chord-length parameters are close to their
  // angle parameter and the error should follow cubic-spline approximation theory:
  // about (5/384) h^4 max|f^(4)| (Hall & Meyer, J. Approx. Theory 1976), with
  // h = 1/segments and |f^(4)| = R a^4 for angle a t.
  struct Case {
    double radius, turn, rise;
  };
  for (const Case& cs : {Case{5, 1.5 * pi, 0}, Case{2, 6 * pi, 4}}) {
    auto truth = [&](double t) {
      return glm::dvec3(cs.radius * std::cos(cs.turn * t), cs.radius * std::sin(cs.turn * t),
                        cs.rise * t);
    };
    std::vector<glm::dvec3> pts;
    for (int j = 0; j <= 400; ++j) pts.push_back(truth(j / 400.0));
    double prev = INFINITY;
    int prev_n = 4;
    for (int n : {6, 10, 18, 34, 66}) {
      const BSpline3 fit = fit_bspline(pts, n);
      const double d = max_distance_to(fit, truth);
      const double h = 1.0 / (n - 3);
      const double theory = 5.0 / 384 * std::pow(h, 4) * cs.radius * std::pow(cs.turn, 4);
      EXPECT_LT(d, prev) << "turn=" << cs.turn << " n=" << n;
      // Once the previous fit resolved the turn (under ~1.5 rad per segment), the
      // h^4 rate must show: almost twice the segments, far more than 4x closer.
      if (cs.turn / (prev_n - 3) < 1.5) {
        EXPECT_LT(d, prev / 4) << "turn=" << cs.turn << " n=" << n;
      }
      EXPECT_LT(d, 8 * theory) << "turn=" << cs.turn << " n=" << n;
      prev = d;
      prev_n = n;
    }
  }
}

TEST(BSplineFit, ClampEndsPassesThroughEndpoints) {
  std::mt19937 rng(12);
  std::normal_distribution<double> noise(0, 0.05);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<glm::dvec3> pts;
    for (int j = 0; j < 50; ++j) {
      const double t = j / 49.0;
      pts.push_back({t * 10 + noise(rng), std::sin(3 * t) + noise(rng), noise(rng)});
    }
    const int n = 4 + trial % 8;
    const BSpline3 fit = fit_bspline(pts, n);
    EXPECT_NEAR(glm::length(fit.eval(0.0) - pts.front()), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(fit.eval(1.0) - pts.back()), 0.0, 1e-12);
    const BSpline3 free_fit = fit_bspline(pts, n, {}, false);
    // The unconstrained fit is the least-squares optimum, so it cannot be worse.
    auto sum_sq = [&](const BSpline3& c) {
      double total = 0, acc = 0;
      for (std::size_t j = 1; j < pts.size(); ++j) total += glm::length(pts[j] - pts[j - 1]);
      double s = 0;
      for (std::size_t j = 0; j < pts.size(); ++j) {
        if (j) acc += glm::length(pts[j] - pts[j - 1]);
        const glm::dvec3 d = c.eval(acc / total) - pts[j];
        s += glm::dot(d, d);
      }
      return s;
    };
    EXPECT_LE(sum_sq(free_fit), sum_sq(fit) * (1 + 1e-9));
  }
}

TEST(BSplineFit, ChordLengthParametersAreUsedByDefault) {
  // Unevenly spaced samples of a straight line: with chord-length parameters the
  // fit is the line itself, traversed at constant speed.
  std::vector<glm::dvec3> pts;
  for (double x : {0.0, 0.1, 0.15, 1.0, 2.0, 2.05, 4.0, 7.0, 9.5, 10.0})
    pts.push_back({x, 2 * x, -x});
  const BSpline3 fit = fit_bspline(pts, 5);
  for (int i = 0; i <= 20; ++i) {
    const double t = i / 20.0;
    EXPECT_NEAR(glm::length(fit.eval(t) - glm::dvec3(10 * t, 20 * t, -10 * t)), 0.0, 1e-8);
  }
}

TEST(BSplineFit, RejectsBadInput) {
  std::vector<glm::dvec3> pts(10, glm::dvec3(0));
  for (int j = 0; j < 10; ++j) pts[j] = glm::dvec3(j, j * j, 0);
  EXPECT_THROW(fit_bspline(pts, 3), Error);
  EXPECT_THROW(fit_bspline(pts, 11), Error);
  EXPECT_THROW(fit_bspline(std::span<const glm::dvec3>(), 4), Error);
  const std::vector<double> short_params(5, 0.5);
  EXPECT_THROW(fit_bspline(pts, 4, short_params), Error);
  std::vector<double> bad_params(10, 0.5);
  bad_params[3] = 1.5;
  EXPECT_THROW(fit_bspline(pts, 4, bad_params), Error);
  bad_params[3] = std::nan("");
  EXPECT_THROW(fit_bspline(pts, 4, bad_params), Error);
  try {
    fit_bspline(pts, 11);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("11"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(fit_bspline(pts, 10));
}

// --- penalised fit (P-splines) ---------------------------------------------------

// The least-squares parabola v = a + b u + c u^2 through (u, v) pairs, by its
// normal equations (Cramer's rule, no project code).
std::array<double, 3> parabola_through(const std::vector<double>& u, const std::vector<double>& v) {
  double S[5] = {0, 0, 0, 0, 0}, T[3] = {0, 0, 0};
  for (std::size_t i = 0; i < u.size(); ++i) {
    double p = 1;
    for (double& s : S) s += p, p *= u[i];
    T[0] += v[i], T[1] += v[i] * u[i], T[2] += v[i] * u[i] * u[i];
  }
  auto det3 = [](double a, double b, double c, double d, double e, double f, double g, double h, double i) {
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  };
  const double D = det3(S[0], S[1], S[2], S[1], S[2], S[3], S[2], S[3], S[4]);
  return {det3(T[0], S[1], S[2], T[1], S[2], S[3], T[2], S[3], S[4]) / D,
          det3(S[0], T[0], S[2], S[1], T[1], S[3], S[2], T[2], S[4]) / D,
          det3(S[0], S[1], T[0], S[1], S[2], T[1], S[2], S[3], T[2]) / D};
}

TEST(BSplinePenalised, ParabolasCostNothingUnderAThirdDifferencePenalty) {
  // A parabola known only near its two ends is continued as that parabola
  // through the middle, whatever the penalty's weight, also far from the origin.
  for (const double offset : {0.0, 1e9}) {
    for (const double lambda : {1e-3, 1.0, 1e6}) {
      SCOPED_TRACE("offset " + std::to_string(offset) + ", lambda " + std::to_string(lambda));
      auto curve = [&](double t) { return glm::dvec3(offset + 3 * t, offset - 2 + 5 * t - 7 * t * t, 0.5); };
      std::vector<glm::dvec3> pts;
      std::vector<double> t, w;
      for (const double ti : {0.0, 0.03, 0.07, 0.1, 0.9, 0.95, 1.0})
        pts.push_back(curve(ti)), t.push_back(ti), w.push_back(1.0);
      const BSpline3 c = fit_bspline_penalised(pts, t, w, 14, 3, lambda);
      double worst = 0;
      for (int i = 0; i <= 100; ++i) worst = std::max(worst, glm::length(c.eval(i / 100.0) - curve(i / 100.0)));
      EXPECT_LT(worst, 1e-6 * std::max(1.0, offset)) << worst;
    }
  }
}

TEST(BSplinePenalised, ThePenaltyFlattensAnSAndZeroWeightsAreIgnored) {
  // A full sine period sampled densely: with a tiny penalty the fit follows it;
  // with a large one only a parabola is left (the S's distance from its best
  // parabola falls from 0.35 to under 1 % of that). Points of weight 0 change nothing.
  std::vector<glm::dvec3> pts;
  std::vector<double> t, w;
  for (int i = 0; i <= 200; ++i) {
    const double ti = i / 200.0;
    pts.emplace_back(ti, std::sin(2 * std::numbers::pi * ti), 0.0), t.push_back(ti), w.push_back(1.0);
  }
  const BSpline3 loose = fit_bspline_penalised(pts, t, w, 24, 3, 1e-9);
  double follow = 0;
  for (int i = 0; i <= 200; ++i) follow = std::max(follow, glm::length(loose.eval(t[i]) - pts[i]));
  EXPECT_LT(follow, 1e-3);
  auto s_amplitude = [&](const BSpline3& c) {
    std::vector<double> u, v;
    for (int i = 0; i <= 200; ++i) u.push_back(c.eval(i / 200.0).x), v.push_back(c.eval(i / 200.0).y);
    const auto p = parabola_through(u, v);
    double worst = 0;
    for (std::size_t i = 0; i < u.size(); ++i)
      worst = std::max(worst, std::fabs(v[i] - (p[0] + p[1] * u[i] + p[2] * u[i] * u[i])));
    return worst;
  };
  const double raw = s_amplitude(loose);
  EXPECT_GT(raw, 0.3);
  const BSpline3 stiff = fit_bspline_penalised(pts, t, w, 24, 3, 1e9);
  EXPECT_LT(s_amplitude(stiff), 0.01 * raw);
  // Outliers given weight 0 leave the fit as it was, bit for bit.
  std::vector<glm::dvec3> more = pts;
  std::vector<double> more_t = t, more_w = w;
  for (const double ti : {0.25, 0.5, 0.75})
    more.emplace_back(ti, 1e3, 0.0), more_t.push_back(ti), more_w.push_back(0.0);
  const BSpline3 same = fit_bspline_penalised(more, more_t, more_w, 24, 3, 1e-9);
  for (int i = 0; i <= 20; ++i) EXPECT_EQ(same.eval(i / 20.0), loose.eval(i / 20.0));
}

TEST(BSplinePenalised, RejectsBadInput) {
  std::vector<glm::dvec3> pts;
  std::vector<double> t, w;
  for (int i = 0; i < 10; ++i) pts.emplace_back(i, i * i, 0), t.push_back(i / 9.0), w.push_back(1.0);
  EXPECT_NO_THROW(fit_bspline_penalised(pts, t, w, 8, 3, 1.0));
  EXPECT_THROW(fit_bspline_penalised(pts, t, w, 3, 3, 1.0), Error);
  EXPECT_THROW(fit_bspline_penalised(pts, t, w, 8, 0, 1.0), Error);
  EXPECT_THROW(fit_bspline_penalised(pts, t, w, 8, 4, 1.0), Error);
  EXPECT_THROW(fit_bspline_penalised(pts, t, w, 8, 3, -1.0), Error);
  EXPECT_THROW(fit_bspline_penalised(pts, t, w, 8, 3, std::nan("")), Error);
  EXPECT_THROW(fit_bspline_penalised(pts, std::vector<double>(5, 0.5), w, 8, 3, 1.0), Error);
  std::vector<double> bad = w;
  bad[2] = -1;
  EXPECT_THROW(fit_bspline_penalised(pts, t, bad, 8, 3, 1.0), Error);
  EXPECT_THROW(fit_bspline_penalised(pts, t, std::vector<double>(10, 0.0), 8, 3, 1.0), Error);
  bad = t;
  bad[4] = 1.5;
  EXPECT_THROW(fit_bspline_penalised(pts, bad, w, 8, 3, 1.0), Error);
  std::vector<glm::dvec3> nan_pts = pts;
  nan_pts[1].y = std::nan("");
  EXPECT_THROW(fit_bspline_penalised(nan_pts, t, w, 8, 3, 1.0), Error);
  // Two weighted points cannot fix a parabola (the penalty's free part): refused.
  std::vector<double> two(10, 0.0);
  two[0] = two[9] = 1.0;
  EXPECT_THROW(fit_bspline_penalised(pts, t, two, 8, 3, 1.0), Error);
  EXPECT_NO_THROW(fit_bspline_penalised(pts, t, two, 8, 2, 1.0));  // a line through two points
}

// --- stress ---------------------------------------------------------------------


TEST(BSplineStress, CoincidentControlPoints) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 30; ++trial) {
    auto cp = random_points(rng, 8);
    // Collapse runs of control points onto each other, up to the whole curve.
    const int from = trial % 8, len = 1 + trial % 8;
    for (int i = from; i < std::min(8, from + len); ++i) cp[i] = cp[from];
    const BSpline3 c(cp);
    expect_tight(c);
    const double L = arc_length(c);
    ASSERT_TRUE(std::isfinite(L));
    EXPECT_NEAR(L, polyline_length(c, 0, 1, 100000), 1e-7 * (L + 1e-300) + 1e-12);
    const ArcLengthTable table(c);
    for (int i = 0; i <= 50; ++i) ASSERT_TRUE(std::isfinite(table.t_at(L * i / 50)));
  }
}

TEST(BSplineStress, HugeAndTinyCoordinates) {
  std::mt19937 rng(14);
  // (size, offset): huge curves, unit curves far from the origin, tiny curves. A
  // tiny curve far away is not representable (1e5 carries ~1e-11 absolute precision).
  const std::pair<double, double> cases[] = {
      {1e5, 0}, {1e5, 1e5}, {1.0, 1e5}, {1e-6, 0}, {1e-6, 1e-5}};
  for (const auto& [scale, off] : cases) {
    {
      const glm::dvec3 offset(off, -off, off);
      const auto cp = random_points(rng, 7, scale, offset);
      const BSpline3 c(cp);
      expect_tight(c);
      const double L = arc_length(c);
      EXPECT_NEAR(L, polyline_length(c, 0, 1, 100000), 1e-7 * L);
      const ArcLengthTable table(c);
      EXPECT_NEAR(table.length(), L, 1e-9 * L);
      const double t = table.t_at(0.3 * L);
      EXPECT_NEAR(arc_length(c, 0, t), 0.3 * L, 1e-9 * L);

      std::vector<glm::dvec3> pts;
      std::vector<double> params;
      for (int j = 0; j <= 140; ++j) {
        params.push_back(j / 140.0);
        pts.push_back(c.eval(params.back()));
      }
      const BSpline3 fit = fit_bspline(pts, 7, params);
      for (int i = 0; i < 7; ++i)
        // A coordinate of 1e5 carries only ~1e-11 absolute precision.
        EXPECT_NEAR(glm::length(fit.control_points()[i] - cp[i]), 0.0,
                    1e-7 * scale + 1e-14 * glm::length(offset))
            << "scale=" << scale << " offset=" << offset.x;
    }
  }
}

TEST(BSplineStress, NonFiniteControlPointsAreRejectedNotLoopedOn) {
  for (double bad : {std::nan(""), double(INFINITY)}) {
    std::vector<glm::dvec3> cp = {{0, 0, 0}, {1, 1, 0}, {2, 0, 1}, {3, 1, 0}, {4, 0, 0}};
    cp[2].y = bad;
    const BSpline3 c(cp);
    EXPECT_THROW(tight_bounds(c), Error);
    EXPECT_THROW(arc_length(c), Error);
    EXPECT_THROW(ArcLengthTable{c}, Error);
  }
  // Finite, but lengths overflow: an error, not a NaN length or box.
  const BSpline3 huge({{-1e308, 0, 0}, {1e308, 0, 0}, {-1e308, 0, 0}, {1e308, 0, 0}});
  EXPECT_THROW(arc_length(huge), Error);
  EXPECT_THROW(tight_bounds(huge), Error);
}

TEST(BSplineFuzz, FitNeverReturnsNaN) {
  std::mt19937 rng(15);
  std::uniform_int_distribution<int> pick(0, 5);
  for (int trial = 0; trial < 300; ++trial) {
    const int m = 4 + trial % 40;
    std::vector<glm::dvec3> pts = random_points(rng, m, std::pow(10.0, trial % 13 - 6));
    // Duplicates: repeated runs, all-identical, and clusters at one place.
    for (int j = 1; j < m; ++j)
      if (pick(rng) == 0) pts[j] = pts[j - 1];
    if (trial % 7 == 0) std::fill(pts.begin(), pts.end(), pts[0]);
    if (trial % 11 == 0) std::fill(pts.begin() + m / 2, pts.end(), pts[m / 2]);
    const int n = 4 + trial % std::max(1, m - 3);
    for (bool clamp : {false, true}) {
      BSpline3 fit;
      ASSERT_NO_THROW(fit = fit_bspline(pts, n, {}, clamp))
          << "trial " << trial << " clamp " << clamp;
      for (const auto& p : fit.control_points()) ASSERT_TRUE(all_finite(p)) << "trial " << trial;
      if (clamp) {
        EXPECT_NEAR(glm::length(fit.eval(0) - pts.front()), 0.0,
                    1e-9 * (1 + glm::length(pts.front())));
      }
    }
  }
}

TEST(BSplineFuzz, NonFinitePointsAreRejected) {
  std::vector<glm::dvec3> pts;
  for (int j = 0; j < 12; ++j) pts.push_back({j, 0, 0});
  for (double bad : {std::nan(""), double(INFINITY), -double(INFINITY)}) {
    for (int where : {0, 5, 11}) {
      auto p = pts;
      p[where].y = bad;
      EXPECT_THROW(fit_bspline(p, 5), Error);
    }
  }
  // Finite points so far apart that their differences overflow.
  std::vector<glm::dvec3> far = pts;
  far[0].x = -1.7e308;
  far[11].x = 1.7e308;
  EXPECT_THROW(fit_bspline(far, 5), Error);
}
