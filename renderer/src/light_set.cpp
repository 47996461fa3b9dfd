#include "plumage/renderer/light_set.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

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
  // Negative or non-finite estimates count as zero (NaN fails the comparisons).
  constexpr float kMax = std::numeric_limits<float>::max();
  for (std::size_t i = 0; i < n; ++i) pmf[i] = (estimates[i] > 0) & (estimates[i] <= kMax) ? estimates[i] : 0.0f;
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += pmf[i];
  const float uniform = 1.0f / float(n);
  if (!(sum > 0) || !std::isfinite(sum)) {
    std::fill(pmf.begin(), pmf.begin() + std::ptrdiff_t(n), uniform);
    return;
  }
  // In double: the scale of estimates near the float minimum does not fit a float.
  const double scale = (1.0 - double(kUniformPickShare)) / sum, floor = double(kUniformPickShare) * uniform;
  for (std::size_t i = 0; i < n; ++i) pmf[i] = float(double(pmf[i]) * scale + floor);
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

namespace {

// proxies()'s loop over the spheres, branch-free (every value computed and then
// selected) and over plain pointers, so that GCC vectorises it.
void sphere_proxies(std::size_t n, const float* cx, const float* cy, const float* cz, const float* r2,
                    const float* lr, const float* lg, const float* lb, glm::vec3 p, float* __restrict x,
                    float* __restrict y, float* __restrict z, float* __restrict sr, float* __restrict sg,
                    float* __restrict sb) {
  constexpr float k2Pi = 2.0f * std::numbers::pi_v<float>;
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = cx[i] - p.x, dy = cy[i] - p.y, dz = cz[i] - p.z;
    const float d2 = dx * dx + dy * dy + dz * dz;
    const float inv_d = 1.0f / std::sqrt(d2);
    // The cone's solid angle 2 pi (1 - cos theta_max) (sphere_light_pdf's
    // reciprocal); inside the sphere the light surrounds p: 2 pi is a fair share.
    const float s2 = r2[i] / d2;
    const float omc = s2 / (1.0f + std::sqrt(std::max(0.0f, 1.0f - s2)));
    const float solid_angle = d2 > r2[i] ? k2Pi * omc : k2Pi;
    const bool away = d2 > 0;
    x[i] = away ? dx * inv_d : 0.0f;
    y[i] = away ? dy * inv_d : 0.0f;
    z[i] = away ? dz * inv_d : 1.0f;
    sr[i] = lr[i] * solid_angle;
    sg[i] = lg[i] * solid_angle;
    sb[i] = lb[i] * solid_angle;
  }
}

// intersect_sphere for every sphere at once, branch-free: t[i] is the distance
// it gives, or infinity for a miss.
void sphere_distances(std::size_t n, const float* cx, const float* cy, const float* cz, const float* r2, glm::vec3 o,
                      glm::vec3 d, float* __restrict t) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const float ox = cx[i] - o.x, oy = cy[i] - o.y, oz = cz[i] - o.z;
    const float b = ox * d.x + oy * d.y + oz * d.z;
    const float c = ox * ox + oy * oy + oz * oz - r2[i];
    const float px = ox - b * d.x, py = oy - b * d.y, pz = oz - b * d.z;
    const float disc = r2[i] - (px * px + py * py + pz * pz);
    const float s = std::sqrt(std::max(disc, 0.0f));
    const bool outside = c > 0;
    const float ti = outside ? b - s : b + s;  // the near side, or the far side from inside
    const bool hit = (disc >= 0) & ((c <= 0) | ((b > 0) & (ti > 0)));
    t[i] = hit ? ti : kInf;
  }
}

}  // namespace

void LightSet::proxies(const glm::vec3& p, LightProxies& out) const {
  const std::size_t n = count(), ns = spheres_.size();
  for (auto* v : {&out.x, &out.y, &out.z, &out.r, &out.g, &out.b}) v->resize(n);
  out.environment = env_ ? n - 1 : n;
  float *x = out.x.data(), *y = out.y.data(), *z = out.z.data();
  float *sr = out.r.data(), *sg = out.g.data(), *sb = out.b.data();
  sphere_proxies(ns, soa_centre_[0].data(), soa_centre_[1].data(), soa_centre_[2].data(), soa_r2_.data(),
                 soa_radiance_[0].data(), soa_radiance_[1].data(), soa_radiance_[2].data(), p, x, y, z, sr, sg, sb);
  for (std::size_t k = 0; k < directional_.size(); ++k) {
    const DirectionalLight& l = directional_[k];
    const std::size_t i = ns + k;
    x[i] = l.to_light.x, y[i] = l.to_light.y, z[i] = l.to_light.z;
    sr[i] = l.irradiance.x, sg[i] = l.irradiance.y, sb[i] = l.irradiance.z;
  }
  if (env_) {
    const std::size_t i = n - 1;
    const float e = std::numbers::pi_v<float> * env_->mean_luminance();
    x[i] = 0, y[i] = 0, z[i] = 1;
    sr[i] = sg[i] = sb[i] = e;
  }
}

std::optional<LightSet::Hit> LightSet::intersect_spheres(const glm::vec3& o, const glm::vec3& d, float tmax) const {
  std::optional<Hit> best;
  // No LED is hit by a segment that stays below the lowest one: most bounces off a
  // feather under a dome head down, and most that head up meet a barb first.
  const float top = d.z > 0 ? o.z + d.z * tmax : o.z;  // +inf for an open ray upward
  if (top < sphere_floor_) return best;
  const std::size_t n = spheres_.size();
  thread_local std::vector<float> t;
  t.resize(n);
  sphere_distances(n, soa_centre_[0].data(), soa_centre_[1].data(), soa_centre_[2].data(), soa_r2_.data(), o, d,
                   t.data());
  // The first of the nearest (as one sphere after the other would find it).
  std::size_t which = n;
  float nearest = tmax;
  for (std::size_t i = 0; i < n; ++i)
    if (t[i] < nearest) nearest = t[i], which = i;
  if (which < n) best = Hit{which, spheres_[which].radiance, nearest, sphere_light_pdf(spheres_[which], o)};
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
