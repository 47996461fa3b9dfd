// `plumage photo-to-feather`: the whole chain of DESIGN §1 on one photo —
// analyze (layout.json, overlay, albedo), generate (feather.fcurves, preview),
// compare (photo | hair | substructure, framed like the photo) — with a
// summary.json and one line per stage with its time. A stage that fails removes
// the files it had written, so outdir holds only finished stages.
#include <chrono>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command.h"
#include "option_checks.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/generator/analysis/analyze.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/generator/preview.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/film.h"
#include "plumage/renderer/panel_layout.h"

namespace plumage::cli {
namespace {

namespace fs = std::filesystem;

struct Options {
  std::string photo, outdir;
  std::optional<int> feather;
  std::optional<double> mm_per_px;
  double grid_mm = 10.0;
  int spp = 16;
  int height = 320;
  std::uint64_t seed = 1;
  std::string rig = std::string(PLUMAGE_DATA_DIR) + "/rigs/dome25.json";
  int threads = 0;
};

// Runs one stage: times it, and on failure removes the files it wrote and
// reports the stage by name in a one-line error.
class Stages {
 public:
  explicit Stages(bool quiet) : quiet_(quiet) {}
  void run(const std::string& name, std::vector<fs::path>& written, const std::function<std::string()>& body) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string report;
    try {
      report = body();
    } catch (const std::exception& e) {
      for (const auto& p : written) {
        std::error_code ec;
        fs::remove(p, ec);
      }
      written.clear();
      throw Error("photo-to-feather: stage '" + name + "' failed: " + e.what());
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    seconds_.push_back({name, s});
    if (!quiet_) {
      std::ostringstream line;
      line << std::left << std::setw(9) << name << std::right << std::fixed << std::setprecision(2) << std::setw(8)
           << s << " s  " << report;
      std::cout << line.str() << std::endl;
    }
  }
  const std::vector<std::pair<std::string, double>>& seconds() const { return seconds_; }

 private:
  bool quiet_;
  std::vector<std::pair<std::string, double>> seconds_;
};

// An orthographic top view that sees the feather as the photo does: the photo's
// centre, its "up" and its height in mm, mapped through image -> feather.
CameraSpec photo_camera(const Layout& layout, const FeatherLayout& f) {
  const glm::dvec2 centre = apply(f.feather_from_image, {0.5 * layout.image_width, 0.5 * layout.image_height});
  const glm::dvec2 up = glm::normalize(apply(f.feather_from_image, {0.0, 0.0}) - apply(f.feather_from_image, {0.0, 1.0}));
  // Low enough to stay under the dome rig's LEDs (300 mm), high above a cupped vane.
  const double above = std::min(0.3 * f.length_mm + 10.0, 250.0);
  CameraSpec c;
  c.projection = Projection::Orthographic;
  c.position = glm::vec3(float(centre.x), float(centre.y), float(above));
  c.look_at = glm::vec3(float(centre.x), float(centre.y), 0.0f);
  c.up = glm::vec3(float(up.x), float(up.y), 0.0f);
  c.ortho_height = float(layout.image_height * layout.scale.mm_per_px);
  return c;
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

int run_photo_to_feather(const Options& o) {
  if (o.spp < 1) throw Error("--spp must be at least 1");
  if (o.height < 16 || o.height > 8192) throw Error("--height must lie in [16, 8192] pixels");
  if (!fs::exists(o.photo)) throw Error(Location{o.photo}, "no such file; give the photograph to analyse");
  const fs::path out = o.outdir;
  if (fs::exists(out) && !fs::is_directory(out))
    throw Error(Location{o.outdir}, "exists and is not a folder; give -o a folder for the artifacts");
  const bool created = !fs::exists(out);
  fs::create_directories(out);
  const bool quiet = global_options().quiet;
  Stages stages(quiet);
  std::vector<fs::path> files;  // finished stages' artifacts, for the summary

  const fs::path layout_path = out / "layout.json", overlay_path = out / "overlay.png";
  const fs::path fcurves_path = out / "feather.fcurves", preview_path = out / "preview.png";
  const fs::path texture_path = out / "feather.albedo.png";
  const fs::path comparison_path = out / "comparison.png", summary_path = out / "summary.json";
  PhotoAnalysis analysis;
  Feather feather;
  std::vector<std::string> warnings;
  std::vector<std::string> sheet_notes;  // which feather of a sheet went on
  std::vector<fs::path> written;
  try {
    stages.run("analyze", written, [&] {
      AnalyzeOptions ao;
      ao.mm_per_px = o.mm_per_px;
      ao.grid_mm = o.grid_mm;
      ao.feather = o.feather;
      analysis = analyze_photo(o.photo, ao);
      write_analysis(analysis, layout_path, overlay_path);
      written = {layout_path, overlay_path};
      for (const auto& f : analysis.layout.feathers) written.push_back(out / f.albedo.file);
      const LayoutScale& s = analysis.layout.scale;
      return std::to_string(analysis.layout.feathers.size()) + " feather(s), scale " + fixed(s.mm_per_px, 4) +
             " mm/px (" + to_string(s.source) + ") -> layout.json, overlay.png, " +
             analysis.layout.feathers.front().albedo.file;
    });
    files.insert(files.end(), written.begin(), written.end());
    written.clear();

    const FeatherLayout& f = pick_feather(analysis.layout, o.feather, layout_path.string());
    const std::size_t found = analysis.layout.feathers.size();
    if (!o.feather && found > 1) {
      // A sheet of several: say which one goes on, and how to pick another.
      const std::string note = std::to_string(found) + " feathers found; using feather " +
                               std::to_string(f.id) + " (the leftmost); pick another with --feather K (K in 1.." +
                               std::to_string(found) + ", numbered left to right as on overlay.png)";
      std::cerr << "warning: " << o.photo << ": " << note << "\n";
      sheet_notes.push_back(note);
    }
    stages.run("generate", written, [&] {
      written.push_back(texture_path);
      feather = layout_to_feather_with_albedo(f, o.seed, out, out, texture_path, layout_path.string(), &warnings);
      validate_feather(feather);
      written.push_back(fcurves_path);
      write_fcurves(fcurves_path, feather);
      written.push_back(preview_path);
      write_image(preview_path, render_preview(feather, PreviewOptions{1024, true}));
      return "feather " + std::to_string(f.id) + ": length " + fixed(f.length_mm, 1) + " mm, " +
             std::to_string(feather.count(VaneSide::Left)) + " + " + std::to_string(feather.count(VaneSide::Right)) +
             " barbs -> feather.fcurves, feather.albedo.png, preview.png";
    });
    files.insert(files.end(), written.begin(), written.end());
    written.clear();
    for (const auto& w : warnings) std::cerr << "warning: feather " << f.id << ": " << w << "\n";

    int width = 0;
    stages.run("compare", written, [&] {
      ViewSpec view;
      view.height = o.height;
      view.width = std::max(16, int(std::lround(double(o.height) * analysis.layout.image_width /
                                                std::max(1, analysis.layout.image_height))));
      width = view.width;
      view.spp = o.spp;
      view.seed = o.seed;
      view.threads = o.threads;
      view.base_dir = out;
      view.camera = photo_camera(analysis.layout, f);
      const DomeRig rig = read_dome_rig(o.rig);
      SceneOptions so;
      so.backdrop = {true, analysis.layout.background == "dark" ? glm::vec3(0.03f) : glm::vec3(0.8f)};
      const Image photo = read_image(o.photo);
      view.card_level = border_luminance(photo);  // expose the renders like the photo: its card at its level
      std::vector<Panel> panels{{scale_to_height(photo, view.height), "photo"}};
      so.mode = ShadingMode::Hair;
      panels.push_back({render_view(Scene(feather, so), rig, view), "hair"});
      so.mode = ShadingMode::Substructure;
      panels.push_back({render_view(Scene(feather, so), rig, view), "substructure"});
      written.push_back(comparison_path);
      write_image(comparison_path, side_by_side(panels));
      return std::to_string(view.width) + "x" + std::to_string(view.height) + " per panel, " +
             std::to_string(o.spp) + " spp -> comparison.png";
    });
    files.insert(files.end(), written.begin(), written.end());
    written.clear();

    stages.run("summary", written, [&] {
      nlohmann::json j;
      j["photo"] = o.photo;
      j["feathers_found"] = analysis.layout.feathers.size();
      j["feather"] = f.id;
      j["scale"] = {{"mm_per_px", analysis.layout.scale.mm_per_px},
                    {"source", to_string(analysis.layout.scale.source)},
                    {"confidence", analysis.layout.scale.confidence}};
      j["length_mm"] = f.length_mm;
      j["counts"] = {{"barbs_left", feather.count(VaneSide::Left)},
                     {"barbs_right", feather.count(VaneSide::Right)},
                     {"curves", feather.curves.size()},
                     {"control_points", feather.num_control_points()}};
      j["render"] = {{"spp", o.spp}, {"seed", o.seed}, {"panel_width", width}, {"panel_height", o.height}};
      nlohmann::json st = nlohmann::json::array();
      for (const auto& [name, s] : stages.seconds()) st.push_back({{"stage", name}, {"seconds", s}});
      j["stages"] = st;
      nlohmann::json names = nlohmann::json::array();
      for (const auto& p : files) names.push_back(p.filename().string());
      names.push_back(summary_path.filename().string());
      j["files"] = names;
      nlohmann::json w = nlohmann::json::array();
      for (const auto& s : sheet_notes) w.push_back("analyze: " + s);
      for (const auto& s : f.warnings) w.push_back("analyze: " + s);
      for (const auto& s : warnings) w.push_back("generate: " + s);
      j["warnings"] = w;
      written.push_back(summary_path);
      write_file_atomic(summary_path, j.dump(2) + "\n");
      return "-> summary.json";
    });
  } catch (...) {
    std::error_code ec;
    if (created && fs::is_empty(out, ec)) fs::remove(out, ec);
    throw;
  }
  return 0;
}

const Registration kPhotoToFeather{
    "photo-to-feather",
    "Photo to feather in one go: analyze, generate the curves, and render photo | hair | substructure framed like "
    "the photo",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.footer(
          "Writes to OUTDIR: layout.json, overlay.png, layout.feather<K>.albedo.png (analyze); feather.fcurves,\n"
          "feather.albedo.png, preview.png (generate); comparison.png (compare); summary.json. A failing stage leaves none of its\n"
          "files behind. Example: plumage photo-to-feather feather.jpg -o out/ --mm-per-px 0.08 --spp 32\n"
          "See docs/cli.md and docs/analysis.md.");
      sub.add_option("photo", o->photo, "Photograph of a feather (or a sheet of feathers)")->required();
      sub.add_option("-o,--output", o->outdir, "Output folder (created when missing)")->required();
      sub.add_option("--feather", o->feather, "On a sheet: which feather (F<id> on the overlay; default the first)")
          ->check(in_range(1, 1e6));
      sub.add_option("--mm-per-px", o->mm_per_px, "Scale of the photo; default: from a grid, else 0.1")
          ->check(in_range(1e-4, 1e3));
      sub.add_option("--grid-mm", o->grid_mm, "Spacing of a grid's lines in the photo (mm)")->capture_default_str()
          ->check(in_range(0.01, 1e4));
      sub.add_option("--spp", o->spp, "Samples per pixel of the renders")->capture_default_str()->check(in_range(1, kMaxSpp));
      sub.add_option("--height", o->height, "Height of each comparison panel in pixels (width follows the photo)")
          ->capture_default_str()
          ->check(in_range(16, 4096));
      sub.add_option("--seed", o->seed, "Seed of the generator and the renderer")->capture_default_str();
      sub.add_option("--rig", o->rig, "Light rig JSON file")->capture_default_str();
      sub.add_option("--threads", o->threads, "Render threads (0 = all cores)")->capture_default_str()->check(in_range(0, kMaxThreads));
      return [o] { return run_photo_to_feather(*o); };
    }};

}  // namespace
}  // namespace plumage::cli
