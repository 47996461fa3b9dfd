#include "plumage/renderer/export_scene.h"

#include <cstdio>

#include "plumage/common/error.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/shading_mode.h"

namespace plumage {

namespace {

void check_exportable(const ViewSpec& view) {
  if (view.environment) throw Error("an environment light is not exported here; set ExportScene::environment");
  if (!view.directional.empty()) throw Error("directional lights are not exported");
  if (view.camera.projection != Projection::Perspective)
    throw Error("only a perspective camera is exported; drop --projection orthographic");
  if (view.max_depth < 0) throw Error("--max-depth must be 0 or more");
}

// The image, camera and lights of `view` for a scene of bounds `fb`.
ExportScene view_of(const Bounds3f& fb, const DomeRig& rig, const ViewSpec& view, ShadingMode mode) {
  ExportScene s;
  s.width = view.width;
  s.height = view.height;
  s.spp = view.spp;
  s.max_depth = view.max_depth;
  s.shading = to_string(mode);

  const Camera camera(view.camera, view.width, view.height, fb);
  const glm::vec3 target = view.camera.look_at.value_or(fb.centre());
  s.camera.eye = camera.position();
  s.camera.look_at = camera.position() + camera.forward() * glm::length(target - camera.position());
  s.camera.up = view.camera.up;
  s.camera.fov_deg = view.camera.fov_deg;

  const LightSet lights = view_lights(fb, rig, view);
  for (const SphereLight& l : lights.spheres()) s.lights.push_back({l.centre, l.radius, l.radiance});
  return s;
}

// The hair material `material` gives the point `centre` of `feather`, and in
// `note` what the export leaves out of it (appended).
ExportMaterial export_material(const Feather& feather, const FibreMaterial& material, const glm::vec3& centre,
                               const ViewSpec& view, std::string& note) {
  const HairParams hp = material.at(centre);
  if (!feather.albedo.texture.empty() && !view.sigma_a && note.find("albedo texture") == std::string::npos)
    note += std::string(note.empty() ? "" : " ") +
            "sigma_a is the one plumage gives the feather's centre: the albedo texture is not exported.";
  if (has_medulla(hp) && note.find("medulla") == std::string::npos) {
    // None of the targets' hair models (pbrt's "hair", Mitsuba's hair, Cycles' Principled Hair) has a
    // scattering core; the nearest each offers is its clear fibre with the cortex's sigma_a.
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "the fibres' medulla (ratio %.3g, sigma_s %.3g %.3g %.3g, sigma_a %.3g %.3g %.3g per radius) has no "
                  "counterpart in this target's hair model: the fibres are exported clear, so pale ones render darker.",
                  double(hp.medulla_ratio), double(hp.medulla_sigma_s.x), double(hp.medulla_sigma_s.y),
                  double(hp.medulla_sigma_s.z), double(hp.medulla_sigma_a.x), double(hp.medulla_sigma_a.y),
                  double(hp.medulla_sigma_a.z));
    if (!note.empty()) note += ' ';
    note += buf;
  }
  return {hp.sigma_a, hp.beta_m, hp.beta_n, hp.alpha_deg, hp.eta};
}

}  // namespace

ExportScene export_scene(const Feather& feather, const DomeRig& rig, const ViewSpec& view,
                         const SceneOptions& options) {
  check_exportable(view);
  // The bounds, backdrop and framing the renderer uses; no curve needs to be in
  // the BVH for them (they are those of the whole feather whatever is culled), and
  // hair mode has the same bounds as substructure mode (render_radius).
  SceneOptions framing;
  framing.backdrop = options.backdrop;
  framing.cull = [](const auto&, float) -> CurveKeep { return [](const auto&) { return false; }; };
  const Scene scene(feather, framing);
  const auto& fb = scene.feather_bounds();
  ExportScene s = view_of(fb, rig, view, options.mode);
  if (options.backdrop.enabled) {
    // The card is the square the scene's bounds grow to in x and y.
    const auto& sb = scene.scene_bounds();
    s.card = ExportCard{{sb.centre().x, sb.centre().y, scene.backdrop_z()}, 0.5f * sb.size().x, options.backdrop.albedo};
  }
  s.material = export_material(feather, view_material(feather, view), fb.centre(), view, s.material_note);
  return s;
}

ExportScene export_scene(const World& world, const DomeRig& rig, const ViewSpec& view, ShadingMode mode,
                         std::vector<ExportMaterial>& materials) {
  check_exportable(view);
  ExportScene s = view_of(world.bounds(), rig, view, mode);
  if (world.backdrop().enabled)
    s.card = ExportCard{{world.backdrop_centre().x, world.backdrop_centre().y, world.backdrop_z()},
                        world.backdrop_half_side(), world.backdrop().albedo};
  materials.clear();
  for (const WorldFeather& f : world.feathers())
    materials.push_back(export_material(f.scene->feather(), *f.material, f.scene->feather_bounds().centre(), view,
                                        s.material_note));
  if (!materials.empty()) s.material = materials.front();
  return s;
}

}  // namespace plumage
