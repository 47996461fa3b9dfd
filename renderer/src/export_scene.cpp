#include "plumage/renderer/export_scene.h"

#include <cstdio>

#include "plumage/common/error.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/shading_mode.h"

namespace plumage {

ExportScene export_scene(const Feather& feather, const DomeRig& rig, const ViewSpec& view,
                         const SceneOptions& options) {
  if (view.environment) throw Error("an environment light is not exported here; set ExportScene::environment");
  if (!view.directional.empty()) throw Error("directional lights are not exported");
  if (view.camera.projection != Projection::Perspective)
    throw Error("only a perspective camera is exported; drop --projection orthographic");
  if (view.max_depth < 0) throw Error("--max-depth must be 0 or more");

  // The bounds, backdrop and framing the renderer uses; no curve needs to be in
  // the BVH for them (they are those of the whole feather whatever is culled), and
  // hair mode has the same bounds as substructure mode (render_radius).
  SceneOptions framing;
  framing.backdrop = options.backdrop;
  framing.cull = [](const auto&, float) -> CurveKeep { return [](const auto&) { return false; }; };
  const Scene scene(feather, framing);
  const auto& fb = scene.feather_bounds();

  ExportScene s;
  s.width = view.width;
  s.height = view.height;
  s.spp = view.spp;
  s.max_depth = view.max_depth;
  s.shading = to_string(options.mode);

  const Camera camera(view.camera, view.width, view.height, fb);
  const glm::vec3 target = view.camera.look_at.value_or(fb.centre());
  s.camera.eye = camera.position();
  s.camera.look_at = camera.position() + camera.forward() * glm::length(target - camera.position());
  s.camera.up = view.camera.up;
  s.camera.fov_deg = view.camera.fov_deg;

  const LightSet lights = view_lights(fb, rig, view);
  for (const SphereLight& l : lights.spheres()) s.lights.push_back({l.centre, l.radius, l.radiance});

  if (options.backdrop.enabled) {
    // The card is the square the scene's bounds grow to in x and y.
    const auto& sb = scene.scene_bounds();
    s.card = ExportCard{{sb.centre().x, sb.centre().y, scene.backdrop_z()}, 0.5f * sb.size().x, options.backdrop.albedo};
  }

  const FibreMaterial material = view_material(feather, view);
  const HairParams hp = material.at(fb.centre());
  s.material = {hp.sigma_a, hp.beta_m, hp.beta_n, hp.alpha_deg, hp.eta};
  if (!feather.albedo.texture.empty() && !view.sigma_a)
    s.material_note = "sigma_a is the one plumage gives the feather's centre: the albedo texture is not exported.";
  if (has_medulla(hp)) {
    // None of the targets' hair models (pbrt's "hair", Mitsuba's hair, Cycles' Principled Hair) has a
    // scattering core; the nearest each offers is its clear fibre with the cortex's sigma_a.
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "the fibres' medulla (ratio %.3g, sigma_s %.3g %.3g %.3g, sigma_a %.3g %.3g %.3g per radius) has no "
                  "counterpart in this target's hair model: the fibres are exported clear, so pale ones render darker.",
                  double(hp.medulla_ratio), double(hp.medulla_sigma_s.x), double(hp.medulla_sigma_s.y),
                  double(hp.medulla_sigma_s.z), double(hp.medulla_sigma_a.x), double(hp.medulla_sigma_a.y),
                  double(hp.medulla_sigma_a.z));
    if (!s.material_note.empty()) s.material_note += ' ';
    s.material_note += buf;
  }
  return s;
}

}  // namespace plumage
