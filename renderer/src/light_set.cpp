#include "plumage/renderer/light_set.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "plumage/common/error.h"

namespace plumage {

const char* to_string(LightPick pick) {
  switch (pick) {
    case LightPick::Uniform: return "uniform";
    case LightPick::Estimate: return "estimate";
    case LightPick::All: return "all";
  }
  return "?";
}

LightPick parse_light_pick(const std::string& name) {
  for (LightPick p : kLightPicks)
    if (name == to_string(p)) return p;
  throw Error("--light-pick '" + name + "': give uniform, estimate or all");
}

void light_pick_pmf(std::span<const float> estimates, std::span<float> pmf) {
  const std::size_t n = estimates.size();
  if (n == 0) return;
  double sum = 0;
  for (float w : estimates)
    if (w > 0 && std::isfinite(w)) sum += w;
  const float uniform = 1.0f / float(n);
  if (!(sum > 0) || !std::isfinite(sum)) {
    std::fill(pmf.begin(), pmf.begin() + std::ptrdiff_t(n), uniform);
    return;
  }
  const double scale = (1.0 - double(kUniformPickShare)) / sum;
  for (std::size_t i = 0; i < n; ++i) {
    const float w = estimates[i] > 0 && std::isfinite(estimates[i]) ? estimates[i] : 0.0f;
    pmf[i] = float(double(w) * scale + double(kUniformPickShare) * uniform);
  }
}

std::size_t pick_from_pmf(std::span<const float> pmf, float u) {
  std::size_t last = 0;
  float cdf = 0;
  for (std::size_t i = 0; i < pmf.size(); ++i) {
    if (!(pmf[i] > 0)) continue;
    last = i;
    cdf += pmf[i];
    if (u < cdf) return i;
  }
  return last;
}

std::optional<LightSample> LightSet::sample(std::size_t i, const glm::vec3& p, const glm::vec2& u) const {
  if (i < spheres_.size()) {
    const SphereLight& l = spheres_[i];
    const auto s = sample_sphere_light(l, p, u);
    if (!s) return std::nullopt;
    return LightSample{s->wi, s->dist, l.radiance, s->pdf, false};
  }
  if (i < spheres_.size() + directional_.size()) {
    const DirectionalLight& l = directional_[i - spheres_.size()];
    return LightSample{l.to_light, std::numeric_limits<float>::infinity(), l.irradiance, 1.0f, true};
  }
  if (!env_) return std::nullopt;
  const EnvSample s = env_->sample(u);
  if (!(s.pdf > 0)) return std::nullopt;
  return LightSample{s.wi, std::numeric_limits<float>::infinity(), s.Le, s.pdf, false};
}

LightProxy LightSet::proxy(std::size_t i, const glm::vec3& p) const {
  if (i < spheres_.size()) {
    const SphereLight& l = spheres_[i];
    const glm::vec3 to_c = l.centre - p;
    const float d2 = glm::dot(to_c, to_c);
    // Inside the sphere the light surrounds p: 2 pi of solid angle is a fair share.
    const float pdf = sphere_light_pdf(l, p);
    const float solid_angle = pdf > 0 ? 1.0f / pdf : 2.0f * std::numbers::pi_v<float>;
    return {d2 > 0 ? to_c / std::sqrt(d2) : glm::vec3(0, 0, 1), l.radiance * solid_angle, true};
  }
  if (i < spheres_.size() + directional_.size()) {
    const DirectionalLight& l = directional_[i - spheres_.size()];
    return {l.to_light, l.irradiance, true};
  }
  if (!env_) return {};
  return {glm::vec3(0, 0, 1), glm::vec3(std::numbers::pi_v<float> * env_->mean_luminance()), false};
}

std::optional<LightSet::Hit> LightSet::intersect_spheres(const glm::vec3& o, const glm::vec3& d, float tmax) const {
  std::optional<Hit> best;
  // No LED is hit by a segment that stays below the lowest one: most bounces off a
  // feather under a dome head down, and most that head up meet a barb first.
  const float top = d.z > 0 ? o.z + d.z * tmax : o.z;  // +inf for an open ray upward
  if (top < sphere_floor_) return best;
  for (std::size_t i = 0; i < spheres_.size(); ++i) {
    const SphereLight& l = spheres_[i];
    const auto t = intersect_sphere(l, o, d);
    if (!t || *t >= tmax || (best && *t >= best->t)) continue;
    best = Hit{i, l.radiance, *t, sphere_light_pdf(l, o)};
  }
  return best;
}

glm::vec3 LightSet::environment_Le(const glm::vec3& d, float* pdf) const {
  if (!env_) {
    *pdf = 0;
    return glm::vec3(0);
  }
  *pdf = env_->pdf(d);
  return env_->Le(d);
}

}  // namespace plumage
