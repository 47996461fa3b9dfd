// `plumage render`: a feather curve file -> an image (EXR linear or PNG sRGB),
// path traced with Embree under the paper's 25-LED dome, an environment and/or
// directional lights (docs/rendering.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "command.h"
#include "material_options.h"
#include "substructure_options.h"
#include "view_options.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/number_text.h"
#include "plumage/common/stats.h"
#include "plumage/renderer/explicit_geometry.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/shading_level.h"
#include "plumage/renderer/structure_aov.h"
#include "plumage/pipeline/feather_scene.h"

namespace plumage::cli {
namespace {

struct Options {
  std::string input, output;
  std::string shading = "hair";
  ViewOptions view{"512x512", "WIDTHxHEIGHT, e.g. 640x480"};
  std::string env;
  float env_scale = 1;
  std::vector<std::string> directional;
  std::string sampler = "sobol";
  MaterialOptions material;
  std::string aov;
  SubstructureOverrides substructure;
  std::string tile;  // --tile I/N: one part of a split render
};

// `plumage render scene.fscene`: every distinct feather built once, placed as the scene says.
int run_render_scene(const Options& o, ViewSpec view, ShadingMode mode, SceneShading shading) {
  if (!o.aov.empty()) throw UsageError("--aov works on one feather; render a .fcurves file for it");
  if (o.view.cull) throw UsageError("--cull works on one feather; leave it out for a .fscene");
  LoadedScene loaded = load_scene(o.input);
  o.view.apply_scene(loaded.scene, view);
  const DomeRig rig = o.view.read_rig_for(view, o.input);
  for (Feather& f : loaded.feathers) {
    o.substructure.apply(f);
    if (mode == ShadingMode::Explicit) check_explicit_fits(f);
  }
  SceneOptions so = o.view.scene_options(view, rig);
  so.mode = mode;
  const BuiltWorld built(loaded, so, view, shading);
  if (view_lights(built.world().bounds(), rig, view).empty())
    std::cerr << "plumage: warning: no light is on (--lights none and no --env/--directional); the image is black\n";
  const Image image = render_view(built.world(), rig, view);
  write_image(o.output, image);
  stats_set_value("Scene/Placements", double(loaded.scene.placements.size()));
  stats_set_value("Scene/Distinct feathers", double(loaded.feathers.size()));
  stats_set_value("Scene/Barbs over all placements", double(loaded.placed_barbs()));
  stats_set_value("Scene/Distinct feathers' control points (bytes)", double(built.feather_bytes()));
  stats_set_value("Scene/Placement records (bytes)", double(built.placement_bytes()));
  if (shading == SceneShading::ByFootprint)
    for (ShadingMode m : {ShadingMode::Substructure, ShadingMode::Farfield})
      stats_set_value(std::string("Scene/Placements shaded ") + to_string(m),
                      double(std::count(built.placement_modes().begin(), built.placement_modes().end(), m)));
  if (!global_options().quiet)
    std::cerr << "wrote " << o.output << " (" << view.width << "x" << view.height << ", " << view.spp << " spp, "
              << loaded.scene.placements.size() << " placements of " << loaded.feathers.size() << " feathers)\n";
  return 0;
}

// The render-only parts of the view: extra lights, the sampler and the material.
void add_lights_and_material(const Options& o, ViewSpec& view) {
  if (!o.env.empty()) {
    if (const auto c = parse_colour(o.env)) {
      const glm::vec3 radiance = *c * o.env_scale;
      if (!std::isfinite(radiance.x + radiance.y + radiance.z))
        throw UsageError("--env " + o.env + " times --env-scale " + num(o.env_scale) +
                         " is beyond the largest radiance a float holds (3.4e38); lower one of them");
      view.environment.emplace(radiance);
    }
    else
      view.environment.emplace(std::filesystem::path(o.env), o.env_scale);
  }
  for (const std::string& d : o.directional) {
    const auto v = parse_numbers(d, "--directional");
    const glm::vec3 given(v[0], v[1], v[2]);  // number_list({4, 6}) checked the count
    const float largest = std::max({std::abs(given.x), std::abs(given.y), std::abs(given.z)});
    if (!(largest > 0)) throw UsageError("--directional " + d + ": the direction must not be zero");
    const glm::vec3 dir = given / largest;  // so that its length cannot overflow (1e30,1e30,1e30)
    view.directional.push_back({glm::normalize(dir), v.size() == 4 ? glm::vec3(v[3]) : glm::vec3(v[3], v[4], v[5])});
  }
  view.sampler = parse_sampler_kind(o.sampler);
  o.material.apply(view);
}

int run_render(const Options& o) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  if (const std::string bad = image_output_problem(o.output, {".exr", ".png", ".hdr", ".tif", ".jpg"}); !bad.empty())
    throw UsageError(bad);
  const bool by_footprint = o.shading == kAutoShading;
  const ShadingMode mode = by_footprint ? ShadingMode::Substructure : parse_shading_mode(o.shading);
  if (o.aov == "structure" && (by_footprint || (mode != ShadingMode::Substructure && mode != ShadingMode::Explicit)))
    throw UsageError("--aov structure shows rami and barbules: give --shading substructure or explicit");
  ViewSpec view = o.view.view_spec(o.input, !global_options().quiet);
  if (!o.tile.empty()) {
    if (std::filesystem::path(o.output).extension() != ".exr")
      throw UsageError("--tile writes a part for `plumage merge`: give -o PART.exr (linear floats, merged bit for bit)");
    if (!o.aov.empty()) throw UsageError("--tile splits the beauty image; leave out --aov");
    parse_tile(o.tile, view.tile_index, view.tile_count);  // tile_part() checked the form
  }
  add_lights_and_material(o, view);  // its usage errors before any file is read
  if (std::filesystem::path(o.input).extension() == ".fscene")
    return run_render_scene(o, view, mode, by_footprint ? SceneShading::ByFootprint : SceneShading::Uniform);
  const DomeRig rig = o.view.read_rig();
  const auto t_setup = clock::now();
  Feather feather = read_fcurves(o.input);
  o.substructure.apply(feather);
  const auto t_read = clock::now();

  SceneOptions so = o.view.scene_options(view, rig);
  so.mode = mode;
  if (so.mode == ShadingMode::Explicit) check_explicit_fits(feather);
  std::optional<Scene> built(std::in_place, feather, so);
  if (by_footprint) {
    // The feather's level by the smallest pixel footprint over it (shading_level.h).
    const Bounds3f& box = built->feather_bounds();
    so.mode = shading_by_footprint(feather, 1.0f, box, Camera(view.camera, view.width, view.height, box));
    stats_set_value(std::string("Scene/Placements shaded ") + to_string(so.mode), 1.0);
    if (so.mode != ShadingMode::Substructure) {
      const std::shared_ptr<const RibbonLayers> layers = built->ribbon_layer_map();
      built.reset();
      built.emplace(feather, so, layers);
    }
  }
  const Scene& scene = *built;
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
  stats_set_value("Time/Lights and setup (s)", secs(t0, t_setup));
  stats_set_value("Time/Read curves (s)", secs(t_setup, t_read));
  stats_set_value("Time/BVH build (s)", secs(t_read, t_build));
  stats_set_value("Time/Write image (s)", secs(t_render, t_write));
  if (!global_options().quiet)
    std::cerr << "wrote " << o.output << " (" << view.width << "x" << view.height << ", " << view.spp << " spp, "
              << secs(t_build, t_render) << " s)\n";
  return 0;
}

const Registration kRender{
    "render", "Path trace a feather curve file to an image (EXR linear / PNG sRGB)", [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      o->view.record_given(sub);
      sub.footer(
          "A .fscene input renders many feathers, each distinct one built once (docs/scene-format.md); its\n"
          "camera and lights records apply where --camera-pos, --look-at, --up, --fov and --lights are not given.\n"
          "Lights: the dome rig's LEDs (--lights all | none | 1,5,12 | 1-8), an environment (--env) and\n"
          "directional lights add up. Units are mm; the feather lies in XY with its dorsal side to +Z.\n"
          "Example: plumage render feather.fcurves -o out.png --spp 64 --lights 1 --exposure 2\n"
          "See docs/rendering.md.");
      sub.add_option("input", o->input, "Feather curve file (.fcurves) or scene of many feathers (.fscene)")->required();
      sub.add_option("-o,--output", o->output, "Output image: .exr (linear float) or .png (sRGB 8-bit)")->required();
      add_shading_option(sub, o->shading, "Barb shading: hair (fibres, production practice), substructure (Baron et al. 2021; docs/substructure.md) explicit (rami and barbules as real curves: the slow reference), farfield (ribbons shaded by a table measured on the explicit geometry; fitted once, cached in $PLUMAGE_FARFIELD_CACHE) or auto (each feather in substructure mode where a pixel over it is smaller than its barbule period, in farfield mode where it is larger; --stats counts each)", true);
      sub.add_option("--tile", o->tile, "Render part I of N of the image (rows split in N bands; the other rows stay 0) into an .exr; `plumage merge` joins the N parts into the image one run gives, bit for bit (docs/rendering.md, \"Split renders\")")
          ->check(tile_part());
      sub.add_option("--aov", o->aov, "Write an AOV instead of the beauty image: 'structure' colours ramus, distal and proximal barbules and gaps (needs --shading substructure or explicit)")
          ->check(one_of({"structure"}));
      o->substructure.add_to(sub);
      o->view.add_to(sub, "Image size WIDTHxHEIGHT",
                     "Dome LEDs that are on: all, none, or numbers 1..25 (e.g. 1,5,12 or 2-9)");
      CLI::Option* env = sub.add_option("--env", o->env, "Environment: a grey value, R,G,B, or a lat-long .exr/.hdr image (+Z is up)")
          ->check(environment(true));
      sub.add_option("--env-scale", o->env_scale, "Multiplier on the environment radiance")->capture_default_str()->check(in_range(0, 1e6))->needs(env);
      sub.add_option("--directional", o->directional, "Directional light DX,DY,DZ,E or DX,DY,DZ,R,G,B (toward the light; irradiance); repeatable")
          ->allow_extra_args(false)
          ->check(number_list({4, 6}))
          ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
      sub.add_option("--sampler", o->sampler, "sobol (Owen-scrambled, Burley 2020) or independent")
          ->capture_default_str()
          ->check(one_of(kSamplerKinds));
      o->material.add_to(sub, true);
      return [o] { return run_render(*o); };
    }};

}  // namespace
}  // namespace plumage::cli
