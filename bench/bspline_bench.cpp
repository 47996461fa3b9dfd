#include <benchmark/benchmark.h>

#include "plumage/common/bspline.h"

static void BM_BSplineEval(benchmark::State& state) {
  plumage::BSpline3 c({{0, 0, 0}, {1, 2, 0}, {2, -1, 1}, {3, 0, 0}, {4, 1, 2}, {5, 0, 0}});
  double t = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.eval(t));
    t += 0.001;
    if (t > 1) t = 0;
  }
}
BENCHMARK(BM_BSplineEval);
