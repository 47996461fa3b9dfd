#include "plumage/renderer/feather_render.h"

#include "plumage/renderer/render.h"

namespace plumage {

Image render_view(const Scene& scene, const DomeRig& rig, const ViewSpec& view) {
  const AxisBox& fb = scene.feather_bounds();
  LightSet lights;
  // The rig sits on the feather's lowest point, as in `plumage render`.
  for (const SphereLight& l : dome_lights(rig, parse_light_selection(view.lights, int(rig.leds.size())),
                                          {fb.centre().x, fb.centre().y, fb.lo.z}))
    lights.add(l);
  validate(view.hair, "--beta-m/--beta-n/--alpha/--eta");
  const FibreMaterial material(view.hair, AlbedoMap(scene.feather().albedo, view.base_dir));
  IntegratorSettings is;
  is.max_depth = view.max_depth;
  const PathIntegrator integrator(scene, lights, material, is);
  const Camera camera(view.camera, view.width, view.height, fb);
  RenderSettings rs;
  rs.spp = view.spp;
  rs.seed = view.seed;
  rs.threads = view.threads;
  rs.progress = view.progress;
  return render(camera, integrator, rs).developed(view.exposure);
}

}  // namespace plumage
