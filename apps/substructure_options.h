#pragma once
// Command-line overrides of the curve file's substructure parameters (DESIGN §5),
// shared by `plumage render` and `plumage compare`. An override applies to both
// vanes; parameters not given keep the curve file's per-vane values.
#include <algorithm>
#include <optional>
#include <vector>
#include <string>

#include <CLI/CLI.hpp>

#include "option_checks.h"
#include "plumage/common/feather.h"

namespace plumage::cli {

struct SubstructureOverrides {
  std::optional<int> barbules;
  std::optional<float> elevation_deg, azimuth_deg, ramus_radius, barbule_radius, hooked_fraction, ribbon_width;

  std::vector<std::string> names;  // of the options add_to added

  // Whether `opt` is one of these overrides.
  bool owns(const CLI::Option* opt) const { return std::find(names.begin(), names.end(), opt->get_name()) != names.end(); }

  void add_to(CLI::App& app) {
    const std::size_t before = app.get_options().size();
    add_options(app);
    const auto all = app.get_options();
    for (std::size_t i = before; i < all.size(); ++i) names.push_back(all[i]->get_name());
  }

  void add_options(CLI::App& app) {
    app.add_option("--barbules", barbules, "Substructure: barbules per side of each barb, N (both vanes)")
        ->check(library_range([](SubstructureParams& p, double v) { p.barbules_per_side = int(v); }));
    app.add_option("--barbule-elevation", elevation_deg, "Substructure: barbule angle from the barb in the vane, theta_b (degrees, 1..90)")
        ->check(library_range([](SubstructureParams& p, double v) { p.elevation_deg = float(v); }));
    app.add_option("--barbule-azimuth", azimuth_deg, "Substructure: barbule lift out of the vane, phi_b (degrees, -90..90 exclusive)")
        ->check(library_range([](SubstructureParams& p, double v) { p.azimuth_deg = float(v); }));
    app.add_option("--ramus-radius", ramus_radius, "Substructure: ramus radius r_r (mm)")
        ->check(library_range([](SubstructureParams& p, double v) { p.ramus_radius = float(v); }));
    app.add_option("--barbule-radius", barbule_radius, "Substructure: barbule radius r_b (mm)")
        ->check(library_range([](SubstructureParams& p, double v) { p.barbule_radius = float(v); }));
    app.add_option("--hooked-fraction", hooked_fraction, "Substructure: hooked fraction of a distal barbule (0..1)")
        ->check(library_range([](SubstructureParams& p, double v) { p.hooked_fraction = float(v); }));
    app.add_option("--ribbon-width", ribbon_width, "Substructure: barb ribbon width W (mm)")
        ->check(library_range([](SubstructureParams& p, double v) { p.ribbon_width = float(v); }));
  }

  // Each flag's value alone is checked with the library's ranges
  // (substructure_problem) when the command line is parsed (a usage error);
  // what depends on two values or on the curve file (the ramus inside the
  // ribbon) is checked where it is used, and named by its setting.
  template <class Set>
  static CLI::Validator library_range(Set set) {
    return CLI::Validator(
        [set](std::string& text) -> std::string {
          double v = 0;
          try {
            v = std::stod(text);
          } catch (...) {
            return "";  // not a number: CLI11's conversion says so
          }
          SubstructureParams p;
          p.ramus_radius = 0, p.ribbon_width = 0;
          set(p, v);
          const auto bad = substructure_problem(p);
          return bad ? bad->problem : "";
        },
        "", "substructure range");
  }

  void apply(Feather& f) const {
    for (SubstructureParams* p : {&f.left, &f.right}) {
      if (barbules) p->barbules_per_side = *barbules;
      if (elevation_deg) p->elevation_deg = *elevation_deg;
      if (azimuth_deg) p->azimuth_deg = *azimuth_deg;
      if (ramus_radius) p->ramus_radius = *ramus_radius;
      if (barbule_radius) p->barbule_radius = *barbule_radius;
      if (hooked_fraction) p->hooked_fraction = *hooked_fraction;
      if (ribbon_width) p->ribbon_width = *ribbon_width;
    }
  }
};

}  // namespace plumage::cli
