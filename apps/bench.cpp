// `plumage bench`: run time against error (issue 7). Renders a high-sample
// reference per shading mode, then a ladder of sample counts with another seed;
// writes a CSV and a log-log plot of RMSE against seconds, and fails when a mode's
// error stops falling (docs/benchladder.md).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "command.h"
#include "option_checks.h"
#include "view_options.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/renderer/error_ladder.h"

namespace plumage::cli {
namespace {

struct Options {
  std::string input, preset = "rock-dove-wing";
  std::uint64_t preset_seed = 1;
  std::string csv = "benchladder.csv", plot = "benchladder.png";
  ViewOptions view{"48x72", "WIDTHxHEIGHT, e.g. 48x72"};  // size, depth, LEDs, rig, card, threads
  std::string spp = "1,2,4,8,16,32,64,128,256";
  std::string modes = "hair,substructure";
  int reference_spp = 4096;
  std::uint64_t seed = 1, reference_seed = 0x5eed5eedull;
  int repeats = 1;
  double max_slope = -0.3;
  std::string reference_mode;  // accuracy study: one reference in this mode for every mode
  std::string zoom;            // X,Y,H: top-down orthographic view H mm high centred on (X, Y)
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(item);
  return out;
}

int run_bench(const Options& o) {
  if (o.csv.empty() || o.plot.empty()) throw UsageError(std::string(o.csv.empty() ? "--csv" : "--plot") + " is empty: give a file name");
  if (o.seed == o.reference_seed)
    throw UsageError("--seed and --reference-seed are both " + std::to_string(o.seed) +
                     ": the reference's noise must not be the ladder's");
  ViewSpec view;
  parse_resolution(o.view.resolution, view.width, view.height);  // resolution() checked it
  view.seed = o.seed;
  view.max_depth = o.view.max_depth;
  view.lights = o.view.lights;
  view.threads = o.view.threads;
  if (!o.zoom.empty()) {
    const auto v = parse_numbers(o.zoom, "--zoom");  // number_list({3}) checked it
    if (!(v[2] > 0)) throw UsageError("--zoom '" + o.zoom + "': the visible height H must be above 0");
    view.camera.projection = Projection::Orthographic;
    view.camera.position = glm::vec3(v[0], v[1], 100.0f);
    view.camera.look_at = glm::vec3(v[0], v[1], 0.0f);
    view.camera.ortho_height = v[2];
  }
  view.light_pick = parse_light_pick(o.view.light_pick);
  view.allocation = parse_sample_allocation(o.view.allocation);

  LadderSpec spec;
  spec.spp.clear();
  for (const std::string& s : split(o.spp)) spec.spp.push_back(std::stoi(s));  // whole_number_list checked them
  if (o.reference_spp < 4 * *std::max_element(spec.spp.begin(), spec.spp.end()))
    throw UsageError("--reference-spp " + std::to_string(o.reference_spp) + " is below 4x the top rung of --spp");
  spec.modes.clear();
  for (const std::string& m : split(o.modes)) spec.modes.push_back(parse_shading_mode(m));
  spec.reference_spp = o.reference_spp;
  spec.reference_seed = o.reference_seed;
  spec.repeats = o.repeats;
  if (!o.reference_mode.empty()) spec.reference_mode = parse_shading_mode(o.reference_mode);
  spec.backdrop = o.view.scene_options(view, DomeRig{}).backdrop;

  const DomeRig rig = o.view.read_rig();
  Feather feather;
  if (!o.input.empty()) {
    feather = read_fcurves(o.input);
    view.base_dir = std::filesystem::path(o.input).parent_path();
  } else {
    feather = build_feather(load_preset(o.preset), o.preset_seed, "preset:" + o.preset);
  }

  const std::vector<LadderPoint> points = run_ladder(feather, rig, view, spec);
  FileBatch outputs;  // the table and its plot: both or neither
  outputs.stage_text(o.csv, ladder_csv(points));
  write_image(outputs, o.plot, plot_ladder(points));
  outputs.commit();
  if (!global_options().quiet) {
    std::cout << ladder_csv(points);
    for (ShadingMode m : spec.modes)
      std::cout << to_string(m) << ": upper-half slope of log RMSE vs log seconds = "
                << upper_half_slope(points, to_string(m)) << "\n";
    if (spec.reference_mode)
      std::cout << "errors are against one " << to_string(*spec.reference_mode)
                << " reference: they level off at each mode's model error, so the slope check is skipped\n";
    std::cout << "wrote " << o.csv << " and " << o.plot << "\n";
  }
  if (spec.reference_mode) return 0;
  const std::vector<std::string> bad = biased_modes(points, o.max_slope);
  if (!bad.empty()) {
    std::cerr << "plumage bench: FAIL: error stops falling with time (bias?) for\n";
    for (const std::string& b : bad) std::cerr << "  " << b << " (must be <= " << o.max_slope << ")\n";
    std::cerr << "Unbiased Monte Carlo gives about -0.5; look for a deterministic error, or raise --reference-spp.\n";
    return 1;
  }
  return 0;
}

const Registration kBench{
    "bench", "Run time against error: a sample-count ladder per shading mode against a high-sample reference",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.footer(
          "Writes a CSV (mode,spp,seconds,rmse,relative_mse,cpu_seconds) and a log-log plot of RMSE against seconds.\n"
          "Exits 1 when a mode's slope over the upper half of the ladder is above --max-slope.\n"
          "Example: plumage bench --preset rock-dove-wing --csv ladder.csv --plot ladder.png\n"
          "See docs/benchladder.md.");
      sub.add_option("input", o->input, "Feather curve file (.fcurves); default: the --preset");
      sub.add_option("--preset", o->preset, "Generator preset to render when no input is given")->capture_default_str();
      sub.add_option("--preset-seed", o->preset_seed, "Generator seed for the preset")->capture_default_str();
      sub.add_option("--csv", o->csv, "CSV output")->capture_default_str();
      sub.add_option("--plot", o->plot, "Plot output (.png)")->capture_default_str();
      using Opt = ViewOptions::Opt;
      o->view.add(sub, Opt::Resolution);
      sub.add_option("--spp", o->spp, "Ladder of sample counts, comma separated")
          ->capture_default_str()
          ->check(whole_number_list(1, kMaxSpp));
      sub.add_option("--modes", o->modes, "Shading modes, comma separated")
          ->capture_default_str()
          ->check(comma_list(one_of(kShadingModes)));
      sub.add_option("--reference-spp", o->reference_spp, "Samples per pixel of the reference (>= 4x the top rung)")->capture_default_str()->check(in_range(1, kMaxSpp));
      sub.add_option("--seed", o->seed, "Seed of the ladder")->capture_default_str();
      sub.add_option("--reference-seed", o->reference_seed, "Seed of the reference (must differ from --seed)")->capture_default_str();
      sub.add_option("--repeats", o->repeats, "Renders per rung; the fastest time counts")->capture_default_str()->check(in_range(1, 1000));
      for (Opt opt : {Opt::MaxDepth, Opt::Lights, Opt::Rig, Opt::LightPick, Opt::Allocation, Opt::Backdrop, Opt::Threads})
        o->view.add(sub, opt);
      sub.add_option("--max-slope", o->max_slope, "Fail when a mode's upper-half slope is above this")->capture_default_str();
      sub.add_option("--reference-mode", o->reference_mode,
                     "Accuracy study: one reference in this mode (e.g. explicit) for every mode; no slope check")
          ->check(one_of(kShadingModes));
      sub.add_option("--zoom", o->zoom, "X,Y,H: top-down orthographic view H mm high centred on (X, Y) mm")
          ->check(number_list({3}));
      return [o] { return run_bench(*o); };
    }};

}  // namespace
}  // namespace plumage::cli
