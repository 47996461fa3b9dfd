// `plumage photo-to-feather`: the whole chain of DESIGN §1 on one photo —
// analyze (layout.json, overlay, albedo), generate (feather.fcurves, preview),
// compare (the picked feather cropped from the photo | hair | substructure, in
// one pose, with their fidelity) — with a summary.json and one line per stage
// with its time. The chain itself is apps/pipeline (photo_to_feather.h); this file
// parses and checks the options — every one before OUTDIR is touched — and prints.
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include "command.h"
#include "option_checks.h"
#include "view_options.h"
#include "plumage/common/atomic_file.h"
#include "plumage/pipeline/photo_to_feather.h"

namespace plumage::cli {
namespace {

struct Options {
  std::string photo, outdir;
  std::optional<int> feather;
  std::optional<double> mm_per_px;
  double grid_mm = 10.0;
  int size = kDefaultSize;
  bool fidelity_image = false;
  int calibrate = CalibrationSettings{}.probes;
  ViewOptions view = default_view();

  static constexpr int kDefaultSize = 672;
  static ViewOptions default_view() {
    ViewOptions v{"", ""};
    v.spp = 8;
    v.seed = 1;
    v.denoise = true;  // the panels are compared with a photo: grain is what a person would see first
    return v;
  }
};

int run_photo_to_feather(const Options& o) {
  // Every option before OUTDIR is touched (a usage error from CLI11 comes earlier still).
  PhotoToFeatherSettings s;
  s.photo = o.photo;
  s.outdir = o.outdir;
  s.view = o.view.sampling_spec(false);
  s.rig = o.view.read_rig();  // with --lights checked against it: a usage error comes first
  check_input_file(s.photo, "a photograph");
  s.analyze.mm_per_px = o.mm_per_px;
  s.analyze.grid_mm = o.grid_mm;
  s.analyze.feather = o.feather;
  s.size = o.size;
  s.fidelity_image = o.fidelity_image;
  s.calibration.probes = o.calibrate;
  const bool quiet = global_options().quiet;
  photo_to_feather(
      s,
      [quiet](const std::string& stage, double seconds, const std::string& what) {
        if (quiet) return;
        std::ostringstream line;
        line << std::left << std::setw(9) << stage << std::right << std::fixed << std::setprecision(2) << std::setw(8)
             << seconds << " s  " << what;
        std::cout << line.str() << std::endl;
      },
      [](const std::string& note) { std::cerr << "warning: " << note << "\n"; });
  return 0;
}

const Registration kPhotoToFeather{
    "photo-to-feather",
    "Photo to feather in one go: analyze, generate the curves, and show the feather's crop of the photo | hair | "
    "substructure in one pose, with their fidelity",
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.footer(
          "Writes to OUTDIR: layout.json, overlay.png, layout.feather<K>.albedo.png (analyze); feather.fcurves,\n"
          "feather.albedo.png, preview.png (generate); comparison.png and with --fidelity-image fidelity.png (compare);\n"
          "summary.json (with silhouette IoU and dE2000 per render panel). A failing stage leaves none of its files behind.\n"
          "Example: plumage photo-to-feather feather.jpg -o out/ --mm-per-px 0.08 --spp 16 --fidelity-image\n"
          "See docs/cli.md and docs/analysis.md.");
      sub.add_option("photo", o->photo, "Photograph of a feather (or a sheet of feathers)")->required();
      sub.add_option("-o,--output", o->outdir, "Output folder (created when missing)")->required();
      sub.add_option("--feather", o->feather, "On a sheet: which feather (F<id> on the overlay; default the first)")
          ->check(in_range(1, 1e6));
      sub.add_option("--mm-per-px", o->mm_per_px, "Scale of the photo; default: from a grid, else 0.1")
          ->check(in_range(1e-4, 1e3));
      sub.add_option("--grid-mm", o->grid_mm, "Spacing of a grid's lines in the photo (mm)")->capture_default_str()
          ->check(in_range(0.01, 1e4));
      sub.add_option("--size", o->size, "Longer side of each comparison panel in pixels (the other follows the crop)")
          ->capture_default_str()
          ->check(in_range(16, 4096));
      sub.add_flag("--fidelity-image", o->fidelity_image,
                   "Also write fidelity.png: each render's silhouette against the photo's and its pixel dE2000");
      sub.add_option("--calibrate", o->calibrate,
                     "Probe renders per shading mode that bring its mean colour to the photo's (0: the card-response "
                     "table alone); docs/analysis.md, \"Colour calibrated by rendering\"")
          ->capture_default_str()
          ->check(in_range(0, 16));
      o->view.add_sampling_to(sub, "Dome LEDs that are on");
      return [o] { return run_photo_to_feather(*o); };
    }};

}  // namespace
}  // namespace plumage::cli
