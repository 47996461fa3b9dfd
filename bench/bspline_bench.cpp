// Uniform cubic B-splines: the per-call costs the generator and the analysis pay
// per barb (evaluation, length, arc-length lookups, fitting a centreline).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "plumage/common/bspline.h"

namespace {

// A barb-like curve: 6 control points, gently bent out of plane.
plumage::BSpline3 barb() {
  return plumage::BSpline3({{0, 0, 0}, {1, 2, 0}, {2, -1, 1}, {3, 0, 0}, {4, 1, 2}, {5, 0, 0}});
}

}  // namespace

static void BM_BSplineEval(benchmark::State& state) {
  const plumage::BSpline3 c = barb();
  double t = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.eval(t));
    t += 0.001;
    if (t > 1) t = 0;
  }
}
BENCHMARK(BM_BSplineEval);

static void BM_BSplineArcLength(benchmark::State& state) {
  const plumage::BSpline3 c = barb();
  for (auto _ : state) benchmark::DoNotOptimize(plumage::arc_length(c));
}
BENCHMARK(BM_BSplineArcLength);

static void BM_ArcLengthTableBuild(benchmark::State& state) {
  const plumage::BSpline3 c = barb();
  for (auto _ : state) {
    plumage::ArcLengthTable table(c);
    benchmark::DoNotOptimize(table.length());
  }
}
BENCHMARK(BM_ArcLengthTableBuild);

static void BM_ArcLengthTableTAt(benchmark::State& state) {
  const plumage::ArcLengthTable table(barb());
  const double L = table.length();
  double s = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(table.t_at(s));
    s += 0.0137 * L;
    if (s > L) s -= L;
  }
}
BENCHMARK(BM_ArcLengthTableTAt);

static void BM_FitBSpline200To12(benchmark::State& state) {
  std::vector<glm::dvec3> pts;
  for (int j = 0; j < 200; ++j) {
    const double t = j / 199.0;
    pts.push_back({30 * t, 4 * std::sin(3 * t), 0.5 * t * t});
  }
  for (auto _ : state) benchmark::DoNotOptimize(plumage::fit_bspline(pts, 12));
}
BENCHMARK(BM_FitBSpline200To12);
