// Reading and writing .fcurves (and the exporters) for a 1,000-barb feather with
// about 10,000 control points (issue 2). Figures: docs/perf/fcurves.md.
#include <benchmark/benchmark.h>

#include "../tests/feather_samples.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/exporters.h"

namespace {

const plumage::Feather& thousand_barbs() {
  static const plumage::Feather f = plumage::samples::sample_feather(1000, 10);
  return f;
}

void BM_FormatFcurves(benchmark::State& state) {
  const plumage::Feather& f = thousand_barbs();
  std::size_t bytes = 0;
  for (auto _ : state) {
    std::string text = plumage::format_fcurves(f);
    bytes = text.size();
    benchmark::DoNotOptimize(text.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
  state.counters["control_points"] = double(f.num_control_points());
}
BENCHMARK(BM_FormatFcurves)->Unit(benchmark::kMillisecond);

void BM_ParseFcurves(benchmark::State& state) {
  const std::string text = plumage::format_fcurves(thousand_barbs());
  for (auto _ : state) {
    plumage::Feather f = plumage::parse_fcurves(text);
    benchmark::DoNotOptimize(f.curves.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text.size()));
  state.counters["file_bytes"] = double(text.size());
}
BENCHMARK(BM_ParseFcurves)->Unit(benchmark::kMillisecond);

void BM_Export(benchmark::State& state) {
  const auto format = static_cast<plumage::ExportFormat>(state.range(0));
  state.SetLabel(plumage::to_string(format));
  const plumage::Feather& f = thousand_barbs();
  std::size_t bytes = 0;
  for (auto _ : state) {
    std::string text = plumage::export_text(f, format, plumage::ExportScene{});
    bytes = text.size();
    benchmark::DoNotOptimize(text.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
}
BENCHMARK(BM_Export)
    ->Arg(int(plumage::ExportFormat::Pbrt))
    ->Arg(int(plumage::ExportFormat::Mitsuba))
    ->Arg(int(plumage::ExportFormat::Obj))
    ->Unit(benchmark::kMillisecond);

}  // namespace
