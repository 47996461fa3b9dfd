#pragma once
// The fibre material's options, shared by `plumage render` and `plumage export`:
// the hair BCSDF's roughnesses, cuticle tilt and index (each checked while the
// command line is parsed, with the library's ranges: validate(HairParams)) and the
// absorption given directly or from melanin.
#include <cmath>
#include <string>

#include <CLI/CLI.hpp>

#include "command.h"
#include "option_checks.h"
#include "view_options.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/hair_bcsdf.h"

namespace plumage::cli {

struct MaterialOptions {
  HairParams hair;
  std::string melanin, sigma_a;

  // `melanin_too`: also --melanin (render; an export writes sigma_a only).
  void add_to(CLI::App& app, bool melanin_too) {
    app.add_option("--beta-m", hair.beta_m, "Hair longitudinal roughness (0,1]")
        ->capture_default_str()
        ->check(library_range([](HairParams& p, float v) { p.beta_m = v; }));
    app.add_option("--beta-n", hair.beta_n, "Hair azimuthal roughness (0,1]")
        ->capture_default_str()
        ->check(library_range([](HairParams& p, float v) { p.beta_n = v; }));
    app.add_option("--alpha", hair.alpha_deg, "Cuticle tilt in degrees, [-45, 45] (plumage's sign; an export writes the target's)")
        ->capture_default_str()
        ->check(library_range([](HairParams& p, float v) { p.alpha_deg = v; }));
    app.add_option("--eta", hair.eta, "Index of refraction of keratin (>= 1)")
        ->capture_default_str()
        ->check(library_range([](HairParams& p, float v) { p.eta = v; }));
    CLI::Option* direct = app.add_option("--sigma-a", sigma_a, "Absorption R,G,B given directly (per unit radius, >= 0)")
                              ->check(number_list({3}, 0));
    if (melanin_too)
      app.add_option("--melanin", melanin, "Absorption from EUMELANIN[,PHEOMELANIN] instead of the feather's albedo")
          ->check(number_list({1, 2}, 0))
          ->excludes(direct);
  }

  void apply(ViewSpec& view) const {
    view.hair = hair;
    if (!sigma_a.empty()) {
      view.sigma_a = parse_vec3(sigma_a, "--sigma-a");
    } else if (!melanin.empty()) {
      const auto m = parse_numbers(melanin, "--melanin");
      view.sigma_a = sigma_a_from_melanin(m[0], m.size() == 2 ? m[1] : 0.0f);
      if (!std::isfinite(view.sigma_a->x + view.sigma_a->y + view.sigma_a->z))
        throw UsageError("--melanin " + melanin +
                         " gives an absorption beyond the largest float; concentrations run from 0 to about 10");
    }
  }

  // A value alone checked by the library's own rule (validate), so the command
  // line and a curve file's material refuse the same numbers.
  template <class Set>
  static CLI::Validator library_range(Set set) {
    return CLI::Validator(
        [set](std::string& text) -> std::string {
          double v = 0;
          if (!detail::parse_double(text, v)) return "";  // not a number: finite_number() says so
          HairParams p;
          set(p, float(v));
          try {
            validate(p, "");
          } catch (const std::exception& e) {
            // ": beta_m = 2 is outside (0, 1]; ..." -> "'2' is outside (0, 1]; ..."
            const std::string why = e.what();
            const auto eq = why.find(" = ");
            const auto rest = eq == std::string::npos ? eq : why.find(' ', eq + 3);
            return "'" + text + "' " + (rest == std::string::npos ? why : why.substr(rest + 1));
          }
          return {};
        },
        "", "RANGE");
  }
};

}  // namespace plumage::cli
