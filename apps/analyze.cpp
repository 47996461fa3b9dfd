// `plumage analyze`: photo -> layout.json (+ albedo textures, + overlay).
#include "plumage/analysis/analyze.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>

#include "command.h"
#include "option_checks.h"
#include "plumage/common/number_text.h"

namespace {

struct AnalyzeArgs {
  std::string photo, output, overlay;
  double mm_per_px = 0, grid_mm = 10.0, max_mp = 16.0;
  int feather = 0;
  bool allow_border = false;
};

const plumage::cli::Registration reg{
    "analyze",
    "Photo of a feather (or a sheet of feathers) -> layout.json: outline, shaft, per-side vane "
    "width, barb angle and spacing, albedo texture, scale",
    [](CLI::App& sub) -> std::function<int()> {
      auto a = std::make_shared<AnalyzeArgs>();
      sub.footer(
          "Light or dark plain backgrounds. Scale: --mm-per-px, else a grid/ruler found in the "
          "photo "
          "(line spacing --grid-mm), else 0.1 mm/px with low confidence.\n"
          "Writes OUT.json, OUT.featherK.albedo.png per feather next to it, and the overlay; all "
          "or "
          "nothing. Format: docs/layout-format.md. Details: docs/analysis.md.\n"
          "Example: plumage analyze sheet.png -o sheet.json --overlay sheet-overlay.png --grid-mm "
          "20");
      sub.add_option("photo", a->photo, "Photograph (PNG, JPEG, TIFF; 8/16-bit, grey, RGB, RGBA)")
          ->required();
      sub.add_option("-o,--output", a->output, "layout.json to write")->required();
      sub.add_option("--overlay", a->overlay,
                     "Overlay image to write (PNG) showing what was found");
      sub.add_option("--mm-per-px", a->mm_per_px, "Scale of the photo in millimetres per pixel")
          ->check(plumage::cli::in_range(1e-4, 1e3));
      sub.add_option(
             "--grid-mm", a->grid_mm,
             "Spacing of the grid lines in the photo, mm (default 10; Feather Atlas sheets: 20)")
          ->check(plumage::cli::in_range(0.01, 1e4));
      sub.add_option("--feather", a->feather,
                     "Report only feather K (1-based, left to right as on the overlay)")
          ->check(plumage::cli::in_range(1, 1e6));
      sub.add_flag("--allow-border", a->allow_border,
                   "Analyse feathers that touch the image border (else they are skipped with a warning)");
      sub.add_option("--max-megapixels", a->max_mp,
                     "Analyse larger photos downscaled to this size (default 16)")
          ->check(plumage::cli::in_range(0.01, 400));
      return [a]() {
        plumage::AnalyzeOptions opt;
        if (a->mm_per_px > 0) opt.mm_per_px = a->mm_per_px;
        opt.grid_mm = a->grid_mm;
        if (a->feather > 0) opt.feather = a->feather;
        opt.allow_border = a->allow_border;
        opt.max_megapixels = a->max_mp;
        plumage::PhotoAnalysis result = plumage::analyze_photo(a->photo, opt);
        plumage::write_analysis(result, a->output, a->overlay);
        if (!plumage::cli::global_options().quiet) {
          for (const auto& w : result.warnings) std::cerr << "plumage: warning: " << w << "\n";
          const auto& L = result.layout;
          std::cerr << "analyze: " << L.feathers.size() << " feather(s)";
          const auto reason = [&](const char* r) {
            return std::count_if(L.skipped.begin(), L.skipped.end(), [&](const auto& s) { return s.reason == r; });
          };
          const auto border = reason("touches_border"), rows = reason("split_row");
          if (rows > 0) std::cerr << " (" << rows << " shingled row(s) cut into one feather per quill)";
          if (L.skipped.size() > std::size_t(rows)) {
            std::cerr << ", " << L.skipped.size() - rows << " region(s) skipped (" << L.skipped.size() - rows - border
                      << " several feathers, " << border << " on the border)";
          }
          std::cerr << ", " << plumage::num(L.scale.mm_per_px) << " mm/px ("
                    << plumage::to_string(L.scale.source) << ")";
          for (const auto& f : L.feathers)
            std::cerr << "; F" << f.id << " " << plumage::num(std::round(10 * f.length_mm) / 10) << " mm";
          std::cerr << " -> " << a->output << "\n";
          if (plumage::cli::global_options().stats) {
            std::cerr << "analyze: stage times:";
            for (const auto& [stage, sec] : result.stage_seconds)
              std::cerr << " " << stage << " " << sec << " s;";
            std::cerr << "\n";
          }
        }
        return 0;
      };
    }};

}  // namespace
