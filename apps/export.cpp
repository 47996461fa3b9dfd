// plumage export: a .fcurves feather written for another renderer or DCC tool
// (docs/cli.md#export, formats in docs/curve-format.md#exporters).
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "command.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/exporters.h"

namespace plumage::cli {
namespace {

// --format left out: the output's extension decides, where it is unambiguous.
std::optional<ExportFormat> format_from_extension(const std::filesystem::path& out) {
  const std::string ext = out.extension().string();
  if (ext == ".fcurves") return ExportFormat::Fcurves;
  if (ext == ".pbrt") return ExportFormat::Pbrt;
  if (ext == ".obj") return ExportFormat::Obj;
  if (ext == ".txt") return ExportFormat::Mitsuba;
  return std::nullopt;
}

struct ExportArgs {
  std::string input, output, format;
};

const Registration kExport{
    "export", "Write a .fcurves feather as pbrt-v4, pbrt-v3, Mitsuba 3 or Wavefront OBJ curves",
    [](CLI::App& sub) -> std::function<int()> {
      auto args = std::make_shared<ExportArgs>();
      sub.footer(
          "Formats:\n"
          "  fcurves  the Plumage curve file itself (re-written in canonical form)\n"
          "  pbrt     pbrt-v4 scene: camera over the dorsal side, hair material, one\n"
          "           Shape \"curve\" per curve (bspline basis; barbs are ribbons)\n"
          "  pbrt-v3  the same scene in pbrt-v3 syntax\n"
          "  mitsuba  Mitsuba 3 bsplinecurve file: x y z radius per line, a blank line\n"
          "           between curves (use it as <shape type=\"bsplinecurve\"> filename)\n"
          "  obj      Wavefront OBJ free-form curves (cstype bspline), for Blender\n"
          "Without --format the output's extension decides: .fcurves, .pbrt (pbrt-v4),\n"
          ".txt (mitsuba), .obj. The output is written atomically: on any error an\n"
          "existing file is left as it was.\n"
          "Example: plumage export feather.fcurves --format pbrt -o feather.pbrt\n"
          "Exit status: 0 done, 1 the input could not be read or exported, 2 usage error.\n");
      sub.add_option("FILE", args->input, "The .fcurves file to read")->required();
      sub.add_option("-o,--output", args->output, "The file to write")->required();
      sub.add_option("-f,--format", args->format, "fcurves, pbrt, pbrt-v3, mitsuba or obj")
          ->check(CLI::IsMember({"fcurves", "pbrt", "pbrt-v3", "mitsuba", "obj"}));
      return [args]() -> int {
        const std::filesystem::path out(args->output);
        ExportFormat format;
        if (!args->format.empty()) {
          format = parse_export_format(args->format);
        } else if (auto f = format_from_extension(out)) {
          format = *f;
        } else {
          std::cerr << "plumage: error: cannot tell the format from '" << out.string()
                    << "': give --format fcurves|pbrt|pbrt-v3|mitsuba|obj\n";
          return 2;
        }
        const Feather feather = read_fcurves(args->input);
        ExportOptions options;
        options.image_filename = out.stem().string() + ".exr";
        export_feather(out, feather, format, options);
        if (!global_options().quiet)
          std::cout << "wrote " << out.string() << " (" << to_string(format)
                    << "): " << feather.count(CurveKind::Shaft) << " shaft, "
                    << feather.count(CurveKind::Barb) << " barbs, " << feather.num_control_points()
                    << " control points\n";
        return 0;
      };
    }};

}  // namespace
}  // namespace plumage::cli
