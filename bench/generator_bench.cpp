// Procedural feather generation (issue 3 target: a 600-barb feather in <= 20 ms
// on the 2-core reference VM). Results: docs/perf/gen.md.
#include <benchmark/benchmark.h>

#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/generator/preview.h"

namespace {

// The osprey preset with 300 barbs per side: every feature on (bend, arch,
// cupping, twist, afterfeather, splits, jitter).
plumage::FeatherParams params_600() {
  plumage::FeatherParams p = plumage::load_preset("osprey-wing-covert");
  p.left.barbs = p.right.barbs = 300;
  return p;
}

void BM_GenerateFeather600(benchmark::State& state) {
  const plumage::FeatherParams p = params_600();
  std::uint64_t seed = 1;
  for (auto _ : state) benchmark::DoNotOptimize(plumage::build_feather(p, seed++));
  state.SetItemsProcessed(state.iterations() * 600);  // barbs
}
BENCHMARK(BM_GenerateFeather600)->Unit(benchmark::kMillisecond);

void BM_Preview600(benchmark::State& state) {
  const plumage::Feather f = plumage::build_feather(params_600(), 1);
  for (auto _ : state) benchmark::DoNotOptimize(plumage::render_preview(f, {1024, true}));
}
BENCHMARK(BM_Preview600)->Unit(benchmark::kMillisecond);

}  // namespace
