#pragma once
// Exporters: a Feather written for other programs (docs/curve-format.md#exporters,
// docs/exporters.md says what each target carries exactly and what it approximates).
//   pbrt     pbrt-v4 scene: plumage's camera, dome LEDs (sphere area lights), card,
//            hair material and depth; one `Shape "curve"` per curve, "bspline" basis,
//            the shaft as a cylinder, barbs as ray-facing "flat" curves of the width
//            plumage draws them with
//   pbrt-v3  the same scene in pbrt-v3 syntax ("point P", WorldBegin/WorldEnd)
//   mitsuba  Mitsuba 3: the `bsplinecurve` text ("x y z radius" per line, a blank line
//            between curves) and, beside it, a scene XML that loads it
//   obj      Wavefront OBJ free-form curves (cstype bspline, deg 3, curv/parm/end), one
//            object per curve (no radius: OBJ curves have none)
//   blender  a Python script for Blender 3.4+ (`blender -b -P feather.py`) that builds
//            the curves with their drawn radius as a Curves object, a Principled
//            Hair BSDF with plumage's sigma_a, the camera, LEDs, card and depth
// Every curve is a uniform cubic B-spline, so control points pass through unchanged.
//
// The scene (camera, lights, card, material, depth) is an ExportScene: plain numbers
// that the renderer fills with what `plumage render` would use
// (renderer/export_scene.h), so the exporters write the renderer's values rather
// than work them out again.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/feather.h"

namespace plumage {

enum class ExportFormat { Fcurves, Pbrt, PbrtV3, Mitsuba, Obj, Blender };

// "fcurves", "pbrt", "pbrt-v3", "mitsuba", "obj", "blender".
const char* to_string(ExportFormat f);
// Throws plumage::Error listing the known names.
ExportFormat parse_export_format(std::string_view name);
// The usual file extension, with the dot (".pbrt", ".txt", ...).
const char* default_extension(ExportFormat f);

// A pinhole camera: eye, the point it looks at, up, and the vertical field of view.
struct ExportCamera {
  glm::vec3 eye{0, 0, 100}, look_at{0}, up{0, 1, 0};
  float fov_deg = 30;
};

// A sphere of uniform radiance (one dome LED).
struct ExportSphereLight {
  glm::vec3 centre{0};
  float radius = 1;        // mm
  glm::vec3 radiance{1};   // W / (mm^2 sr)
};

// A square diffuse card in a plane z = const, facing +Z (the backdrop).
struct ExportCard {
  glm::vec3 centre{0};
  float half_side = 1;     // mm
  glm::vec3 albedo{0.8f};
};

// The hair BCSDF's parameters in plumage's conventions: alpha_deg > 0 shifts R
// toward the root (the exporters write each target's sign).
struct ExportMaterial {
  glm::vec3 sigma_a{0};    // per unit fibre radius
  float beta_m = 0.3f, beta_n = 0.3f, alpha_deg = 2.0f, eta = 1.55f;
};

struct ExportScene {
  std::string image_filename = "feather.exr";  // the film's output file
  int width = 512, height = 512, spp = 64;
  int max_depth = 16;                          // scattering events; 1 = direct light only
  ExportCamera camera;
  std::vector<ExportSphereLight> lights;
  std::optional<glm::vec3> environment;        // constant radiance from every direction
  std::optional<ExportCard> card;
  ExportMaterial material;
  std::string shading = "hair";                // the plumage mode this scene stands for
  std::string material_note;                   // one line on what the material leaves out, or empty
};

// pbrt's "fov" is that of the image's shorter side; plumage's is vertical.
float pbrt_fov_deg(const ExportScene& scene);

std::string format_pbrt_v4(const Feather& feather, const ExportScene& scene);
std::string format_pbrt_v3(const Feather& feather, const ExportScene& scene);
// The curves at the radius plumage draws them with (render_radius).
std::string format_mitsuba_curves(const Feather& feather);
// A Mitsuba 3 scene XML that loads `curves_filename` (relative to the XML's folder).
std::string format_mitsuba_scene(const Feather& feather, const ExportScene& scene,
                                 const std::string& curves_filename);
std::string format_obj(const Feather& feather);
std::string format_blender(const Feather& feather, const ExportScene& scene);

// The text of `feather` in `format` (for Mitsuba, the curves file).
std::string export_text(const Feather& feather, ExportFormat format, const ExportScene& scene);
// Writes atomically: on any error the file at `path` is left as it was. Mitsuba
// also writes the scene XML beside `path` (mitsuba_scene_path), curves first.
void export_feather(const std::filesystem::path& path, const Feather& feather, ExportFormat format,
                    const ExportScene& scene);
// Where export_feather puts the Mitsuba scene XML for a curves file at `curves`.
std::filesystem::path mitsuba_scene_path(const std::filesystem::path& curves);

}  // namespace plumage
