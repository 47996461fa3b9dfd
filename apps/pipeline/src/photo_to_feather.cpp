// The photo-to-feather chain (photo_to_feather.h): analyze -> generate -> compare
// -> summary, each stage timed; a run that fails leaves OUTDIR as it was.
#include "plumage/pipeline/photo_to_feather.h"

#include <unistd.h>

#include <chrono>
#include <iomanip>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/interrupt.h"
#include "plumage/common/text.h"
#include "plumage/generator/layout_to_params.h"
#include "plumage/pipeline/photo_comparison.h"

namespace plumage {
namespace {

namespace fs = std::filesystem;

// Runs one stage: times it, and on failure removes the files it wrote and
// reports the stage by name in a one-line error.
class Stages {
 public:
  explicit Stages(const StageReport& report) : report_(report) {}
  void run(const std::string& name, std::vector<fs::path>& written, const std::function<std::string()>& body) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string report;
    auto remove_written = [&] {
      for (const auto& p : written) {
        std::error_code ec;
        fs::remove(p, ec);
      }
      written.clear();
    };
    try {
      check_interrupted();
      report = body();
    } catch (const Interrupted&) {
      remove_written();
      throw;  // as it is: the CLI exits 128 + signal
    } catch (const std::exception& e) {
      remove_written();
      throw Error("photo-to-feather: stage '" + name + "' failed: " + e.what());
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    seconds_.push_back({name, s});
    if (report_) report_(name, s, report);
  }
  const std::vector<std::pair<std::string, double>>& seconds() const { return seconds_; }

 private:
  StageReport report_;
  std::vector<std::pair<std::string, double>> seconds_;
};

// Whether `name` is a file photo-to-feather writes into OUTDIR.
bool is_artifact(const std::string& name) {
  static const std::set<std::string> fixed_names = {"layout.json",   "overlay.png",    "feather.fcurves",
                                                    "feather.albedo.png", "preview.png", "comparison.png",
                                                    "fidelity.png",  "summary.json"};
  static const std::regex albedo(R"(layout\.feather[0-9]+\.albedo\.png)");
  return fixed_names.count(name) > 0 || std::regex_match(name, albedo);
}

// OUTDIR as a previous run left it, kept until this run ends, so that OUTDIR is
// all-or-nothing: each artifact already there is kept under a hard link in a
// hidden folder inside OUTDIR (a copy where the file system has no links), and
// this run's files replace the artifacts by rename, never in place. A run that
// fails puts every kept file back and removes the artifacts it wrote; a run that
// succeeds removes the previous run's artifacts it did not write again (a
// fidelity.png, or a sheet's layout.feather7.albedo.png), so that OUTDIR holds
// one run's results, as summary.json lists them.
class PreviousRun {
 public:
  explicit PreviousRun(const fs::path& out) : out_(out) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(out, ec)) {
      const std::string name = e.path().filename().string();
      if (!is_artifact(name) || !e.is_regular_file(ec)) continue;
      if (keep_.empty()) {
        keep_ = out / (".plumage-previous-" + std::to_string(::getpid()));
        fs::create_directory(keep_);
      }
      fs::create_hard_link(e.path(), keep_ / name, ec);
      if (ec) fs::copy_file(e.path(), keep_ / name, fs::copy_options::overwrite_existing);
      kept_.insert(name);
    }
  }
  PreviousRun(const PreviousRun&) = delete;
  PreviousRun& operator=(const PreviousRun&) = delete;
  ~PreviousRun() {
    if (!keep_.empty()) {
      std::error_code ec;
      fs::remove_all(keep_, ec);
    }
  }

  // The run failed: OUTDIR's artifacts as they were.
  void restore() {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(out_, ec)) {
      const std::string name = e.path().filename().string();
      if (is_artifact(name) && !kept_.count(name) && e.is_regular_file(ec)) fs::remove(e.path(), ec);  // this run's
    }
    for (const std::string& name : kept_) fs::rename(keep_ / name, out_ / name, ec);
  }

  // The run succeeded and wrote `written`: the previous run's other artifacts go.
  void finish(const std::vector<fs::path>& written) {
    std::set<std::string> names;
    for (const auto& p : written) names.insert(p.filename().string());
    std::error_code ec;
    for (const std::string& name : kept_)
      if (!names.count(name)) fs::remove(out_ / name, ec);
  }

 private:
  fs::path out_, keep_;
  std::set<std::string> kept_;
};

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

}  // namespace

void photo_to_feather(const PhotoToFeatherSettings& o, const StageReport& report, const Notice& warn) {
  const ViewSpec& sampling = o.view;
  const fs::path out = o.outdir;
  if (fs::exists(out) && !fs::is_directory(out))
    throw Error(Location{out.string()}, "exists and is not a folder; give -o a folder for the artifacts");
  const bool created = !fs::exists(out);
  fs::create_directories(out);
  // A folder this run made is removed when a signal stops it (interrupt.h); the
  // handler's last resort removes it only when empty.
  const RemovedOnSignal made_by_this_run = created ? RemovedOnSignal(out, true) : RemovedOnSignal();
  PreviousRun previous(out);  // OUTDIR all-or-nothing
  Stages stages(report);
  std::vector<fs::path> files;  // finished stages' artifacts, for the summary

  const fs::path layout_path = out / "layout.json", overlay_path = out / "overlay.png";
  const fs::path fcurves_path = out / "feather.fcurves", preview_path = out / "preview.png";
  const fs::path texture_path = out / "feather.albedo.png";
  const fs::path comparison_path = out / "comparison.png", summary_path = out / "summary.json";
  const fs::path fidelity_path = out / "fidelity.png";
  PhotoAnalysis analysis;
  Feather feather;
  std::vector<std::string> warnings;
  std::vector<std::string> sheet_notes;  // which feather of a sheet went on
  std::vector<fs::path> written;
  try {
    stages.run("analyze", written, [&] {
      // The compare stage reads the photo whole (as any image input, at most
      // kMaxImageMegapixels), so the analysis refuses a larger one from its header
      // before any work, not only after analysing it.
      AnalyzeOptions analyze = o.analyze;
      analyze.refuse_megapixels = std::min(analyze.refuse_megapixels, kMaxImageMegapixels);
      analysis = analyze_photo(o.photo, analyze);
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

    const FeatherLayout& f = pick_feather(analysis.layout, o.analyze.feather, layout_path.string());
    const std::size_t found = analysis.layout.feathers.size();
    if (!o.analyze.feather && found > 1) {
      // A sheet of several: say which one goes on, and how to pick another.
      const std::string note = std::to_string(found) + " feathers found; using feather " +
                               std::to_string(f.id) + " (the leftmost); pick another with --feather K (K in 1.." +
                               std::to_string(found) + ", numbered left to right as on overlay.png)";
      if (warn) warn(o.photo.string() + ": " + note);
      sheet_notes.push_back(note);
    }
    stages.run("generate", written, [&] {
      FileBatch outputs;
      feather = generate_from_layout(f, sampling.seed, layout_path, fcurves_path, preview_path, 1024, outputs, &warnings);
      outputs.commit();
      written = {fcurves_path, texture_path, preview_path};
      return "feather " + std::to_string(f.id) + ": length " + fixed(f.length_mm, 1) + " mm, " +
             std::to_string(feather.count(VaneSide::Left)) + " + " + std::to_string(feather.count(VaneSide::Right)) +
             " barbs -> feather.fcurves, feather.albedo.png, preview.png";
    });
    files.insert(files.end(), written.begin(), written.end());
    written.clear();
    if (warn)
      for (const auto& w : warnings) warn("feather " + std::to_string(f.id) + ": " + w);

    PhotoComparison comparison;
    ImageSource photo_source;  // how many of the photo's samples were not finite
    stages.run("compare", written, [&] {
      ViewSpec view = sampling;
      view.base_dir = out;
      comparison = compare_with_photo(read_image(o.photo, true, kMaxImageMegapixels, &photo_source), analysis.layout,
                                      f, feather, o.rig, view, o.size, FidelitySettings{}, o.calibration);
      FileBatch outputs;
      write_image(outputs, comparison_path, comparison_image(comparison));
      if (o.fidelity_image) write_image(outputs, fidelity_path, fidelity_image(comparison));
      outputs.commit();
      written = {comparison_path};
      if (o.fidelity_image) written.push_back(fidelity_path);
      const auto& h = comparison.fidelity.at(0).feather;
      const auto& sub = comparison.fidelity.at(1).feather;
      const PhotoCrop& g = comparison.render_grid;
      const bool own_grid = g != comparison.crop;
      return std::to_string(comparison.crop.width) + "x" + std::to_string(comparison.crop.height) + " per panel, " +
             (own_grid ? "traced at the photo's " + std::to_string(g.width) + "x" + std::to_string(g.height) + ", " +
                             std::to_string(comparison.render_spp) + " spp"
                       : std::to_string(sampling.spp) + " spp") +
             " -> comparison.png" + (o.fidelity_image ? ", fidelity.png" : "") +
             "; silhouette IoU hair " + fixed(h.iou, 3) + ", substructure " + fixed(sub.iou, 3) +
             "; colour dE2000 hair " + fixed(h.mean_colour_de2000, 1) + ", substructure " +
             fixed(sub.mean_colour_de2000, 1);
    });
    files.insert(files.end(), written.begin(), written.end());
    written.clear();

    stages.run("summary", written, [&] {
      nlohmann::json j;
      j["photo"] = o.photo.string();
      j["photo_samples_replaced"] = photo_source.replaced;  // NaN or infinite samples of a float photo
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
      j["render"] = {{"spp", sampling.spp},
                     {"seed", sampling.seed},
                     {"panel_width", comparison.crop.width},
                     {"panel_height", comparison.crop.height},
                     {"traced_width", comparison.render_grid.width},
                     {"traced_height", comparison.render_grid.height},
                     {"traced_spp", comparison.render_spp}};
      j["fidelity"] = fidelity_json(comparison);
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
      write_file_atomic(summary_path, json_text(j, 2) + "\n");
      return "-> summary.json";
    });
    files.push_back(summary_path);
    previous.finish(files);
  } catch (...) {
    previous.restore();
    std::error_code ec;
    if (created && interrupt_signal()) fs::remove_all(out, ec);  // stopped by a signal: as if never run
    else if (created && fs::is_empty(out, ec)) fs::remove(out, ec);
    throw;
  }
}


}  // namespace plumage
