// Substructure against hair shading: time per camera sample for the same feather
// (the rock-dove preset), same view (the vanes' middle, a few mm across, where
// barbules are resolved), same lights (25-LED dome) and sample count; one thread
// so the figure is per core. docs/perf/subst.md records the results.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/feather_render.h"

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

// state.range(0): 0 = hair, 1 = substructure; range(1): camera height above the feather (mm).
void BM_RenderSample(benchmark::State& state) {
  const ShadingMode mode = state.range(0) ? ShadingMode::Substructure : ShadingMode::Hair;
  const Scene scene(rock_dove(), SceneOptions{mode, {true, glm::vec3(0.8f)}});
  ViewSpec view;
  view.width = view.height = 64;
  view.spp = 4;
  view.threads = 1;
  view.camera.position = glm::vec3(10.0f, 60.0f, float(state.range(1)));
  view.camera.look_at = glm::vec3(10.0f, 60.0f, 0.0f);
  for (auto _ : state) benchmark::DoNotOptimize(render_view(scene, rig(), view));
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
