// `plumage render`: a feather curve file -> an image (EXR linear or PNG sRGB),
// path traced with Embree under the paper's 25-LED dome, an environment and/or
// directional lights (docs/rendering.md).
#include <chrono>
#include <filesystem>
#include <regex>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "command.h"
#include "substructure_options.h"
#include "view_options.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/stats.h"
#include "plumage/renderer/explicit_geometry.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/structure_aov.h"

namespace plumage::cli {
namespace {

// "R,G,B" or one grey number: a constant colour; otherwise nullopt (a file name).
std::optional<glm::vec3> parse_colour(const std::string& text) {
  try {
    const auto v = parse_numbers(text, "");
    if (v.size() == 1) return glm::vec3(v[0]);
    if (v.size() == 3) return glm::vec3(v[0], v[1], v[2]);
  } catch (const Error&) {
  }
  return std::nullopt;
}

struct Options {
  std::string input, output;
  std::string shading = "hair";
  ViewOptions view{"512x512", "WIDTHxHEIGHT, e.g. 640x480"};
  std::string env;
  float env_scale = 1;
  std::vector<std::string> directional;
  std::string sampler = "sobol";
  HairParams hair;
  std::string melanin, sigma_a;
  std::string aov;
  SubstructureOverrides substructure;
};

// The render-only parts of the view: extra lights, the sampler and the material.
void add_lights_and_material(const Options& o, ViewSpec& view) {
  if (!o.env.empty()) {
    if (const auto c = parse_colour(o.env))
      view.environment.emplace(*c * o.env_scale);
    else
      view.environment.emplace(std::filesystem::path(o.env), o.env_scale);
  }
  for (const std::string& d : o.directional) {
    const auto v = parse_numbers(d, "--directional");
    if (v.size() != 4 && v.size() != 6)
      throw Error("--directional takes DX,DY,DZ,E or DX,DY,DZ,R,G,B (direction toward the light, irradiance)");
    const glm::vec3 dir(v[0], v[1], v[2]);
    if (!(glm::length(dir) > 0)) throw Error("--directional: the direction must not be zero");
    view.directional.push_back({glm::normalize(dir), v.size() == 4 ? glm::vec3(v[3]) : glm::vec3(v[3], v[4], v[5])});
  }
  view.sampler = parse_sampler_kind(o.sampler);
  view.hair = o.hair;
  validate(view.hair, "--beta-m/--beta-n/--alpha/--eta");  // before the BVH build, not after
  if (!o.sigma_a.empty()) {
    view.sigma_a = parse_vec3(o.sigma_a, "--sigma-a");
  } else if (!o.melanin.empty()) {
    const auto m = parse_numbers(o.melanin, "--melanin");
    if (m.empty() || m.size() > 2 || m[0] < 0 || (m.size() == 2 && m[1] < 0))
      throw Error("--melanin takes EUMELANIN[,PHEOMELANIN], both >= 0");
    view.sigma_a = sigma_a_from_melanin(m[0], m.size() == 2 ? m[1] : 0.0f);
  }
}

int run_render(const Options& o) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  ViewSpec view = o.view.view_spec(o.input, !global_options().quiet);
  const std::string ext = std::filesystem::path(o.output).extension().string();
  if (ext != ".exr" && ext != ".png" && ext != ".hdr" && ext != ".tif" && ext != ".jpg")
    throw Error("-o " + o.output + ": the extension picks the format; use .exr (linear) or .png (sRGB)");
  Feather feather = read_fcurves(o.input);
  o.substructure.apply(feather);
  const auto t_read = clock::now();
  add_lights_and_material(o, view);
  const DomeRig rig = read_dome_rig(o.view.rig);
  const auto t_setup = clock::now();

  SceneOptions so = o.view.scene_options(view, rig);
  so.mode = parse_shading_mode(o.shading);
  if (so.mode == ShadingMode::Explicit) check_explicit_fits(feather);
  const Scene scene(feather, so);
  const auto t_build = clock::now();

  if (view_lights(scene.feather_bounds(), rig, view).empty())
    std::cerr << "plumage: warning: no light is on (--lights none and no --env/--directional); the image is black\n";
  if (o.aov == "structure") {
    write_image(o.output, render_structure_aov(scene, Camera(view.camera, view.width, view.height, scene.feather_bounds())));
    if (!global_options().quiet)
      std::cerr << "wrote " << o.output << " (structure AOV, " << view.width << "x" << view.height << ")\n";
    return 0;
  }
  const Image image = render_view(scene, rig, view);
  const auto t_render = clock::now();
  write_image(o.output, image);
  const auto t_write = clock::now();

  const auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  stats_set_value("Time/Read curves (s)", secs(t0, t_read));
  stats_set_value("Time/Lights and setup (s)", secs(t_read, t_setup));
  stats_set_value("Time/BVH build (s)", secs(t_setup, t_build));
  stats_set_value("Time/Write image (s)", secs(t_render, t_write));
  if (!global_options().quiet)
    std::cerr << "wrote " << o.output << " (" << view.width << "x" << view.height << ", " << view.spp << " spp, "
              << secs(t_build, t_render) << " s)\n";
  return 0;
}

const Registration kRender{
    "render", "Path trace a feather curve file to an image (EXR linear / PNG sRGB)", [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.footer(
          "Lights: the dome rig's LEDs (--lights all | none | 1,5,12 | 1-8), an environment (--env) and\n"
          "directional lights add up. Units are mm; the feather lies in XY with its dorsal side to +Z.\n"
          "Example: plumage render feather.fcurves -o out.png --spp 64 --lights 1 --exposure 2\n"
          "See docs/rendering.md.");
      sub.add_option("input", o->input, "Feather curve file (.fcurves)")->required();
      sub.add_option("-o,--output", o->output, "Output image: .exr (linear float) or .png (sRGB 8-bit)")->required();
      sub.add_option("--shading", o->shading, "Barb shading: hair (fibres, production practice), substructure (Baron et al. 2021; docs/substructure.md) explicit (rami and barbules as real curves: the slow reference) or farfield (ribbons shaded by a table measured on the explicit geometry; fitted once, cached in $PLUMAGE_FARFIELD_CACHE)")
          ->capture_default_str()
          ->check(one_of(kShadingModes));
      sub.add_option("--aov", o->aov, "Write an AOV instead of the beauty image: 'structure' colours ramus, distal and proximal barbules and gaps (needs --shading substructure or explicit)")
          ->check(one_of({"structure"}));
      o->substructure.add_to(sub);
      o->view.add_to(sub, "Image size WIDTHxHEIGHT",
                     "Dome LEDs that are on: all, none, or numbers 1..25 (e.g. 1,5,12 or 2-9)");
      sub.add_option("--env", o->env, "Environment: a grey value, R,G,B, or a lat-long .exr/.hdr image (+Z is up)")
          ->check([](const std::string& v) -> std::string {
            // Numbers that do not make a colour ("nan", "inf,1,1", "1,2") are a
            // usage error, not a file that is missing.
            static const std::regex numeric(R"(^[-+0-9.,eE ]*(nan|NaN|NAN|inf|Inf|INF|infinity)?[-+0-9.,eE ]*$)");
            if (parse_colour(v) || std::filesystem::exists(v) || !std::regex_match(v, numeric)) return "";
            return "'" + v + "' is neither a grey value nor R,G,B of finite numbers (nor an image file)";
          });
      sub.add_option("--env-scale", o->env_scale, "Multiplier on the environment radiance")->capture_default_str()->check(in_range(0, 1e6));
      sub.add_option("--directional", o->directional, "Directional light DX,DY,DZ,E or DX,DY,DZ,R,G,B (toward the light; irradiance); repeatable")
          ->allow_extra_args(false)
          ->check(number_list({4, 6}))
          ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
      sub.add_option("--sampler", o->sampler, "sobol (Owen-scrambled, Burley 2020) or independent")
          ->capture_default_str()
          ->check(one_of(kSamplerKinds));
      sub.add_option("--beta-m", o->hair.beta_m, "Hair longitudinal roughness (0,1]")->capture_default_str();
      sub.add_option("--beta-n", o->hair.beta_n, "Hair azimuthal roughness (0,1]")->capture_default_str();
      sub.add_option("--alpha", o->hair.alpha_deg, "Cuticle tilt in degrees")->capture_default_str();
      sub.add_option("--eta", o->hair.eta, "Index of refraction of keratin")->capture_default_str();
      sub.add_option("--melanin", o->melanin, "Absorption from EUMELANIN[,PHEOMELANIN] instead of the feather's albedo")
          ->check(number_list({1, 2}, 0));
      sub.add_option("--sigma-a", o->sigma_a, "Absorption R,G,B given directly (per unit radius)")
          ->check(number_list({3}, 0));
      return [o] { return run_render(*o); };
    }};

}  // namespace
}  // namespace plumage::cli
