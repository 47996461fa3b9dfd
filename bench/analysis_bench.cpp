// Photo analysis speed (issue 6 aims: the 1920x623 pink feather photo <= 1 s,
// a 12-megapixel photo <= 4 s). Times analyze_photo: decode plus analysis,
// without writing the outputs.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "shared_photos.h"

#include "../tests/synthetic_feather.h"
#include "plumage/analysis/analyze.h"

namespace fs = std::filesystem;
using namespace plumage;

static void BM_AnalyzePinkFeatherPhoto(benchmark::State& state) {
  const auto found = bench::shared_photo(state, "pink-contour-feather.jpg");
  if (!found) return;
  const fs::path photo = *found;
  for (auto _ : state) benchmark::DoNotOptimize(analyze_photo(photo, AnalyzeOptions{}));
}
BENCHMARK(BM_AnalyzePinkFeatherPhoto)->Unit(benchmark::kMillisecond)->Iterations(3);

static void BM_AnalyzeSynthetic12MP(benchmark::State& state) {
  const fs::path photo = fs::temp_directory_path() / "plumage_bench_12mp.png";
  if (!fs::exists(photo)) {
    synthetic::SyntheticFeather F;
    F.width = 4000, F.height = 3000;
    F.calamus = {1100, 2850};
    F.length = 2600, F.w_left = 280, F.w_right = 420, F.shaft_width = 18, F.spacing = 30;
    write_image(photo, F.draw());
  }
  AnalyzeOptions opt;
  opt.mm_per_px = 0.05;
  for (auto _ : state) benchmark::DoNotOptimize(analyze_photo(photo, opt));
}
BENCHMARK(BM_AnalyzeSynthetic12MP)->Unit(benchmark::kMillisecond)->Iterations(2);

// Issue 11 aim: a 1500x1056 sheet of many feathers (the blue-jay sheet: 52 regions,
// 46 analysed) in <= 1.5 s on 2 cores. Decode plus analysis, no writing.
static void BM_AnalyzeBlueJaySheet(benchmark::State& state) {
  const auto found = bench::shared_photo(state, "blue-jay-feather-sheet.jpg");
  if (!found) return;
  const fs::path photo = *found;
  for (auto _ : state) benchmark::DoNotOptimize(analyze_photo(photo, AnalyzeOptions{}));
}
BENCHMARK(BM_AnalyzeBlueJaySheet)->Unit(benchmark::kMillisecond)->Iterations(3);
