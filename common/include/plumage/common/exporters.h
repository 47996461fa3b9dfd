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

// A scene of many feathers (a .fscene, docs/scene-format.md) for the exporters:
// each distinct feather once, with its name and its own material, and the
// placements that put it into the scene. pbrt and Mitsuba get real instancing
// (pbrt's ObjectBegin/ObjectInstance, Mitsuba's shapegroup/instance), Blender
// objects that share one Curves datablock, OBJ every placement's curves carried
// into the scene (it has no instancing).
struct ExportFeather {
  std::string name;                  // 1-64 of A-Z a-z 0-9 _ - . (a .fscene feather name); unique
  const Feather* feather = nullptr;  // must outlive the call
  ExportMaterial material;
};
struct ExportPlacement {
  std::size_t feather = 0;  // index into ExportInstances::feathers
  glm::mat4 to_world{1.0f};  // affine; the .fscene reader keeps it a similarity
};
struct ExportInstances {
  std::vector<ExportFeather> feathers;
  std::vector<ExportPlacement> placements;
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

// A scene of placed feathers. The scene's ExportScene::material is not used (each
// feather has its own). Throws plumage::Error for no feather or placement, a bad or
// repeated name, a feather index out of range or a non-finite transform.
std::string format_pbrt_v4(const ExportInstances& scene, const ExportScene& s);
std::string format_pbrt_v3(const ExportInstances& scene, const ExportScene& s);
// `curve_files[i]`: feather i's curves file (format_mitsuba_curves), relative to the XML.
std::string format_mitsuba_scene(const ExportInstances& scene, const ExportScene& s,
                                 const std::vector<std::string>& curve_files);
std::string format_obj(const ExportInstances& scene);
std::string format_blender(const ExportInstances& scene, const ExportScene& s);
// Writes the scene atomically per file, every text built before the first is
// written. Mitsuba: one curves file per distinct feather beside `path`
// (mitsuba_feather_path) and the scene XML at mitsuba_scene_path(path); nothing
// at `path` itself. Fcurves is refused: a .fscene's feathers are curve files already.
void export_instances(const std::filesystem::path& path, const ExportInstances& scene, ExportFormat format,
                      const ExportScene& s);
// Where export_instances puts feather `name`'s Mitsuba curves for a scene exported to `path`.
std::filesystem::path mitsuba_feather_path(const std::filesystem::path& path, const std::string& name);

// The text of `feather` in `format` (for Mitsuba, the curves file).
std::string export_text(const Feather& feather, ExportFormat format, const ExportScene& scene);
// Writes atomically: on any error the file at `path` is left as it was. Mitsuba
// also writes the scene XML beside `path` (mitsuba_scene_path), curves first.
void export_feather(const std::filesystem::path& path, const Feather& feather, ExportFormat format,
                    const ExportScene& scene);
// Where export_feather puts the Mitsuba scene XML for a curves file at `curves`.
std::filesystem::path mitsuba_scene_path(const std::filesystem::path& curves);

}  // namespace plumage
