// The medulla's cost (issue 33; docs/hair-bcsdf.md, "The medulla"): time per camera
// sample of the rock-dove preset under the 25-LED dome (one thread, 64 x 64 x 4 spp,
// the close view of explicit_bench.cpp) in hair and substructure mode, with clear
// fibres and with every fibre given the photo inversion's medulla (ratio 0.7,
// sigma_s 4 per radius); and the BCSDF alone (f, sample) both ways. Results:
// docs/perf/bcsdf.md, "The medulla's cost".
#include <benchmark/benchmark.h>

#include <filesystem>
#include <random>
#include <vector>

#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/card_response.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/hair_bcsdf.h"

using namespace plumage;

namespace {

const Feather& rock_dove() {
  static const Feather f = build_feather(load_preset("rock-dove-wing"), 1, "preset:rock-dove-wing");
  return f;
}

HairParams fibre(bool medulla) {
  HairParams p;
  p.sigma_a = glm::vec3(0.2f, 0.4f, 0.8f);
  if (medulla) {
    p.medulla_ratio = kPhotoMedullaRatio;
    p.medulla_sigma_s = glm::vec3(4.0f);
  }
  return p;
}

// state.range(0): 0 hair, 1 substructure; range(1): 0 clear fibres, 1 with a medulla.
void BM_MedullaRenderSample(benchmark::State& state) {
  static const DomeRig rig = read_dome_rig(std::filesystem::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  const ShadingMode mode = state.range(0) ? ShadingMode::Substructure : ShadingMode::Hair;
  const Scene scene(rock_dove(), SceneOptions{mode, {true, glm::vec3(0.8f)}});
  ViewSpec view;
  view.width = view.height = 64;
  view.spp = 4;
  view.threads = 1;
  view.hair = fibre(state.range(1) != 0);
  view.camera.position = glm::vec3(10.0f, 60.0f, 8.0f);
  view.camera.look_at = glm::vec3(10.0f, 60.0f, 0.0f);
  for (auto _ : state) benchmark::DoNotOptimize(render_view(scene, rig, view));
  const double samples = double(view.width) * view.height * view.spp;
  state.counters["us_per_sample"] =
      benchmark::Counter(samples * 1e-6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_MedullaRenderSample)
    ->ArgNames({"substructure", "medulla"})
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

struct Inputs {
  std::vector<float> h;
  std::vector<glm::vec3> wo, wi;
  std::vector<glm::vec2> u0, u1;
};
const Inputs& inputs() {
  static const Inputs in = [] {
    Inputs r;
    std::mt19937 rng(33);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const auto dir = [&] {
      const float x = 2 * u(rng) - 1, phi = 6.2831853f * u(rng), c = std::sqrt(1 - x * x);
      return glm::vec3(x, c * std::sin(phi), c * std::cos(phi));
    };
    for (int i = 0; i < 1024; ++i) {
      r.h.push_back(2 * u(rng) - 1);
      r.wo.push_back(dir());
      r.wi.push_back(dir());
      r.u0.push_back({u(rng), u(rng)});
      r.u1.push_back({u(rng), u(rng)});
    }
    return r;
  }();
  return in;
}

// range(0): 0 clear, 1 medulla. One construction (for wo) and one call per input.
template <class Call>
void bcsdf_calls(benchmark::State& state, Call&& call) {
  const HairParams p = fibre(state.range(0) != 0);
  const Inputs& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    const HairBCSDF b(p, in.h[i], in.wo[i]);
    benchmark::DoNotOptimize(call(b, in, i));
    i = (i + 1) & 1023;
  }
}

void BM_MedullaBCSDF_F(benchmark::State& state) {
  bcsdf_calls(state, [](const HairBCSDF& b, const Inputs& in, std::size_t i) { return b.f(in.wo[i], in.wi[i]); });
}
BENCHMARK(BM_MedullaBCSDF_F)->ArgName("medulla")->DenseRange(0, 1);

void BM_MedullaBCSDF_Sample(benchmark::State& state) {
  bcsdf_calls(state, [](const HairBCSDF& b, const Inputs& in, std::size_t i) { return b.sample(in.wo[i], in.u0[i], in.u1[i]); });
}
BENCHMARK(BM_MedullaBCSDF_Sample)->ArgName("medulla")->DenseRange(0, 1);

}  // namespace
