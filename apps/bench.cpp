// `plumage bench`: run time against error (issue 7). Renders a high-sample
// reference per shading mode, then a ladder of sample counts with another seed;
// writes a CSV and a log-log plot of RMSE against seconds, and fails when a mode's
// error stops falling (docs/benchladder.md).
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "command.h"
#include "option_checks.h"
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
  std::string resolution = "48x72";
  std::string spp = "1,2,4,8,16,32,64,128,256";
  std::string modes = "hair,substructure";
  int reference_spp = 4096;
  std::uint64_t seed = 1, reference_seed = 0x5eed5eedull;
  int max_depth = 16, threads = 0, repeats = 1;
  std::string lights = "all";
  std::string rig = std::string(PLUMAGE_DATA_DIR) + "/rigs/dome25.json";
  std::string backdrop = "white";
  std::string light_pick = to_string(IntegratorSettings{}.light_pick);
  std::string allocation = to_string(RenderSettings{}.allocation);
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
  ViewSpec view;
  {
    char x = 0;
    std::stringstream ss(o.resolution);
    if (!(ss >> view.width >> x >> view.height) || x != 'x' || !ss.eof())
      throw Error("--resolution '" + o.resolution + "': give WIDTHxHEIGHT, e.g. 48x72");
  }
  if (o.max_depth < 0) throw Error("--max-depth must be 0 or more");
  view.seed = o.seed;
  view.max_depth = o.max_depth;
  view.lights = o.lights;
  view.threads = o.threads;
  if (!o.zoom.empty()) {
    float x = 0, y = 0, h = 0;
    char c1 = 0, c2 = 0;
    std::stringstream ss(o.zoom);
    if (!(ss >> x >> c1 >> y >> c2 >> h) || c1 != ',' || c2 != ',' || !ss.eof() || !(h > 0))
      throw Error("--zoom '" + o.zoom + "': give X,Y,H in mm (centre of the view, visible height > 0), e.g. 10,60,1");
    view.camera.projection = Projection::Orthographic;
    view.camera.position = glm::vec3(x, y, 100.0f);
    view.camera.look_at = glm::vec3(x, y, 0.0f);
    view.camera.ortho_height = h;
  }
  view.light_pick = parse_light_pick(o.light_pick);
  view.allocation = parse_sample_allocation(o.allocation);

  LadderSpec spec;
  spec.spp.clear();
  for (const std::string& s : split(o.spp)) {
    std::size_t used = 0;
    int n = 0;
    try {
      n = std::stoi(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || n < 1) throw Error("--spp '" + o.spp + "': give positive integers separated by commas");
    spec.spp.push_back(n);
  }
  spec.modes.clear();
  for (const std::string& m : split(o.modes)) spec.modes.push_back(parse_shading_mode(m));
  spec.reference_spp = o.reference_spp;
  spec.reference_seed = o.reference_seed;
  spec.repeats = o.repeats;
  if (!o.reference_mode.empty()) spec.reference_mode = parse_shading_mode(o.reference_mode);
  if (o.backdrop == "white") spec.backdrop = {true, glm::vec3(0.8f)};
  else if (o.backdrop == "black") spec.backdrop = {true, glm::vec3(0.03f)};
  else if (o.backdrop == "none") spec.backdrop = {};
  else throw Error("--backdrop '" + o.backdrop + "': use white, black or none");

  Feather feather;
  if (!o.input.empty()) {
    feather = read_fcurves(o.input);
    view.base_dir = std::filesystem::path(o.input).parent_path();
  } else {
    feather = build_feather(load_preset(o.preset), o.preset_seed, "preset:" + o.preset);
  }
  const DomeRig rig = read_dome_rig(o.rig);

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
      sub.add_option("--resolution", o->resolution, "Image size WIDTHxHEIGHT")->capture_default_str()->check(cli::resolution());
      sub.add_option("--spp", o->spp, "Ladder of sample counts, comma separated")->capture_default_str();
      sub.add_option("--modes", o->modes, "Shading modes, comma separated")->capture_default_str();
      sub.add_option("--reference-spp", o->reference_spp, "Samples per pixel of the reference (>= 4x the top rung)")->capture_default_str()->check(in_range(1, kMaxSpp));
      sub.add_option("--seed", o->seed, "Seed of the ladder")->capture_default_str();
      sub.add_option("--reference-seed", o->reference_seed, "Seed of the reference (must differ from --seed)")->capture_default_str();
      sub.add_option("--repeats", o->repeats, "Renders per rung; the fastest time counts")->capture_default_str()->check(in_range(1, 1000));
      sub.add_option("--max-depth", o->max_depth, "Maximum scattering events per path")->capture_default_str()->check(in_range(0, 1024));
      sub.add_option("--lights", o->lights, "Dome LEDs that are on")->capture_default_str();
      sub.add_option("--rig", o->rig, "Light rig JSON file")->capture_default_str();
      sub.add_option("--light-pick", o->light_pick, "Next-event estimation's light choice: uniform, estimate or all")
          ->capture_default_str()
          ->check(one_of(kLightPicks));
      sub.add_option("--allocation", o->allocation, "Samples over pixels: variance or uniform (docs/skip-work.md)")
          ->capture_default_str()
          ->check(one_of(kSampleAllocations));
      sub.add_option("--backdrop", o->backdrop, "Card under the feather: white, black or none")->capture_default_str()->check(one_of({"white", "black", "none"}));
      sub.add_option("--threads", o->threads, "Worker threads (0 = all cores)")->capture_default_str()->check(in_range(0, kMaxThreads));
      sub.add_option("--max-slope", o->max_slope, "Fail when a mode's upper-half slope is above this")->capture_default_str();
      sub.add_option("--reference-mode", o->reference_mode,
                     "Accuracy study: one reference in this mode (e.g. explicit) for every mode; no slope check")
          ->check(one_of(kShadingModes));
      sub.add_option("--zoom", o->zoom, "X,Y,H: top-down orthographic view H mm high centred on (X, Y) mm");
      return [o] { return run_bench(*o); };
    }};

}  // namespace
}  // namespace plumage::cli
