// What skipping work buys: BVH build and render time of a zoomed view with and
// without view culling (the rock-dove preset, 25-LED dome, white backdrop; one
// thread), and adaptive against fixed sampling. docs/perf/benchladder.md.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/view_cull.h"

using namespace plumage;

namespace {

const Feather& rock_dove() {
  static const Feather f = build_feather(load_preset("rock-dove-wing"), 1, "preset:rock-dove-wing");
  return f;
}

const DomeRig& rig() {
  static const DomeRig r = read_dome_rig(std::filesystem::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  return r;
}

// A top view 15 mm over the vane at (10, 60): about 8 mm across.
ViewSpec zoomed() {
  ViewSpec v;
  v.width = v.height = 64;
  v.spp = 4;
  v.threads = 1;
  v.camera.position = glm::vec3(10.0f, 60.0f, 15.0f);
  v.camera.look_at = glm::vec3(10.0f, 60.0f, 0.0f);
  return v;
}

SceneOptions options(bool cull) {
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.8f)};
  if (cull) so.cull = view_cull_for(zoomed(), rig());
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
  for (auto _ : state) benchmark::DoNotOptimize(render_view(scene, rig(), view));
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
  for (auto _ : state) benchmark::DoNotOptimize(render_view(scene, rig(), view));
}
BENCHMARK(BM_RenderAdaptive)->ArgName("adaptive")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
