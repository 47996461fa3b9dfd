// plumage export: a .fcurves feather written for another renderer or DCC tool
// (docs/cli.md#export, formats in docs/curve-format.md#exporters, what each target
// reproduces in docs/exporters.md).
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "command.h"
#include "material_options.h"
#include "substructure_options.h"
#include "view_options.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/exporters.h"
#include "plumage/renderer/export_scene.h"
#include "plumage/pipeline/feather_scene.h"

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
  MaterialOptions material;
  std::string env;
  SubstructureOverrides substructure;
  std::vector<std::string> scene_options_given;  // filled while parsing
  ExportArgs() { view.spp = 64; }
};

// What the view leaves to the export: --env's constant environment and the film's
// file name (OUT's stem, .exr).
void add_environment_and_film(const ExportArgs& a, const std::filesystem::path& out, ExportScene& scene) {
  if (!a.env.empty()) scene.environment = *parse_colour(a.env);  // environment(false) made sure it is one
  scene.image_filename = out.stem().string() + ".exr";
}

// The scene `plumage render` would render with the same options.
ExportScene scene_for(const ExportArgs& a, const Feather& feather, const std::filesystem::path& out) {
  ViewSpec view = a.view.view_spec(a.input, false);
  a.material.apply(view);
  const DomeRig rig = a.view.read_rig();
  SceneOptions so = a.view.scene_options(view, rig);
  so.mode = parse_shading_mode(a.shading);
  ExportScene scene = export_scene(feather, rig, view, so);
  add_environment_and_film(a, out, scene);
  return scene;
}

// A .fscene: each distinct feather once and its placements, instanced where the
// target can (exporters.h, ExportInstances), with the scene's camera and lights as
// `plumage render` takes them.
int export_fscene(const ExportArgs& a, const std::filesystem::path& out, ExportFormat format) {
  if (format == ExportFormat::Fcurves)
    throw UsageError(a.input + ": a scene's feathers are .fcurves files already (docs/scene-format.md); give "
                     "--format pbrt, pbrt-v3, mitsuba, obj or blender");
  LoadedScene loaded = load_scene(a.input);
  for (Feather& f : loaded.feathers) a.substructure.apply(f);
  ViewSpec view = a.view.view_spec(a.input, false);
  a.view.apply_scene(loaded.scene, view);
  a.material.apply(view);
  const DomeRig rig = a.view.read_rig_for(view, a.input);
  SceneOptions so = a.view.scene_options(view, rig);
  so.mode = ShadingMode::Hair;  // every target's fibres are hair fibres
  const BuiltWorld built(loaded, so, view);
  std::vector<ExportMaterial> materials;
  ExportScene scene = export_scene(built.world(), rig, view, parse_shading_mode(a.shading), materials);
  add_environment_and_film(a, out, scene);
  ExportInstances instances;
  for (std::size_t i = 0; i < loaded.feathers.size(); ++i)
    instances.feathers.push_back({loaded.scene.feathers[i].name, &loaded.feathers[i], materials[i]});
  for (const ScenePlacement& p : loaded.scene.placements) instances.placements.push_back({p.feather, p.to_world});
  export_instances(out, instances, format, scene);
  if (!global_options().quiet) {
    if (format == ExportFormat::Mitsuba)
      std::cout << "wrote " << loaded.feathers.size() << " curve files beside " << mitsuba_scene_path(out).string()
                << " (Mitsuba 3 scene)";
    else
      std::cout << "wrote " << out.string() << " (" << to_string(format) << ")";
    std::cout << ": " << loaded.feathers.size() << " distinct feathers, " << loaded.scene.placements.size()
              << " placements, " << loaded.placed_barbs() << " barbs over all placements\n";
  }
  return 0;
}

const Registration kExport{
    "export", "Write a .fcurves feather or a .fscene scene as a pbrt-v4, pbrt-v3, Mitsuba 3 or Blender scene, or Wavefront OBJ curves",
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
          "A .fscene (a scene of many feathers, docs/scene-format.md) is written with each distinct\n"
          "feather once and its own material, and every placement: pbrt's ObjectBegin/ObjectInstance,\n"
          "Mitsuba's shapegroup/instance (a curves file per feather, OUT.NAME.txt, and OUT.xml),\n"
          "Blender objects sharing a feather's Curves datablock, OBJ with each placement's curves\n"
          "carried into the scene (OBJ has no instancing); not fcurves (its feathers are curve files).\n"
          "Example: plumage export feather.fcurves --format pbrt -o feather.pbrt\n"
          "Exit status: 0 done, 1 the input could not be read or exported, 2 usage error.\n");
      sub.add_option("FILE", args->input, "The .fcurves file to read, or a .fscene scene of many feathers")->required();
      sub.add_option("-o,--output", args->output, "The file to write")->required();
      sub.add_option("-f,--format", args->format, "fcurves, pbrt, pbrt-v3, mitsuba, obj or blender")
          ->check(CLI::IsMember({"fcurves", "pbrt", "pbrt-v3", "mitsuba", "obj", "blender"}));
      add_shading_option(sub, args->shading,
                         "The plumage mode the scene reproduces: hair, or substructure/explicit/farfield (exported as hair)");
      using Opt = ViewOptions::Opt;
      ViewOptions& v = args->view;
      for (Opt opt : {Opt::Lights, Opt::Rig, Opt::Backdrop, Opt::Resolution, Opt::Spp, Opt::MaxDepth, Opt::CameraPos,
                      Opt::LookAt, Opt::Up, Opt::Fov, Opt::Margin})
        v.add(sub, opt);
      sub.add_option("--env", args->env, "A constant environment: a grey value or R,G,B")->check(environment(false));
      args->material.add_to(sub, false);
      args->substructure.add_to(sub);
      // Every option but the input, the output, the format and the substructure
      // overrides (which change the curve file itself) sets the scene; noted while
      // the options exist (the command runs after they are gone).
      sub.parse_complete_callback([args, &sub] {
        for (const CLI::Option* opt : sub.get_options())
          if (opt->count() > 0 && !opt->check_name("FILE") && !opt->check_name("--output") &&
              !opt->check_name("--format") && !args->substructure.owns(opt))
            args->scene_options_given.push_back(opt->get_name());
      });
      return [args]() -> int {
        const std::filesystem::path out(args->output);
        ExportFormat format;
        if (!args->format.empty()) {
          format = parse_export_format(args->format);
        } else if (auto f = format_from_extension(out)) {
          format = *f;
        } else {
          throw UsageError("cannot tell the format from '" + out.string() +
                           "': give --format fcurves|pbrt|pbrt-v3|mitsuba|obj|blender");
        }
        const bool scene_format = format != ExportFormat::Fcurves && format != ExportFormat::Obj;
        if (!scene_format && !args->scene_options_given.empty())
          throw UsageError(args->scene_options_given.front() + " sets the scene, and " + to_string(format) +
                           " holds only the curves: leave it out or export a scene format");
        if (std::filesystem::path(args->input).extension() == ".fscene") return export_fscene(*args, out, format);
        Feather feather = read_fcurves(args->input);
        args->substructure.apply(feather);
        const ExportScene scene = scene_format ? scene_for(*args, feather, out) : ExportScene{};
        export_feather(out, feather, format, scene);
        if (!global_options().quiet) {
          std::cout << "wrote " << out.string() << " (" << to_string(format)
                    << "): " << feather.count(CurveKind::Shaft) << " shaft, "
                    << feather.count(CurveKind::Barb) << " barbs, ";
          if (const std::size_t down = feather.count(CurveKind::Down)) std::cout << down << " down barbs, ";
          std::cout << feather.num_control_points() << " control points\n";
          if (format == ExportFormat::Mitsuba)
            std::cout << "wrote " << mitsuba_scene_path(out).string() << " (Mitsuba 3 scene)\n";
        }
        return 0;
      };
    }};

}  // namespace
}  // namespace plumage::cli
