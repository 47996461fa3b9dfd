#include "plumage/renderer/light_set.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plumage {

std::optional<LightSample> LightSet::sample(const glm::vec3& p, float u_pick, const glm::vec2& u) const {
  const std::size_t n = count();
  if (n == 0) return std::nullopt;
  const std::size_t i = std::min(std::size_t(u_pick * float(n)), n - 1);
  const float pick = 1.0f / float(n);
  if (i < spheres_.size()) {
    const SphereLight& l = spheres_[i];
    const auto s = sample_sphere_light(l, p, u);
    if (!s) return std::nullopt;
    return LightSample{s->wi, s->dist, l.radiance, s->pdf * pick, false};
  }
  if (i < spheres_.size() + directional_.size()) {
    const DirectionalLight& l = directional_[i - spheres_.size()];
    return LightSample{l.to_light, std::numeric_limits<float>::infinity(), l.irradiance, pick, true};
  }
  const EnvSample s = env_->sample(u);
  if (!(s.pdf > 0)) return std::nullopt;
  return LightSample{s.wi, std::numeric_limits<float>::infinity(), s.Le, s.pdf * pick, false};
}

std::optional<LightSet::Hit> LightSet::intersect_spheres(const glm::vec3& o, const glm::vec3& d, float tmax) const {
  std::optional<Hit> best;
  const float pick = 1.0f / float(count());
  for (const SphereLight& l : spheres_) {
    const auto t = intersect_sphere(l, o, d);
    if (!t || *t >= tmax || (best && *t >= best->t)) continue;
    best = Hit{l.radiance, *t, sphere_light_pdf(l, o) * pick};
  }
  return best;
}

glm::vec3 LightSet::environment_Le(const glm::vec3& d, float* pdf) const {
  if (!env_) {
    *pdf = 0;
    return glm::vec3(0);
  }
  *pdf = env_->pdf(d) / float(count());
  return env_->Le(d);
}

}  // namespace plumage
