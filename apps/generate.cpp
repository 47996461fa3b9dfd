// `plumage generate`: species preset or params JSON -> feather.fcurves (+ preview).
#include <iostream>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "command.h"
#include "option_checks.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/common/text.h"
#include "plumage/layout/layout.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/generator/presets.h"
#include "plumage/generator/preview.h"
#include "plumage/pipeline/photo_comparison.h"

namespace plumage::cli {
namespace {

struct GenerateArgs {
  std::string preset, params, layout, output, preview;
  std::optional<int> feather;
  std::uint64_t seed = 1;
  int preview_size = 1024;
  bool list_presets = false, print_params = false;
  bool more_than_list = false;  // options beside --list-presets
};

// What the command line asks must be something generate can do, before any file is read.
void check_usage(const GenerateArgs& a, bool anything_else) {
  if (a.list_presets) {
    if (anything_else) throw UsageError("--list-presets lists the presets and takes no other option");
    return;
  }
  if (a.preset.empty() && a.params.empty() && a.layout.empty())
    throw UsageError("give --preset NAME (--list-presets names them), --params FILE or --layout layout.json");
  if (a.output.empty() && !a.print_params) throw UsageError("no output file: give -o feather.fcurves");
  if (!a.output.empty() && std::filesystem::path(a.output).extension() != ".fcurves")
    throw UsageError("-o " + a.output + ": the output must be a .fcurves file; convert it afterwards with `plumage export`");
  if (a.output.empty() && !a.preview.empty()) throw UsageError("--preview draws the curves written to -o: give -o too");
}

// "N barbs (left L, right R)", and how many of them are down barbs when any are.
std::string barbs_text(const Feather& f) {
  const std::size_t down = f.count(CurveKind::Down);
  std::string t = std::to_string(f.count(CurveKind::Barb) + down) + " barbs (left " +
                  std::to_string(f.count(VaneSide::Left)) + ", right " + std::to_string(f.count(VaneSide::Right));
  if (down) t += "; " + std::to_string(down) + " of them down";
  return t + ")";
}

// The feather a layout.json describes (docs/layout-format.md), its albedo texture
// referenced relative to the curve file.
int run_generate_from_layout(const GenerateArgs& a) {
  const Layout layout = read_layout(a.layout);
  const FeatherLayout& f = pick_feather(layout, a.feather, a.layout);
  if (a.print_params) {  // what the layout gives the generator, repairs included
    std::cout << json_text(params_to_json(layout_to_params(f, a.layout).params), 2) << "\n";
    if (a.output.empty()) return 0;
  }
  std::vector<std::string> warnings;
  FileBatch outputs;  // the curves, their albedo texture and the preview: all or none
  const Feather feather =
      generate_from_layout(f, a.seed, a.layout, a.output, a.preview, a.preview_size, outputs, &warnings);
  outputs.commit();
  for (const auto& w : warnings) std::cerr << "warning: " << a.layout << ": feather " << f.id << ": " << w << "\n";
  if (!global_options().quiet) {
    std::cout << "wrote " << a.output << ": feather " << f.id << " of " << a.layout << " (seed " << a.seed
              << "), 1 shaft + " << barbs_text(feather) << "\n";
    if (!a.preview.empty()) std::cout << "wrote " << a.preview << " (top view)\n";
  }
  return 0;
}

int run_generate(const GenerateArgs& a) {
  if (a.list_presets) {  // check_usage made sure it is alone
    for (const auto& name : list_presets()) {
      try {
        std::cout << name << "\n    " << load_preset(name).description << "\n";
      } catch (const Error& e) {  // one broken file should not hide the others
        std::cout << name << "\n    (invalid: " << e.what() << ")\n";
      }
    }
    return 0;
  }
  if (!a.layout.empty()) return run_generate_from_layout(a);

  const FeatherParams params = a.preset.empty() ? read_params(a.params) : load_preset(a.preset);
  if (a.print_params) {
    std::cout << json_text(params_to_json(params), 2) << "\n";
    if (a.output.empty()) return 0;
  }

  const std::string source = a.preset.empty() ? "params:" + a.params : "preset:" + a.preset;
  const Feather feather = build_feather(params, a.seed, source);
  validate_feather(feather);
  FileBatch outputs;  // the curves and the preview: both or neither
  write_fcurves(outputs, a.output, feather);
  if (!a.preview.empty()) write_image(outputs, a.preview, render_preview(feather, PreviewOptions{a.preview_size, true}));
  outputs.commit();

  if (!global_options().quiet) {
    std::cout << "wrote " << a.output << ": " << params.name << " (seed " << a.seed << "), 1 shaft + "
              << barbs_text(feather) << ", " << feather.num_control_points() << " control points\n";
    if (!a.preview.empty()) std::cout << "wrote " << a.preview << " (top view)\n";
  }
  return 0;
}

const Registration reg{
    "generate",
    "Build a procedural feather (OpenSubdiv vane, B-spline shaft and barbs) from a species preset or a "
    "params JSON and write it as .fcurves",
    [](CLI::App& sub) {
      auto a = std::make_shared<GenerateArgs>();
      sub.footer(
          "Examples:\n"
          "  plumage generate --preset osprey-wing-covert --seed 1 -o feather.fcurves --preview preview.png\n"
          "  plumage generate --preset rock-dove-wing --print-params > my.json   (start a custom feather)\n"
          "  plumage generate --params my.json --seed 7 -o my.fcurves\n"
          "  plumage generate --layout layout.json --feather 2 -o photo.fcurves   (from `plumage analyze`)\n"
          "Parameters, units and ranges: docs/generator.md; preset sources: docs/presets.md.");
      auto* preset = sub.add_option("--preset", a->preset, "Species preset by name (--list-presets)");
      auto* params = sub.add_option("--params", a->params, "Feather parameters JSON file (docs/generator.md)");
      auto* layout = sub.add_option("--layout", a->layout, "Analysis layout.json from `plumage analyze` (docs/layout-format.md)");
      sub.add_option("--feather", a->feather, "With --layout: which feather (its id, F<id> on the overlay; default the first)")
          ->check(in_range(1, 1e6))
          ->needs(layout);
      preset->excludes(params)->excludes(layout);
      params->excludes(layout);
      sub.add_option("--seed", a->seed, "Random seed: same seed, same feather (default 1)");
      sub.add_option("-o,--output", a->output, "Output .fcurves file (written atomically)");
      sub.add_option("--preview", a->preview, "Also write a top-view image of the curves (.png, .jpg, .exr)");
      auto* preview = sub.get_option("--preview");
      sub.add_option("--preview-size", a->preview_size, "Preview size in pixels along the longer side (default 1024)")
          ->check(in_range(16, 16384))
          ->needs(preview);
      sub.add_flag("--list-presets", a->list_presets, "List the species presets and exit");
      sub.add_flag("--print-params", a->print_params, "Print the resolved parameters as JSON");
      // While the options exist (the command runs after they are gone): was
      // anything but --list-presets given? (+1: count_all counts the subcommand.)
      sub.parse_complete_callback([a, &sub] { a->more_than_list = sub.count_all() > sub.count("--list-presets") + 1; });
      return [a] {
        check_usage(*a, a->more_than_list);
        return run_generate(*a);
      };
    }};

}  // namespace
}  // namespace plumage::cli
