// `plumage render`: a feather curve file -> an image (EXR linear or PNG sRGB),
// path traced with Embree under the paper's 25-LED dome, an environment and/or
// directional lights (docs/rendering.md).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "command.h"
#include "substructure_options.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/stats.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/render.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/structure_aov.h"

namespace plumage::cli {
namespace {

std::vector<float> parse_numbers(const std::string& text, const std::string& flag) {
  std::vector<float> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    float v = 0;
    try {
      v = std::stof(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v))
      throw Error(flag + ": '" + item + "' is not a number");
    out.push_back(v);
  }
  return out;
}

glm::vec3 parse_vec3(const std::string& text, const std::string& flag) {
  const auto v = parse_numbers(text, flag);
  if (v.size() != 3) throw Error(flag + " takes three comma-separated numbers, e.g. 0,0,100");
  return {v[0], v[1], v[2]};
}

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
  int spp = 16;
  std::string resolution = "512x512";
  std::uint64_t seed = 0;
  int max_depth = 16;
  float exposure = 0;
  std::string lights = "all";
  std::string rig = std::string(PLUMAGE_DATA_DIR) + "/rigs/dome25.json";
  std::string env;
  float env_scale = 1;
  std::vector<std::string> directional;
  std::string backdrop = "white";
  int threads = 0;
  std::string sampler = "sobol";
  std::string projection = "perspective";
  std::string camera_pos, look_at, up = "0,1,0";
  float fov = 30;
  float margin = 0.05f;
  HairParams hair;
  std::string melanin, sigma_a;
  std::string aov;
  SubstructureOverrides substructure;
};

int run_render(const Options& o) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  int W = 0, H = 0;
  {
    char x = 0;
    std::stringstream ss(o.resolution);
    if (!(ss >> W >> x >> H) || x != 'x' || !ss.eof())
      throw Error("--resolution '" + o.resolution + "': give WIDTHxHEIGHT, e.g. 640x480");
  }
  const std::string ext = std::filesystem::path(o.output).extension().string();
  if (ext != ".exr" && ext != ".png" && ext != ".hdr" && ext != ".tif" && ext != ".jpg")
    throw Error("-o " + o.output + ": the extension picks the format; use .exr (linear) or .png (sRGB)");

  if (!o.aov.empty() && o.aov != "structure") throw Error("--aov '" + o.aov + "': the only AOV is 'structure'");
  Feather feather = read_fcurves(o.input);
  o.substructure.apply(feather);
  const auto t_read = clock::now();

  SceneOptions so;
  so.mode = parse_shading_mode(o.shading);
  if (o.backdrop == "white") {
    so.backdrop = {true, glm::vec3(0.8f)};
  } else if (o.backdrop == "black") {
    so.backdrop = {true, glm::vec3(0.03f)};
  } else if (o.backdrop != "none") {
    throw Error("--backdrop '" + o.backdrop + "': use white, black or none");
  }
  const Scene scene(feather, so);
  const auto t_build = clock::now();

  // Lights.
  LightSet lights;
  const DomeRig rig = read_dome_rig(o.rig);
  const AxisBox& fb = scene.feather_bounds();
  const glm::vec3 rig_centre(fb.centre().x, fb.centre().y, fb.lo.z);
  for (const SphereLight& l : dome_lights(rig, parse_light_selection(o.lights, int(rig.leds.size())), rig_centre))
    lights.add(l);
  if (!o.env.empty()) {
    if (const auto c = parse_colour(o.env))
      lights.set_environment(EnvironmentLight(*c * o.env_scale));
    else
      lights.set_environment(EnvironmentLight(std::filesystem::path(o.env), o.env_scale));
  }
  for (const std::string& d : o.directional) {
    const auto v = parse_numbers(d, "--directional");
    if (v.size() != 4 && v.size() != 6)
      throw Error("--directional takes DX,DY,DZ,E or DX,DY,DZ,R,G,B (direction toward the light, irradiance)");
    const glm::vec3 dir(v[0], v[1], v[2]);
    if (!(glm::length(dir) > 0)) throw Error("--directional: the direction must not be zero");
    lights.add(DirectionalLight{glm::normalize(dir), v.size() == 4 ? glm::vec3(v[3]) : glm::vec3(v[3], v[4], v[5])});
  }
  if (lights.empty())
    std::cerr << "plumage: warning: no light is on (--lights none and no --env/--directional); the image is black\n";

  // Material.
  HairParams hp = o.hair;
  validate(hp, "--beta-m/--beta-n/--alpha/--eta");
  std::optional<FibreMaterial> material;
  if (!o.sigma_a.empty()) {
    hp.sigma_a = parse_vec3(o.sigma_a, "--sigma-a");
    material.emplace(hp);
  } else if (!o.melanin.empty()) {
    const auto m = parse_numbers(o.melanin, "--melanin");
    if (m.empty() || m.size() > 2 || m[0] < 0 || (m.size() == 2 && m[1] < 0))
      throw Error("--melanin takes EUMELANIN[,PHEOMELANIN], both >= 0");
    hp.sigma_a = sigma_a_from_melanin(m[0], m.size() == 2 ? m[1] : 0.0f);
    material.emplace(hp);
  } else {
    material.emplace(hp, AlbedoMap(feather.albedo, std::filesystem::path(o.input).parent_path()));
  }

  // Camera.
  CameraSpec cs;
  if (o.projection == "perspective") cs.projection = Projection::Perspective;
  else if (o.projection == "orthographic") cs.projection = Projection::Orthographic;
  else throw Error("--projection '" + o.projection + "': use perspective or orthographic");
  if (!o.camera_pos.empty()) cs.position = parse_vec3(o.camera_pos, "--camera-pos");
  if (!o.look_at.empty()) cs.look_at = parse_vec3(o.look_at, "--look-at");
  cs.up = parse_vec3(o.up, "--up");
  cs.fov_deg = o.fov;
  cs.margin = o.margin;
  const Camera camera(cs, W, H, fb);
  if (o.aov == "structure") {
    write_image(o.output, render_structure_aov(scene, camera));
    if (!global_options().quiet) std::cerr << "wrote " << o.output << " (structure AOV, " << W << "x" << H << ")\n";
    return 0;
  }

  IntegratorSettings is;
  if (o.max_depth < 0) throw Error("--max-depth must be 0 or more");
  is.max_depth = o.max_depth;
  const PathIntegrator integrator(scene, lights, *material, is);
  RenderSettings rs;
  rs.spp = o.spp;
  rs.seed = o.seed;
  rs.threads = o.threads;
  rs.sampler = parse_sampler_kind(o.sampler);
  const auto t_setup = clock::now();
  const Film film = render(camera, integrator, rs);
  const auto t_render = clock::now();
  film.write(o.output, o.exposure);
  const auto t_write = clock::now();

  const auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  stats_set_value("Time/Read curves (s)", secs(t0, t_read));
  stats_set_value("Time/BVH build (s)", secs(t_read, t_build));
  stats_set_value("Time/Lights and setup (s)", secs(t_build, t_setup));
  stats_set_value("Time/Write image (s)", secs(t_render, t_write));
  if (!global_options().quiet)
    std::cerr << "wrote " << o.output << " (" << W << "x" << H << ", " << o.spp << " spp, "
              << secs(t_setup, t_render) << " s)\n";
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
      sub.add_option("--shading", o->shading, "Barb shading: hair or substructure (Baron et al. 2021; docs/substructure.md)")->capture_default_str();
      sub.add_option("--aov", o->aov, "Write an AOV instead of the beauty image: 'structure' colours ramus, distal and proximal barbules and gaps (needs --shading substructure)");
      o->substructure.add_to(sub);
      sub.add_option("--spp", o->spp, "Samples per pixel (a power of two suits the Sobol sampler)")->capture_default_str();
      sub.add_option("--resolution", o->resolution, "Image size WIDTHxHEIGHT")->capture_default_str();
      sub.add_option("--seed", o->seed, "Random seed; the same seed gives the same image at any --threads")->capture_default_str();
      sub.add_option("--max-depth", o->max_depth, "Maximum scattering events per path (1 = direct light only)")->capture_default_str();
      sub.add_option("--exposure", o->exposure, "Exposure in stops: pixels are scaled by 2^exposure")->capture_default_str();
      sub.add_option("--lights", o->lights, "Dome LEDs that are on: all, none, or numbers 1..25 (e.g. 1,5,12 or 2-9)")->capture_default_str();
      sub.add_option("--rig", o->rig, "Light rig JSON file")->capture_default_str();
      sub.add_option("--env", o->env, "Environment: a grey value, R,G,B, or a lat-long .exr/.hdr image (+Z is up)");
      sub.add_option("--env-scale", o->env_scale, "Multiplier on the environment radiance")->capture_default_str();
      sub.add_option("--directional", o->directional, "Directional light DX,DY,DZ,E or DX,DY,DZ,R,G,B (toward the light; irradiance); repeatable")
          ->allow_extra_args(false)
          ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
      sub.add_option("--backdrop", o->backdrop, "Card under the feather: white (albedo 0.8), black (0.03) or none")->capture_default_str();
      sub.add_option("--threads", o->threads, "Worker threads (0 = all cores)")->capture_default_str();
      sub.add_option("--sampler", o->sampler, "sobol (Owen-scrambled, Burley 2020) or independent")->capture_default_str();
      sub.add_option("--projection", o->projection, "perspective or orthographic")->capture_default_str();
      sub.add_option("--camera-pos", o->camera_pos, "Camera position X,Y,Z in mm (default: auto-framed top view)");
      sub.add_option("--look-at", o->look_at, "Point the camera looks at (default: the feather's centre)");
      sub.add_option("--up", o->up, "Camera up vector")->capture_default_str();
      sub.add_option("--fov", o->fov, "Vertical field of view in degrees (perspective)")->capture_default_str();
      sub.add_option("--margin", o->margin, "Auto-framing: fraction of the view left around the feather")->capture_default_str();
      sub.add_option("--beta-m", o->hair.beta_m, "Hair longitudinal roughness (0,1]")->capture_default_str();
      sub.add_option("--beta-n", o->hair.beta_n, "Hair azimuthal roughness (0,1]")->capture_default_str();
      sub.add_option("--alpha", o->hair.alpha_deg, "Cuticle tilt in degrees")->capture_default_str();
      sub.add_option("--eta", o->hair.eta, "Index of refraction of keratin")->capture_default_str();
      sub.add_option("--melanin", o->melanin, "Absorption from EUMELANIN[,PHEOMELANIN] instead of the feather's albedo");
      sub.add_option("--sigma-a", o->sigma_a, "Absorption R,G,B given directly (per unit radius)");
      return [o] { return run_render(*o); };
    }};

}  // namespace
}  // namespace plumage::cli
