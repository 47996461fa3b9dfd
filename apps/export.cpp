// plumage export: a .fcurves feather written for another renderer or DCC tool
// (docs/cli.md#export, formats in docs/curve-format.md#exporters, what each target
// reproduces in docs/exporters.md).
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "command.h"
#include "substructure_options.h"
#include "view_options.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/exporters.h"
#include "plumage/renderer/export_scene.h"

namespace plumage::cli {
namespace {

// --format left out: the output's extension decides, where it is unambiguous.
std::optional<ExportFormat> format_from_extension(const std::filesystem::path& out) {
  const std::string ext = out.extension().string();
  if (ext == ".fcurves") return ExportFormat::Fcurves;
  if (ext == ".pbrt") return ExportFormat::Pbrt;
  if (ext == ".obj") return ExportFormat::Obj;
  if (ext == ".txt") return ExportFormat::Mitsuba;
  if (ext == ".py") return ExportFormat::Blender;
  return std::nullopt;
}

struct ExportArgs {
  std::string input, output, format;
  std::string shading = "hair";
  ViewOptions view{"512x512", "WIDTHxHEIGHT, e.g. 640x480"};
  HairParams hair;
  std::string sigma_a, env;
  SubstructureOverrides substructure;
  ExportArgs() { view.spp = 64; }
};

// The scene `plumage render` would render with the same options.
ExportScene scene_for(const ExportArgs& a, const Feather& feather, const std::filesystem::path& out) {
  ViewSpec view = a.view.view_spec(a.input, false);
  view.hair = a.hair;
  if (!a.sigma_a.empty()) view.sigma_a = parse_vec3(a.sigma_a, "--sigma-a");
  const DomeRig rig = read_dome_rig(a.view.rig);
  SceneOptions so = a.view.scene_options(view, rig);
  so.mode = parse_shading_mode(a.shading);
  ExportScene scene = export_scene(feather, rig, view, so);
  if (!a.env.empty()) {
    const auto v = parse_numbers(a.env, "--env");
    if (v.size() != 1 && v.size() != 3) throw Error("--env takes a grey value or R,G,B (a constant environment)");
    scene.environment = v.size() == 1 ? glm::vec3(v[0]) : glm::vec3(v[0], v[1], v[2]);
  }
  scene.image_filename = out.stem().string() + ".exr";
  return scene;
}

const Registration kExport{
    "export", "Write a .fcurves feather as a pbrt-v4, pbrt-v3, Mitsuba 3 or Blender scene, or Wavefront OBJ curves",
    [](CLI::App& sub) -> std::function<int()> {
      auto args = std::make_shared<ExportArgs>();
      sub.footer(
          "Formats:\n"
          "  fcurves  the Plumage curve file itself (re-written in canonical form)\n"
          "  pbrt     pbrt-v4 scene of what `plumage render` renders: its camera, the dome's\n"
          "           LEDs as sphere area lights, the card, the hair material (sigma_a, beta_m,\n"
          "           beta_n, alpha, eta) and depth; barbs as ray-facing \"flat\" curves of the\n"
          "           width plumage draws them with, the shaft as a \"cylinder\"\n"
          "  pbrt-v3  the same scene in pbrt-v3 syntax\n"
          "  mitsuba  Mitsuba 3 bsplinecurve file (x y z radius per line, a blank line between\n"
          "           curves) and beside it a scene XML (same name, .xml) that loads it\n"
          "  obj      Wavefront OBJ free-form curves (cstype bspline): Blender imports them\n"
          "           as NURBS curves, without radius (OBJ has none)\n"
          "  blender  Python script for Blender 3.4+ (blender -b -P feather.py): the curves\n"
          "           with their drawn radius as a Curves object, a Principled Hair BSDF with\n"
          "           plumage's sigma_a, the camera, LEDs (point lights with radius) and card\n"
          "The view options mean what they mean to `plumage render`; --shading substructure\n"
          "is exported as hair (no other renderer has it) with a comment saying so.\n"
          "Without --format the output's extension decides: .fcurves, .pbrt (pbrt-v4),\n"
          ".txt (mitsuba), .obj, .py (blender). The output is written atomically: on any error an\n"
          "existing file is left as it was. See docs/exporters.md.\n"
          "Example: plumage export feather.fcurves --format pbrt -o feather.pbrt\n"
          "Exit status: 0 done, 1 the input could not be read or exported, 2 usage error.\n");
      sub.add_option("FILE", args->input, "The .fcurves file to read")->required();
      sub.add_option("-o,--output", args->output, "The file to write")->required();
      sub.add_option("-f,--format", args->format, "fcurves, pbrt, pbrt-v3, mitsuba, obj or blender")
          ->check(CLI::IsMember({"fcurves", "pbrt", "pbrt-v3", "mitsuba", "obj", "blender"}));
      sub.add_option("--shading", args->shading, "The plumage mode the scene reproduces: hair, or substructure/explicit/farfield (exported as hair)")
          ->capture_default_str();
      ViewOptions& v = args->view;
      sub.add_option("--lights", v.lights, "Dome LEDs that are on: all, none, or numbers 1..25 (e.g. 1,5,12 or 2-9)")->capture_default_str();
      sub.add_option("--rig", v.rig, "Light rig JSON file")->capture_default_str();
      sub.add_option("--backdrop", v.backdrop, "Card under the feather: white (albedo 0.8), black (0.03) or none")->capture_default_str();
      sub.add_option("--env", args->env, "A constant environment: a grey value or R,G,B");
      sub.add_option("--resolution", v.resolution, "Image size WIDTHxHEIGHT")->capture_default_str();
      sub.add_option("--spp", v.spp, "Samples per pixel")->capture_default_str();
      sub.add_option("--max-depth", v.max_depth, "Maximum scattering events per path (1 = direct light only)")->capture_default_str();
      sub.add_option("--camera-pos", v.camera_pos, "Camera position X,Y,Z in mm (default: auto-framed top view)");
      sub.add_option("--look-at", v.look_at, "Point the camera looks at (default: the feather's centre)");
      sub.add_option("--up", v.up, "Camera up vector")->capture_default_str();
      sub.add_option("--fov", v.fov, "Vertical field of view in degrees")->capture_default_str();
      sub.add_option("--margin", v.margin, "Auto-framing: fraction of the view left around the feather")->capture_default_str();
      sub.add_option("--beta-m", args->hair.beta_m, "Hair longitudinal roughness (0,1]")->capture_default_str();
      sub.add_option("--beta-n", args->hair.beta_n, "Hair azimuthal roughness (0,1]")->capture_default_str();
      sub.add_option("--alpha", args->hair.alpha_deg, "Cuticle tilt in degrees (plumage's sign; written in the target's)")->capture_default_str();
      sub.add_option("--eta", args->hair.eta, "Index of refraction of keratin")->capture_default_str();
      sub.add_option("--sigma-a", args->sigma_a, "Absorption R,G,B given directly (per unit radius)");
      args->substructure.add_to(sub);
      return [args]() -> int {
        const std::filesystem::path out(args->output);
        ExportFormat format;
        if (!args->format.empty()) {
          format = parse_export_format(args->format);
        } else if (auto f = format_from_extension(out)) {
          format = *f;
        } else {
          std::cerr << "plumage: error: cannot tell the format from '" << out.string()
                    << "': give --format fcurves|pbrt|pbrt-v3|mitsuba|obj|blender\n";
          return 2;
        }
        Feather feather = read_fcurves(args->input);
        args->substructure.apply(feather);
        const bool scene_format = format != ExportFormat::Fcurves && format != ExportFormat::Obj;
        const ExportScene scene = scene_format ? scene_for(*args, feather, out) : ExportScene{};
        export_feather(out, feather, format, scene);
        if (!global_options().quiet) {
          std::cout << "wrote " << out.string() << " (" << to_string(format)
                    << "): " << feather.count(CurveKind::Shaft) << " shaft, "
                    << feather.count(CurveKind::Barb) << " barbs, " << feather.num_control_points()
                    << " control points\n";
          if (format == ExportFormat::Mitsuba)
            std::cout << "wrote " << mitsuba_scene_path(out).string() << " (Mitsuba 3 scene)\n";
        }
        return 0;
      };
    }};

}  // namespace
}  // namespace plumage::cli
