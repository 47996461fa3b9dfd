// What skipping work buys: BVH build and render time of a zoomed view with and
// without view culling (the rock-dove preset, 25-LED dome, white backdrop; one
// thread), and adaptive against fixed sampling. docs/perf/benchladder.md.
#include <benchmark/benchmark.h>

#include "bench_scenes.h"
#include "plumage/renderer/view_cull.h"

using namespace plumage;

namespace {

using bench::dome25;
using bench::rock_dove;

// A top view 15 mm over the vane at (10, 60): about 8 mm across.
ViewSpec zoomed() { return bench::top_view(15.0f); }

SceneOptions options(bool cull) {
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.8f)};
  if (cull) so.cull = view_cull_for(zoomed(), dome25());
  return so;
}

// range(0): 1 = cull.
void BM_SceneBuildZoomed(benchmark::State& state) {
  std::size_t culled = 0;
  for (auto _ : state) {
    const Scene scene(rock_dove(), options(state.range(0)));
    culled = scene.culled_curves();
  }
  state.counters["curves_culled"] = double(culled);
}
BENCHMARK(BM_SceneBuildZoomed)->ArgName("cull")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_RenderZoomed(benchmark::State& state) {
  const Scene scene(rock_dove(), options(state.range(0)));
  const ViewSpec view = zoomed();
  for (auto _ : state) benchmark::DoNotOptimize(render_view(scene, dome25(), view));
}
BENCHMARK(BM_RenderZoomed)->ArgName("cull")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// range(0): 1 = adaptive (5 % target, at most 64 spp) against 64 fixed samples.
void BM_RenderAdaptive(benchmark::State& state) {
  const Scene scene(rock_dove(), options(false));
  ViewSpec view = zoomed();
  view.spp = 64;
  view.width = view.height = 32;
  view.adaptive = state.range(0);
  view.target_error = 0.05f;
  for (auto _ : state) benchmark::DoNotOptimize(render_view(scene, dome25(), view));
}
BENCHMARK(BM_RenderAdaptive)->ArgName("adaptive")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
