#include "plumage/renderer/feather_render.h"
#include "plumage/renderer/denoise.h"
#include "plumage/common/image.h"

#include <cmath>
#include <numbers>

#include "plumage/common/error.h"
#include "plumage/renderer/render.h"

namespace plumage {

namespace {
// The view's exposure, or the one that develops the lit card to view.card_level.
float exposure_for(const World& world, const LightSet& lights, const ViewSpec& view) {
  if (!(view.card_level > 0) || !world.backdrop().enabled) return view.exposure;
  const glm::vec3 centre(world.bounds().centre().x, world.bounds().centre().y, world.backdrop_z());
  glm::vec3 E(0);
  for (const SphereLight& l : lights.spheres()) E += sphere_light_irradiance(l, centre, {0, 0, 1});
  const glm::vec3 card = world.backdrop().albedo * E / std::numbers::pi_v<float>;
  const float level = luminance(card);
  return level > 0 ? std::log2(view.card_level / level) : view.exposure;
}
}  // namespace

LightSet view_lights(const Bounds3f& fb, const DomeRig& rig, const ViewSpec& view) {
  LightSet lights;
  for (const SphereLight& l : dome_lights(rig, parse_light_selection(view.lights, int(rig.leds.size())),
                                          {fb.centre().x, fb.centre().y, fb.lo.z}))
    lights.add(l);
  if (view.environment) lights.set_environment(*view.environment);
  for (const DirectionalLight& d : view.directional) lights.add(d);
  return lights;
}

FibreMaterial view_material(const Feather& feather, const ViewSpec& view, ShadingMode mode) {
  validate(view.hair, "--beta-m/--beta-n/--alpha/--eta");
  HairParams fibre = view.hair;
  if (feather.medulla.ratio > 0 && !has_medulla(fibre)) {  // the curve file's medulla, unless the view sets one
    fibre.medulla_ratio = feather.medulla.ratio;
    fibre.medulla_sigma_s = feather.medulla.sigma_s;
    fibre.medulla_sigma_a = feather.medulla.sigma_a;
  }
  if (!view.sigma_a) {
    FibreMaterial m(fibre, AlbedoMap(feather.albedo, view.base_dir, feather.shaft()));
    // Down barbs are fibres in every mode: the hair response's correction.
    if (view.photo_card)
      m.set_card(*view.photo_card, card_response(mode), view.photo_texture_absolute, view.photo_gain,
                 &card_response(ShadingMode::Hair));
    return m;
  }
  HairParams hp = fibre;
  hp.sigma_a = *view.sigma_a;
  return FibreMaterial(hp);
}

Image render_view(const Scene& scene, const DomeRig& rig, const ViewSpec& view) {
  const FibreMaterial material = view_material(scene.feather(), view, scene.options().mode);
  return render_view(World(scene, material), rig, view);
}

Image render_view(const World& world, const DomeRig& rig, const ViewSpec& view) {
  const Bounds3f& fb = world.bounds();
  const LightSet lights = view_lights(fb, rig, view);
  if (view.max_depth < 0) throw Error("--max-depth must be 0 or more");
  IntegratorSettings is;
  is.max_depth = view.max_depth;
  is.light_pick = view.light_pick;
  const PathIntegrator integrator(world, lights, is);
  const Camera camera(view.camera, view.width, view.height, fb);
  RenderSettings rs;
  rs.spp = view.spp;
  rs.seed = view.seed;
  rs.sampler = view.sampler;
  rs.threads = view.threads;
  rs.progress = view.progress;
  rs.adaptive = view.adaptive;
  rs.allocation = view.allocation;
  rs.target_error = view.target_error;
  rs.min_spp = view.min_spp;
  rs.tile_index = view.tile_index;
  rs.tile_count = view.tile_count;
  rs.keep_variance = view.denoise;
  if (view.denoise && view.tile_count > 1)
    throw Error("--denoise filters the whole image, so a part of a split render (--tile) cannot take it; "
                "render the parts without it");
  const Film film = render(camera, integrator, rs);
  const float exposure = exposure_for(world, lights, view);
  if (!view.denoise) return film.developed(exposure);
  DenoiseSettings ds;
  ds.threads = view.threads;
  return denoise(film.developed(exposure), film.developed_variance(exposure), ds);
}

}  // namespace plumage
