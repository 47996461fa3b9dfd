// Cost of one hair BCSDF call (f, pdf, sample) and of building the per-hit BCSDF,
// over a fixed table of random fibre offsets and directions. Figures: docs/perf/bcsdf.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "plumage/renderer/hair_bcsdf.h"

namespace {

struct Input {
  float h;
  glm::vec3 wo, wi;
  glm::vec2 u0, u1;
};

// A fixed table so every run measures the same work (LCG; quality is irrelevant here).
const std::vector<Input>& inputs() {
  static const std::vector<Input> table = [] {
    std::vector<Input> t(4096);
    uint32_t s = 12345u;
    const auto u = [&] {
      s = s * 1664525u + 1013904223u;
      return float(s >> 8) * 0x1.0p-24f;
    };
    const auto dir = [&] {
      const float x = 2 * u() - 1, phi = 2 * std::numbers::pi_v<float> * u();
      const float c = std::sqrt(1 - x * x);
      return glm::vec3(x, c * std::sin(phi), c * std::cos(phi));
    };
    for (Input& in : t) in = {2 * u() - 1, dir(), dir(), {u(), u()}, {u(), u()}};
    return t;
  }();
  return table;
}

plumage::HairParams brown_hair() {
  plumage::HairParams p;
  p.beta_m = 0.3f;
  p.beta_n = 0.3f;
  p.sigma_a = plumage::sigma_a_from_melanin(1.3f, 0.2f);
  return p;
}

void BM_HairBCSDF_Construct(benchmark::State& state) {
  const auto& in = inputs();
  const plumage::HairParams p = brown_hair();
  size_t k = 0;
  for (auto _ : state) {
    plumage::HairBCSDF b(p, in[k++ & 4095].h);
    benchmark::DoNotOptimize(b);
  }
}
BENCHMARK(BM_HairBCSDF_Construct);

void BM_HairBCSDF_F(benchmark::State& state) {
  const auto& in = inputs();
  const plumage::HairBCSDF b(brown_hair(), 0.3f);
  size_t k = 0;
  for (auto _ : state) {
    const Input& x = in[k++ & 4095];
    benchmark::DoNotOptimize(b.f(x.wo, x.wi));
  }
}
BENCHMARK(BM_HairBCSDF_F);

void BM_HairBCSDF_Pdf(benchmark::State& state) {
  const auto& in = inputs();
  const plumage::HairBCSDF b(brown_hair(), 0.3f);
  size_t k = 0;
  for (auto _ : state) {
    const Input& x = in[k++ & 4095];
    benchmark::DoNotOptimize(b.pdf(x.wo, x.wi));
  }
}
BENCHMARK(BM_HairBCSDF_Pdf);

void BM_HairBCSDF_Sample(benchmark::State& state) {
  const auto& in = inputs();
  const plumage::HairBCSDF b(brown_hair(), 0.3f);
  size_t k = 0;
  for (auto _ : state) {
    const Input& x = in[k++ & 4095];
    benchmark::DoNotOptimize(b.sample(x.wo, x.u0, x.u1));
  }
}
BENCHMARK(BM_HairBCSDF_Sample);

}  // namespace
