// The generate stage of photo-to-feather: a layout like the pink contour
// feather's (150 mm, 24 stations, ~170 barbs per side) to params, and to a
// feather. Results: docs/perf/p2f.md.
#include <benchmark/benchmark.h>

#include <cmath>

#include "plumage/generator/layout_to_params.h"

namespace {

plumage::FeatherLayout pink_like_layout() {
  plumage::FeatherLayout f;
  const double L = 150.0;
  std::vector<glm::dvec2> pts;
  for (int i = 0; i < 12; ++i) pts.push_back({0.0, L * (i - 1) / 9.0});
  f.shaft_mm = plumage::BSpline2(pts);
  f.length_mm = L;
  f.shaft_width_mm = 2.6;
  for (int i = 0; i < 24; ++i) f.stations_t.push_back((i + 0.5) / 24.0);
  for (auto* v : {&f.left, &f.right})
    for (double t : f.stations_t) {
      v->width_mm.push_back(t < 0.2 ? 0.0 : 20.0 * std::sqrt(std::sin(3.14159 * (t - 0.2) / 0.8)));
      v->width_confidence.push_back(1.0);
      v->barb_angle_deg.push_back(45.0);
      v->barb_angle_confidence.push_back(t < 0.5 ? 0.9 : 0.2);
      v->barb_spacing_mm.push_back(0.72);
      v->barb_spacing_confidence.push_back(0.8);
    }
  return f;
}

void BM_LayoutToParams(benchmark::State& state) {
  const plumage::FeatherLayout f = pink_like_layout();
  for (auto _ : state) benchmark::DoNotOptimize(plumage::layout_to_params(f));
}
BENCHMARK(BM_LayoutToParams)->Unit(benchmark::kMicrosecond);

void BM_LayoutToFeather(benchmark::State& state) {
  const plumage::FeatherLayout f = pink_like_layout();
  std::uint64_t seed = 1;
  for (auto _ : state) benchmark::DoNotOptimize(plumage::layout_to_feather(f, seed++, ".", "."));
}
BENCHMARK(BM_LayoutToFeather)->Unit(benchmark::kMillisecond);

}  // namespace
