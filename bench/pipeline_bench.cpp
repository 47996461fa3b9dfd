// The photo-to-feather chain (apps/pipeline) on the pink photo at the command's
// defaults — analyze, generate (closed vanes), crop, both renders at 672x240 and
// 8 spp, fidelity — and the fidelity metrics alone on panels of that size
// (issue 12: the whole command within 20 s on 2 cores; docs/perf/p2f.md).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "shared_photos.h"

#include "plumage/common/atomic_file.h"
#include "plumage/analysis/analyze.h"
#include "plumage/pipeline/photo_comparison.h"

namespace fs = std::filesystem;
using namespace plumage;

static void BM_PhotoToFeatherPink(benchmark::State& state) {
  const auto found = bench::shared_photo(state, "pink-contour-feather.jpg");
  if (!found) return;
  const fs::path photo = *found;
  const fs::path dir = fs::temp_directory_path() / "plumage_bench_p2f";
  fs::create_directories(dir);
  const DomeRig rig = read_dome_rig(fs::path(PLUMAGE_DATA_DIR) / "rigs" / "dome25.json");
  double iou = 0;
  for (auto _ : state) {
    PhotoAnalysis a = analyze_photo(photo, AnalyzeOptions{});
    write_analysis(a, dir / "layout.json");
    FileBatch outputs;
    std::vector<std::string> warnings;
    const Feather feather = generate_from_layout(a.layout.feathers.front(), 1, dir / "layout.json",
                                                 dir / "feather.fcurves", dir / "preview.png", 1024, outputs, &warnings);
    outputs.commit();
    ViewSpec view;
    view.spp = 8;
    view.seed = 1;
    view.threads = int(state.range(0));
    view.base_dir = dir;
    const PhotoComparison c =
        compare_with_photo(read_image(photo), a.layout, a.layout.feathers.front(), feather, rig, view, 672);
    iou = c.fidelity.at(1).feather.iou;
  }
  state.counters["substructure_iou"] = iou;
  fs::remove_all(dir);
}
BENCHMARK(BM_PhotoToFeatherPink)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

static void BM_FidelityMetrics(benchmark::State& state) {
  const int w = 672, h = 240;
  Image photo(w, h, 3, 0.9f), render(w, h, 3, 0.9f);
  PanelRegions regions;
  regions.width = w, regions.height = h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool in = std::abs(y - h / 2) < h / 4 && x > w / 8 && x < 7 * w / 8;
      if (in) photo.set_rgb(x, y, {0.9f, 0.4f, 0.4f}), render.set_rgb(x, y, {0.85f, 0.45f, 0.45f});
      regions.side.push_back(std::abs(y - h / 2) < h / 3 ? (y < h / 2 ? 1 : 2) : 0);
    }
  for (auto _ : state) {
    const MeasuredPanel p = measure_panel(photo, regions, {}), r = measure_panel(render, regions, {});
    benchmark::DoNotOptimize(compare_panels(p, r, regions));
  }
}
BENCHMARK(BM_FidelityMetrics)->Unit(benchmark::kMillisecond);
