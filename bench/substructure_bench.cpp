// Substructure against hair shading: time per camera sample for the same feather
// (the rock-dove preset), same view (the vanes' middle, a few mm across, where
// barbules are resolved), same lights (25-LED dome) and sample count; one thread
// so the figure is per core. docs/perf/subst.md records the results.
#include <benchmark/benchmark.h>

#include "bench_scenes.h"

using namespace plumage;

namespace {

// state.range(0): 0 = hair, 1 = substructure; range(1): camera height above the feather (mm).
void BM_RenderSample(benchmark::State& state) {
  const ShadingMode mode = state.range(0) ? ShadingMode::Substructure : ShadingMode::Hair;
  const Scene scene(bench::rock_dove(), SceneOptions{mode, {true, glm::vec3(0.8f)}});
  const ViewSpec view = bench::top_view(float(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(render_view(scene, bench::dome25(), view));
  const double samples = double(view.width) * view.height * view.spp;
  state.SetItemsProcessed(state.iterations() * std::int64_t(samples));
  state.counters["us_per_sample"] =
      benchmark::Counter(samples * 1e-6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_RenderSample)
    ->ArgNames({"substructure", "height_mm"})
    ->Args({0, 8})
    ->Args({1, 8})
    ->Args({0, 100})
    ->Args({1, 100})
    ->Unit(benchmark::kMillisecond);

}  // namespace
