#pragma once
// The lights of a render: the dome's LEDs that are switched on (sphere lights),
// directional lights and an optional environment. Next-event estimation picks one
// light uniformly; lights that are off are simply not in the set.
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/renderer/environment_light.h"
#include "plumage/renderer/sphere_light.h"

namespace plumage {

// A distant light (sun-like): a delta in direction, given by its irradiance on a
// surface facing it.
struct DirectionalLight {
  glm::vec3 to_light{0, 0, 1};  // unit, from the scene toward the light
  glm::vec3 irradiance{1};      // W / mm^2
};

struct LightSample {
  glm::vec3 wi;       // unit, toward the light
  float dist;         // distance to the emitter (infinity for distant lights)
  glm::vec3 Le;       // radiance (irradiance for a delta light)
  float pdf;          // solid-angle pdf including the choice of the light; 1/count for delta lights
  bool delta;         // cannot be hit by BCSDF sampling
};

class LightSet {
 public:
  void add(const SphereLight& l) { spheres_.push_back(l); }
  void add(const DirectionalLight& l) { directional_.push_back(l); }
  void set_environment(EnvironmentLight env) { env_ = std::move(env); }

  std::size_t count() const { return spheres_.size() + directional_.size() + (env_ ? 1 : 0); }
  bool empty() const { return count() == 0; }
  const std::vector<SphereLight>& spheres() const { return spheres_; }
  const EnvironmentLight* environment() const { return env_ ? &*env_ : nullptr; }

  // One light chosen with u_pick, then a direction on it with u.
  std::optional<LightSample> sample(const glm::vec3& p, float u_pick, const glm::vec2& u) const;

  // The nearest sphere light along the ray closer than tmax: its radiance, distance
  // and the pdf light sampling from `o` would have given that direction.
  struct Hit {
    glm::vec3 Le;
    float t;
    float pdf;
  };
  std::optional<Hit> intersect_spheres(const glm::vec3& o, const glm::vec3& d, float tmax) const;
  // Environment radiance along d and its light-sampling pdf (zero Le without an environment).
  glm::vec3 environment_Le(const glm::vec3& d, float* pdf) const;

 private:
  std::vector<SphereLight> spheres_;
  std::vector<DirectionalLight> directional_;
  std::optional<EnvironmentLight> env_;
};

}  // namespace plumage
