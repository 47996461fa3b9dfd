#pragma once
// The white furnace at full depth for the in-vane ribbon modes (substructure,
// farfield): fibres with sigma_a = 0 under a white environment can only pass on
// what they receive, so every pixel's mean stays at most 1 (within the Monte Carlo
// error) and most light that enters the ribbons comes back out.
#include <gtest/gtest.h>

#include "plumage/renderer/path_integrator.h"
#include "plumage/renderer/render.h"
#include "plumage/renderer/scene.h"

namespace plumage::test {

// A top view of make_test_feather(12, 0.4, 0.05): 12 x 12 pixels over its middle.
inline Camera furnace_camera(const Scene& scene) {
  CameraSpec cs;
  cs.position = glm::vec3(1.0f, 6.5f, 3.0f);
  cs.look_at = glm::vec3(1.0f, 6.5f, 0.0f);
  return Camera(cs, 12, 12, scene.feather_bounds());
}

// That view at 256 spp (independent sampler, depth 64) with sigma_a = 0 under a
// white environment; no pixel above 1.08, the mean in [min_mean, 1.01].
inline void expect_furnace(const Scene& scene, double min_mean) {
  LightSet lights;
  lights.set_environment(EnvironmentLight(glm::vec3(1.0f)));
  HairParams hp;
  hp.sigma_a = glm::vec3(0.0f);
  const FibreMaterial material(hp);
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{64, 64});
  RenderSettings rs;
  rs.spp = 256;
  rs.progress = false;
  rs.sampler = SamplerKind::Independent;
  const Image img = render(furnace_camera(scene), integrator, rs).developed(0);
  double sum = 0;
  for (float v : img.pixels) {
    EXPECT_LE(v, 1.08f);
    sum += v;
  }
  const double mean = sum / double(img.pixels.size());
  EXPECT_LE(mean, 1.01);
  EXPECT_GE(mean, min_mean);
}

}  // namespace plumage::test
