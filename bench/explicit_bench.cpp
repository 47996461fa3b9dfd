// Explicit mode's cost (docs/substructure.md "Explicit reference"): building the
// Embree scene of the rock-dove preset in each shading mode (explicit mode makes
// barbs x (1 + 2N) round curves), and time per camera sample in the close view of
// substructure_bench.cpp (one thread, 25-LED dome, 64x64 x 4 spp), far-field
// mode beside them. Results: docs/perf/subst.md.
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

constexpr ShadingMode kModes[] = {ShadingMode::Hair, ShadingMode::Substructure, ShadingMode::Explicit,
                                  ShadingMode::Farfield};

// state.range(0): 0 hair, 1 substructure, 2 explicit, 3 farfield (its tables' fit,
// or their read from the cache, is part of the integrator's construction, not the scene's).
void BM_SceneBuild(benchmark::State& state) {
  const SceneOptions so{kModes[state.range(0)], {true, glm::vec3(0.8f)}};
  std::size_t curves = 0, bytes = 0;
  for (auto _ : state) {
    const Scene scene(rock_dove(), so);
    curves = scene.explicit_curves();
    bytes = scene.explicit_bytes();
    benchmark::DoNotOptimize(scene.embree_scene());
  }
  state.counters["explicit_curves"] = double(curves);
  state.counters["explicit_MB"] = double(bytes) / (1 << 20);
}
BENCHMARK(BM_SceneBuild)->ArgName("mode")->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->Iterations(2);

// state.range(0): mode as above; range(1): camera height above the feather (mm).
void BM_RenderSampleByMode(benchmark::State& state) {
  static const DomeRig rig = read_dome_rig(std::filesystem::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  const Scene scene(rock_dove(), SceneOptions{kModes[state.range(0)], {true, glm::vec3(0.8f)}});
  ViewSpec view;
  view.width = view.height = 64;
  view.spp = 4;
  view.threads = 1;
  view.camera.position = glm::vec3(10.0f, 60.0f, float(state.range(1)));
  view.camera.look_at = glm::vec3(10.0f, 60.0f, 0.0f);
  // Once untimed: farfield mode fits (or reads) its tables when the first render starts.
  benchmark::DoNotOptimize(render_view(scene, rig, view));
  for (auto _ : state) benchmark::DoNotOptimize(render_view(scene, rig, view));
  const double samples = double(view.width) * view.height * view.spp;
  state.counters["us_per_sample"] =
      benchmark::Counter(samples * 1e-6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_RenderSampleByMode)
    ->ArgNames({"mode", "height_mm"})
    ->ArgsProduct({{0, 1, 2, 3}, {8, 100}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
