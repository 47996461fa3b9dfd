// The far-field fit's cost (docs/substructure.md "Fit and cache"): every table the
// rock-dove preset needs (per vane and barb class, its transmittance table and its
// BSDF table for the material at the feather's centre), measured by the virtual
// gonioreflectometer at the default settings on all cores, no cache. Counters: the
// tables, the rays traced per incident path, and the worst table's noise (the fit's
// own error, split-half relative RMS). Results: docs/perf/subst.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/farfield.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/scene.h"

using namespace plumage;

namespace {

struct DoveTables {
  std::vector<FarfieldGeometry> geometries;
  HairParams material;
};

const DoveTables& dove_tables() {
  static const DoveTables t = [] {
    const Feather f = build_feather(load_preset("rock-dove-wing"), 1, "preset:rock-dove-wing");
    // The scene's transmittance tables come from the in-memory model store; only
    // the geometries are wanted here.
    const Scene scene(f, SceneOptions{ShadingMode::Farfield, {true, glm::vec3(0.8f)}});
    DoveTables d;
    for (VaneSide side : {VaneSide::Left, VaneSide::Right})
      for (const FarfieldGeometry& g : scene.farfield_geometries(side)) d.geometries.push_back(g);
    d.material = view_material(f, ViewSpec{}, ShadingMode::Farfield).at(scene.feather_bounds().centre());
    return d;
  }();
  return t;
}

// state.range(0): 0 transmittance tables only, 1 transmittance and BSDF tables.
void BM_FarfieldFitRockDove(benchmark::State& state) {
  const DoveTables& d = dove_tables();
  const FarfieldFitSettings s;  // the defaults renders use
  double rays = 0, paths = 0, noise = 0;
  for (auto _ : state) {
    rays = paths = noise = 0;
    for (const FarfieldGeometry& g : d.geometries) {
      const FarfieldModel t = measure_farfield(g, nullptr, s);
      benchmark::DoNotOptimize(t.T.data());
      if (state.range(0) == 0) continue;
      const FarfieldModel m = measure_farfield(g, &d.material, s);
      rays += double(m.report.rays);
      paths += double(m.report.paths);
      noise = std::max(noise, m.report.noise);
    }
  }
  state.counters["tables"] = double(d.geometries.size() * (state.range(0) ? 2 : 1));
  state.counters["rays_per_path"] = paths > 0 ? rays / paths : 0;
  state.counters["noise_worst"] = noise;
}
BENCHMARK(BM_FarfieldFitRockDove)->ArgName("bsdf")->DenseRange(0, 1)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
