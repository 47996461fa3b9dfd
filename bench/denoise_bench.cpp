// The non-local-means filter's cost (renderer/denoise.h, docs/rendering.md
// "Denoising") on a photo-to-feather panel's size: 672x240 RGB with noise of a
// known variance, at the default window (11x11) and patch (3x3), on 1 and 2 threads.
#include <benchmark/benchmark.h>

#include <random>

#include "plumage/renderer/denoise.h"

using namespace plumage;

static void BM_Denoise(benchmark::State& state) {
  constexpr int W = 672, H = 240;
  Image colour(W, H, 3), variance(W, H, 3, 0.03f * 0.03f);
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.03f);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float v = (x / 48 + y / 48) % 2 ? 0.7f : 0.3f;  // a checker of 48 px squares
      colour.set_rgb(x, y, {v + noise(rng), 0.8f * v + noise(rng), 0.6f * v + noise(rng)});
    }
  DenoiseSettings s;
  s.threads = int(state.range(0));
  for (auto _ : state) {
    const Image out = denoise(colour, variance, s);
    benchmark::DoNotOptimize(out.pixels.data());
  }
  state.counters["Mpixels_per_s"] =
      benchmark::Counter(double(W) * H * double(state.iterations()) / 1e6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Denoise)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
