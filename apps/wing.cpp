// `plumage wing`: a bird's wing as a .fscene of placed feathers (docs/wing.md),
// its distinct feathers written as .fcurves files beside it.
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "command.h"
#include "option_checks.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/common/progress.h"
#include "plumage/common/scene_format.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/layout/layout.h"
#include "plumage/generator/wing.h"

namespace plumage::cli {
namespace {

struct WingArgs {
  std::string output, preset = "rock-dove", layout;
  std::uint64_t seed = 1;
  double fold = 0;
  bool folded = false, pair = false, list = false;
};

// A key feather's colour from its analysed albedo texture: the mean of the texels
// inside the feather (albedo_mean), times the texture's scale. The photo's card is
// not inverted here (photo-to-feather's calibration, docs/analysis.md, does that).
std::optional<glm::vec3> texture_mean(const FeatherLayout& f, const std::filesystem::path& layout_dir) {
  if (f.albedo.file.empty()) return std::nullopt;
  const std::optional<glm::dvec3> mean = albedo_mean(read_image(layout_dir / f.albedo.file));
  if (!mean) return std::nullopt;
  return glm::vec3(*mean * f.albedo.scale);
}

int run_wing(const WingArgs& a) {
  if (a.list) {
    for (const std::string& p : wing_presets()) std::cout << p << "\n";
    return 0;
  }
  if (a.output.empty()) throw UsageError("no output file: give -o wing.fscene");
  const std::filesystem::path out(a.output);
  if (out.extension() != ".fscene") throw UsageError("-o " + a.output + ": the output is a scene, NAME.fscene");
  if (a.folded && a.fold != 0) throw UsageError("--folded is --fold 1; give one of them");
  WingOptions o;
  o.preset = a.preset;
  o.seed = a.seed;
  o.fold = a.folded ? 1.0 : a.fold;
  o.pair = a.pair;
  if (!a.layout.empty()) {
    const Layout layout = read_layout(a.layout);
    for (const FeatherLayout& f : layout.feathers) {
      try {
        FeatherParams key = layout_to_params(f, a.layout).params;
        const std::filesystem::path dir = std::filesystem::path(a.layout).parent_path();
        if (const auto colour = texture_mean(f, dir.empty() ? "." : dir)) key.albedo = *colour;
        o.keys.push_back(std::move(key));
      } catch (const Error& e) {
        std::cerr << "warning: " << a.layout << ": feather " << f.id << " is not a key feather: " << e.what() << "\n";
      }
    }
    if (o.keys.size() < 2)
      throw Error(a.layout + ": " + std::to_string(o.keys.size()) + " usable feathers; a wing needs at least 2 key feathers");
  }
  const Wing wing = build_wing(o);
  // The feathers go to NAME_feathers/ beside the scene: all files or none.
  const std::string folder = out.stem().string() + "_feathers";
  const std::filesystem::path dir = (out.parent_path().empty() ? std::filesystem::path(".") : out.parent_path()) / folder;
  const bool made_dir = std::filesystem::create_directory(dir);
  try {
    FileBatch batch;
    ProgressBar progress("Feathers", wing.feathers.size(), global_options().quiet);
    std::size_t barbs = 0;
    for (std::size_t i = 0; i < wing.feathers.size(); ++i) {
      const WingFeather& f = wing.feathers[i];
      const Feather feather = build_feather(f.params, a.seed * 1000 + i, "wing:" + a.preset + ":" + f.name);
      barbs += feather.count(CurveKind::Barb);
      write_fcurves(batch, dir / (f.name + ".fcurves"), feather);
      progress.advance();
    }
    progress.finish();
    batch.stage_text(out, format_fscene(wing_scene(wing, o, folder)));
    batch.commit();
    if (!global_options().quiet)
      std::cout << "wrote " << a.output << ": " << wing.description << "; " << wing.feathers.size()
                << " distinct feathers in " << (dir).string() << "/, " << (o.pair ? 2 : 1) * wing.feathers.size()
                << " placements, " << (o.pair ? 2 : 1) * barbs << " barbs over all placements\n";
  } catch (...) {
    std::error_code ec;
    if (made_dir) std::filesystem::remove(dir, ec);  // only if still empty
    throw;
  }
  return 0;
}

const Registration kWing{
    "wing", "Build a bird's wing (primaries, secondaries, two covert rows, spread or folded) as a .fscene of placed feathers",
    [](CLI::App& sub) {
      auto a = std::make_shared<WingArgs>();
      sub.footer(
          "Each feather's parameters are interpolated between key feathers along its row (Chen et al. 2002);\n"
          "the distinct feathers are written as .fcurves in NAME_feathers/ beside the scene, and --pair adds the\n"
          "other wing as the mirror image of the first, sharing the same feathers (instanced when rendered).\n"
          "Example: plumage wing -o wing.fscene --pair && plumage render wing.fscene -o wing.png --resolution 1280x720\n"
          "See docs/wing.md and docs/scene-format.md.");
      sub.add_option("-o,--output", a->output, "Output scene (.fscene)");
      sub.add_option("--preset", a->preset, "Wing preset (--list-presets)")->capture_default_str();
      sub.add_option("--seed", a->seed, "Seed of the feathers (feather i gets SEED x 1000 + i)")->capture_default_str();
      sub.add_option("--fold", a->fold, "0 spread .. 1 folded: how far the elbow and wrist are closed")
          ->capture_default_str()
          ->check(in_range(0, 1));
      sub.add_flag("--folded", a->folded, "The folded wing (--fold 1)");
      sub.add_flag("--pair", a->pair, "Add the left wing, the mirror image of the right sharing its feathers");
      sub.add_option("--layout", a->layout, "Take the key feathers from a sheet's analysed feathers (plumage analyze's layout.json)");
      sub.add_flag("--list-presets", a->list, "List the wing presets");
      return [a] { return run_wing(*a); };
    }};

}  // namespace
}  // namespace plumage::cli
