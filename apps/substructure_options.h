#pragma once
// Command-line overrides of the curve file's substructure parameters (DESIGN §5),
// shared by `plumage render` and `plumage compare`. An override applies to both
// vanes; parameters not given keep the curve file's per-vane values.
#include <optional>

#include <CLI/CLI.hpp>

#include "option_checks.h"
#include "plumage/common/feather.h"

namespace plumage::cli {

struct SubstructureOverrides {
  std::optional<int> barbules;
  std::optional<float> elevation_deg, azimuth_deg, ramus_radius, barbule_radius, hooked_fraction, ribbon_width;

  void add_to(CLI::App& app) {
    app.add_option("--barbules", barbules, "Substructure: barbules per side of each barb, N (both vanes)")
        ->check(in_range(0, 2147483647));
    app.add_option("--barbule-elevation", elevation_deg, "Substructure: barbule angle from the barb in the vane, theta_b (degrees, 1..90)");
    app.add_option("--barbule-azimuth", azimuth_deg, "Substructure: barbule lift out of the vane, phi_b (degrees)");
    app.add_option("--ramus-radius", ramus_radius, "Substructure: ramus radius r_r (mm)");
    app.add_option("--barbule-radius", barbule_radius, "Substructure: barbule radius r_b (mm)");
    app.add_option("--hooked-fraction", hooked_fraction, "Substructure: hooked fraction of a distal barbule (0..1)");
    app.add_option("--ribbon-width", ribbon_width, "Substructure: barb ribbon width W (mm)");
  }

  // Values are checked where they are used (BarbSubstructure), which names the flag.
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
