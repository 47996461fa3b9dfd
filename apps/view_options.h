#pragma once
// The options `plumage render` and `plumage compare` share: image size, camera,
// sampling, the dome rig and its LEDs, exposure, backdrop and view culling. They
// become one ViewSpec and SceneOptions, so both commands render through
// render_view() (renderer/feather_render.h) the same way.
#include <cmath>
#include <cstdint>
#include <optional>
#include <regex>
#include <set>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "command.h"
#include "option_checks.h"
#include "plumage/common/error.h"
#include "plumage/common/scene_format.h"
#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/view_cull.h"

namespace plumage::cli {

// "1,2,3" -> numbers; `flag` names the option in the error.
inline std::vector<float> parse_numbers(const std::string& text, const std::string& flag) {
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

inline glm::vec3 parse_vec3(const std::string& text, const std::string& flag) {
  const auto v = parse_numbers(text, flag);
  if (v.size() != 3) throw Error(flag + " takes three comma-separated numbers, e.g. 0,0,100");
  return {v[0], v[1], v[2]};
}

// "R,G,B" or one grey number: a constant colour; otherwise nullopt (a file name).
inline std::optional<glm::vec3> parse_colour(const std::string& text) {
  try {
    const auto v = parse_numbers(text, "");
    if (v.size() == 1) return glm::vec3(v[0]);
    if (v.size() == 3) return glm::vec3(v[0], v[1], v[2]);
  } catch (const Error&) {
  }
  return std::nullopt;
}

// --env: a constant environment, a grey value or R,G,B, none of them negative;
// with `files`, also the name of an existing lat-long image. Numbers that make no
// colour ("nan", "inf,1,1", "1,2", "-1") are a usage error, not a missing file.
inline CLI::Validator environment(bool files) {
  return CLI::Validator(
      [files](std::string& text) -> std::string {
        if (const auto c = parse_colour(text)) {
          if (c->x < 0 || c->y < 0 || c->z < 0) return "'" + text + "' is negative; an environment's radiance is 0 or more";
          return {};
        }
        static const std::regex numeric(R"(^[-+0-9.,eE ]*(nan|NaN|NAN|inf|Inf|INF|infinity)?[-+0-9.,eE ]*$)");
        if (files && (std::filesystem::exists(text) || !std::regex_match(text, numeric))) return {};
        return "'" + text + "' is neither a grey value nor R,G,B of finite numbers" +
               std::string(files ? " (nor an image file)" : "");
      },
      "", "ENV");
}

// --shading, one of the library's modes (and, where `with_auto`, "auto": each
// feather's level by its pixel footprint, shading_level.h).
inline constexpr const char* kAutoShading = "auto";
inline CLI::Option* add_shading_option(CLI::App& app, std::string& shading, const std::string& help,
                                       bool with_auto = false) {
  std::vector<std::string> names;
  for (ShadingMode m : kShadingModes) names.push_back(to_string(m));
  if (with_auto) names.push_back(kAutoShading);
  return app.add_option("--shading", shading, help)->capture_default_str()->check(one_of(std::move(names)));
}

struct ViewOptions {
  std::string resolution;
  int spp = 16;
  bool adaptive = false;
  bool denoise = false;
  std::string allocation = to_string(RenderSettings{}.allocation);
  float target_error = 0.02f;
  int min_spp = 16;
  bool cull = false;
  std::uint64_t seed = 0;
  int max_depth = 16;
  float exposure = 0;
  std::string lights = "all";
  std::string light_pick = to_string(IntegratorSettings{}.light_pick);
  std::string rig;  // empty: the built-in dome (default_rig_path())
  std::string backdrop = "white";
  int threads = 0;
  std::string projection = "perspective";
  std::string camera_pos, look_at, up = "0,1,0";
  float fov = 30;
  float margin = 0.05f;

  std::string resolution_form;  // what --resolution wants, for its error message
  // The view flags given on the command line (record_given): a scene's own camera
  // and lights (.fscene) yield to them.
  std::set<std::string> given;

  ViewOptions(std::string default_resolution, std::string form)
      : resolution(std::move(default_resolution)), resolution_form(std::move(form)) {}

  // Each option of a view, declared once: its name, help and check. Every command
  // that takes one (render, compare, photo-to-feather, export, bench) adds it
  // from here, so a value means and is checked the same in all of them.
  enum class Opt {
    Resolution, Spp, Allocation, Adaptive, TargetError, MinSpp, Denoise, Seed, MaxDepth, Lights, LightPick, Rig,
    Threads, Cull, Exposure, Backdrop, Projection, CameraPos, LookAt, Up, Fov, Margin
  };
  static constexpr Opt kSampling[] = {Opt::Spp,      Opt::Allocation, Opt::Adaptive,  Opt::TargetError,
                                      Opt::MinSpp,   Opt::Denoise,    Opt::Seed,      Opt::MaxDepth,  Opt::Lights,
                                      Opt::LightPick, Opt::Rig,       Opt::Threads};
  static constexpr Opt kFraming[] = {Opt::Resolution, Opt::Cull, Opt::Exposure, Opt::Backdrop, Opt::Projection,
                                     Opt::CameraPos,  Opt::LookAt, Opt::Up,     Opt::Fov,      Opt::Margin};

  // `resolution_help` and `lights_help` say what the size and the LEDs mean for the command.
  void add_to(CLI::App& app, const std::string& resolution_help, const std::string& lights_help) {
    for (Opt o : kFraming) add(app, o, resolution_help);
    for (Opt o : kSampling) add(app, o, lights_help);
  }

  // The options of how a view is sampled and lit, without its size, camera,
  // exposure and card: for a command that sets those itself (photo-to-feather).
  void add_sampling_to(CLI::App& app, const std::string& lights_help) {
    for (Opt o : kSampling) add(app, o, lights_help);
  }

  // One option; `help` replaces the generic text of --resolution and --lights.
  CLI::Option* add(CLI::App& app, Opt which, const std::string& help = {}) {
    const auto text = [&](const char* generic) { return help.empty() ? std::string(generic) : help; };
    switch (which) {
      case Opt::Resolution:
        return app.add_option("--resolution", resolution, text("Image size WIDTHxHEIGHT"))
            ->capture_default_str()
            ->check(cli::resolution());
      case Opt::Spp:
        return app.add_option("--spp", spp, "Samples per pixel (a power of two suits the Sobol sampler)")
            ->capture_default_str()
            ->check(in_range(1, kMaxSpp));
      case Opt::Allocation:
        return app.add_option("--allocation", allocation,
                              "How samples spread over pixels: variance (a pilot of spp/4, the rest where the noise "
                              "is; unbiased) or uniform (spp everywhere); docs/skip-work.md")
            ->capture_default_str()
            ->check(one_of(kSampleAllocations));
      case Opt::Adaptive:
        return app.add_flag("--adaptive", adaptive,
                            "Adaptive sampling: a pixel stops once converged (--spp is the cap; docs/skip-work.md)");
      case Opt::TargetError:
        return app.add_option("--target-error", target_error,
                              "With --adaptive: relative standard error of a pixel's mean at which it stops")
            ->capture_default_str()
            ->check(positive(1))
            ->needs("--adaptive");
      case Opt::MinSpp:
        return app.add_option("--min-spp", min_spp, "With --adaptive: samples every pixel takes before it may stop")
            ->capture_default_str()
            ->check(in_range(1, kMaxSpp))
            ->needs("--adaptive");
      case Opt::Denoise:
        return app.add_flag("--denoise,!--no-denoise", denoise,
                            std::string("Filter each render by its own per-pixel variance (non-local means): far less "
                                        "grain, a slight blur of what differs by less than the noise (") +
                                (denoise ? "on unless --no-denoise" : "off unless --denoise") +
                                "); docs/rendering.md, \"Denoising\"");
      case Opt::Seed:
        return app.add_option("--seed", seed, "Random seed; the same seed gives the same image at any --threads")
            ->capture_default_str();
      case Opt::MaxDepth:
        return app.add_option("--max-depth", max_depth, "Maximum scattering events per path (1 = direct light only)")
            ->capture_default_str()
            ->check(in_range(0, 1024));
      case Opt::Lights:
        return app.add_option("--lights", lights, text("Dome LEDs that are on: all, none, or numbers (e.g. 1,5,12 or 2-9)"))
            ->capture_default_str()
            ->check(light_list());
      case Opt::LightPick:
        return app.add_option("--light-pick", light_pick,
                              "Next-event estimation's choice of light: estimate (in proportion to each light's "
                              "estimated contribution), uniform, or all (every light at every vertex); docs/rendering.md")
            ->capture_default_str()
            ->check(one_of(kLightPicks));
      case Opt::Rig:
        return app.add_option("--rig", rig, "Light rig JSON file (default: the paper's 25-LED dome, rigs/dome25.json in "
                                            "plumage's data folder)");
      case Opt::Threads:
        return app.add_option("--threads", threads, "Worker threads (0 = all cores)")
            ->capture_default_str()
            ->check(in_range(0, kMaxThreads));
      case Opt::Cull:
        return app.add_flag("--cull", cull,
                            "Leave out of the BVH curves that can neither be seen nor shadow what is seen (docs/skip-work.md)");
      case Opt::Exposure:
        return app.add_option("--exposure", exposure, "Exposure in stops: pixels are scaled by 2^exposure")
            ->capture_default_str()
            ->check(in_range(-64, 64));
      case Opt::Backdrop:
        return app.add_option("--backdrop", backdrop, "Card under the feather: white (albedo 0.8), black (0.03) or none")
            ->capture_default_str()
            ->check(one_of({"white", "black", "none"}));
      case Opt::Projection:
        return app.add_option("--projection", projection, "perspective or orthographic")
            ->capture_default_str()
            ->check(one_of({"perspective", "orthographic"}));
      case Opt::CameraPos:
        return app.add_option("--camera-pos", camera_pos, "Camera position X,Y,Z in mm (default: auto-framed top view)")
            ->check(number_list({3}));
      case Opt::LookAt:
        return app.add_option("--look-at", look_at, "Point the camera looks at (default: the feather's centre)")
            ->check(number_list({3}));
      case Opt::Up:
        return app.add_option("--up", up, "Camera up vector")->capture_default_str()->check(number_list({3}));
      case Opt::Fov:
        return app.add_option("--fov", fov, "Vertical field of view in degrees (perspective)")
            ->capture_default_str()
            ->check(in_range(0.01, 179));
      case Opt::Margin:
        return app.add_option("--margin", margin, "Auto-framing: fraction of the view left around the feather")
            ->capture_default_str()
            ->check(in_range(0, 10));
    }
    return nullptr;
  }

  // Remembers which of the flags a .fscene's camera and lights records stand for
  // were given, once `app` has parsed its command line.
  void record_given(CLI::App& app) {
    app.parse_complete_callback([this, &app] {
      for (const char* flag : {"--camera-pos", "--look-at", "--up", "--fov", "--lights"})
        if (app.count(flag) > 0) given.insert(flag);
    });
  }

  // A .fscene's camera and LEDs, where the command line does not set them.
  void apply_scene(const FeatherScene& scene, ViewSpec& view) const {
    const auto set = [&](const char* flag) { return given.count(flag) > 0; };
    if (scene.camera.position && !set("--camera-pos")) view.camera.position = scene.camera.position;
    if (scene.camera.look_at && !set("--look-at")) view.camera.look_at = scene.camera.look_at;
    if (scene.camera.up && !set("--up")) view.camera.up = *scene.camera.up;
    if (scene.camera.fov_deg && !set("--fov")) view.camera.fov_deg = *scene.camera.fov_deg;
    if (scene.lights && !set("--lights")) view.lights = *scene.lights;
  }

  // The rig for a .fscene `file` whose LED selection `view` now holds (the scene's
  // or --lights), checked against the rig's LEDs.
  DomeRig read_rig_for(const ViewSpec& view, const std::string& file) const {
    DomeRig r = read_rig();
    try {
      (void)light_ranges(view.lights, int(r.leds.size()));
    } catch (const Error& e) {
      throw Error(file + ": lights: " + e.what());
    }
    return r;
  }

  // --rig, or the built-in dome.
  std::filesystem::path rig_file() const { return rig.empty() ? default_rig_path() : std::filesystem::path(rig); }

  // The rig, read first of a command's files, with --lights checked against its
  // LEDs (light_list() checked the grammar while parsing).
  DomeRig read_rig() const {
    DomeRig r = read_dome_rig(rig_file());
    try {
      (void)light_ranges(lights, int(r.leds.size()));
    } catch (const Error& e) {
      throw UsageError(e.what());  // an LED the rig does not have
    }
    return r;
  }

  // Everything add_sampling_to's options set; size, camera, exposure and base folder left at their defaults.
  ViewSpec sampling_spec(bool progress) const {
    ViewSpec v;
    v.spp = spp;
    v.adaptive = adaptive;
    v.denoise = denoise;
    v.allocation = parse_sample_allocation(allocation);
    v.target_error = target_error;
    v.min_spp = min_spp;
    v.seed = seed;
    if (max_depth < 0) throw Error("--max-depth must be 0 or more");
    v.max_depth = max_depth;
    v.lights = lights;
    v.light_pick = parse_light_pick(light_pick);
    v.threads = threads;
    v.progress = progress;
    return v;
  }

  // Everything but the lights beyond the LEDs and the material, which the command adds.
  ViewSpec view_spec(const std::filesystem::path& curve_file, bool progress) const {
    ViewSpec v = sampling_spec(progress);
    if (!parse_resolution(resolution, v.width, v.height))
      throw Error("--resolution '" + resolution + "': give " + resolution_form);
    v.exposure = exposure;
    v.base_dir = curve_file.parent_path();
    if (projection == "perspective") v.camera.projection = Projection::Perspective;
    else if (projection == "orthographic") v.camera.projection = Projection::Orthographic;
    else throw Error("--projection '" + projection + "': use perspective or orthographic");
    if (!camera_pos.empty()) v.camera.position = parse_vec3(camera_pos, "--camera-pos");
    if (!look_at.empty()) v.camera.look_at = parse_vec3(look_at, "--look-at");
    v.camera.up = parse_vec3(up, "--up");
    v.camera.fov_deg = fov;
    v.camera.margin = margin;
    return v;
  }

  // The backdrop, and with --cull the culling for `view` under `rig` (its lights complete).
  SceneOptions scene_options(const ViewSpec& view, const DomeRig& dome) const {
    SceneOptions so;
    if (backdrop == "white") so.backdrop = {true, glm::vec3(0.8f)};
    else if (backdrop == "black") so.backdrop = {true, glm::vec3(0.03f)};
    else if (backdrop != "none") throw Error("--backdrop '" + backdrop + "': use white, black or none");
    if (cull) so.cull = view_cull_for(view, dome);
    return so;
  }
};

}  // namespace plumage::cli
