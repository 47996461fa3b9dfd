#pragma once
// Exporters: a Feather written for other programs (docs/curve-format.md#exporters).
//   pbrt     pbrt-v4 scene: one `Shape "curve"` per curve, "bspline" basis, shaft
//            as a cylinder, barbs as ribbons oriented by the vane normal, a hair material
//   pbrt-v3  the same scene in pbrt-v3 syntax ("point P", WorldBegin/WorldEnd)
//   mitsuba  Mitsuba 3 `bsplinecurve` text: "x y z radius" per line, a blank line between curves
//   obj      Wavefront OBJ free-form curves (cstype bspline, deg 3, curv/parm/end), one
//            object per curve, which Blender imports as NURBS curves
// Every curve is a uniform cubic B-spline, so control points pass through unchanged.
#include <filesystem>
#include <string>
#include <string_view>

#include "plumage/common/feather.h"

namespace plumage {

enum class ExportFormat { Fcurves, Pbrt, PbrtV3, Mitsuba, Obj };

// "fcurves", "pbrt", "pbrt-v3", "mitsuba", "obj".
const char* to_string(ExportFormat f);
// Throws plumage::Error listing the known names.
ExportFormat parse_export_format(std::string_view name);
// The usual file extension, with the dot (".pbrt", ".txt", ...).
const char* default_extension(ExportFormat f);

struct ExportOptions {
  std::string image_filename = "feather.exr";   // pbrt: the Film's output file
  int image_width = 1024, image_height = 1024;  // pbrt: film resolution
};

std::string format_pbrt_v4(const Feather& feather, const ExportOptions& options = {});
std::string format_pbrt_v3(const Feather& feather, const ExportOptions& options = {});
std::string format_mitsuba_curves(const Feather& feather);
std::string format_obj(const Feather& feather);

// The text of `feather` in `format`.
std::string export_text(const Feather& feather, ExportFormat format, const ExportOptions& options = {});
// Writes atomically: on any error the file at `path` is left as it was.
void export_feather(const std::filesystem::path& path, const Feather& feather, ExportFormat format,
                    const ExportOptions& options = {});

}  // namespace plumage
