#pragma once
// The lights of a render: the dome's LEDs that are switched on (sphere lights),
// directional lights and an optional environment; lights that are off are simply
// not in the set. Light i is the i-th sphere, then the directional lights, then
// the environment. How next-event estimation chooses among them (LightPick) is
// the integrator's business; this class gives per-light sampling, pdfs, and the
// estimates the integrator weighs its choice with (docs/rendering.md, "Lights").
#include <algorithm>
#include <limits>
#include <optional>
#include <span>
#include <string>
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
  float pdf;          // solid-angle pdf of this light's own sampling (1 for delta lights)
  bool delta;         // cannot be hit by BCSDF sampling
};

// What every light delivers to a point, roughly, for weighing the choice of light:
// an unoccluded estimate of light i's contribution is lum(f_cos(wi_i) * strength_i).
// Structure of arrays, one entry per light in LightSet order, so that the loops
// over the 25 LEDs vectorise.
struct LightProxies {
  // Toward the light's centre (sphere, directional); (0, 0, 1) for the environment.
  std::vector<float> x, y, z;
  // Le x solid angle (sphere), irradiance (directional), pi x mean Le (environment).
  std::vector<float> r, g, b;
  // The entry with no single direction (the environment); the count when none.
  std::size_t environment = 0;
  std::size_t size() const { return x.size(); }
  glm::vec3 wi(std::size_t i) const { return {x[i], y[i], z[i]}; }
  glm::vec3 strength(std::size_t i) const { return {r[i], g[i], b[i]}; }
};

// How next-event estimation chooses the light it sends a shadow ray to.
enum class LightPick {
  Uniform,   // one light, each with probability 1/count
  Estimate,  // one light, in proportion to its unoccluded estimate (mixed with uniform)
  All,       // every light, one shadow ray each
};
// Every choice, in the order the CLI lists them (the default first).
inline constexpr LightPick kLightPicks[] = {LightPick::Estimate, LightPick::Uniform, LightPick::All};
const char* to_string(LightPick pick);
// "uniform", "estimate" or "all"; throws plumage::Error naming the choices otherwise.
LightPick parse_light_pick(const std::string& name);

// The part of the selection pmf that stays uniform, so every light keeps a
// probability of at least kUniformPickShare / count whatever the estimates say
// (an estimate at the light's centre can be zero where the light is not).
inline constexpr float kUniformPickShare = 0.1f;

// Fills `pmf` (same size as `estimates`) with (1 - s) w_i / sum(w) + s / n, s =
// kUniformPickShare; uniform when the estimates sum to zero or are not finite.
// Negative or non-finite estimates count as zero.
void light_pick_pmf(std::span<const float> estimates, std::span<float> pmf);
// The index whose cdf interval holds u in [0,1) (the last light with p > 0 for u
// beyond a cdf that rounding left below 1).
std::size_t pick_from_pmf(std::span<const float> pmf, float u);

class LightSet {
 public:
  void add(const SphereLight& l) {
    spheres_.push_back(l);
    sphere_floor_ = std::min(sphere_floor_, l.centre.z - l.radius);
    for (int c = 0; c < 3; ++c) {
      soa_centre_[c].push_back(l.centre[c]);
      soa_radiance_[c].push_back(l.radiance[c]);
    }
    soa_r2_.push_back(l.radius * l.radius);
  }
  void add(const DirectionalLight& l) { directional_.push_back(l); }
  void set_environment(EnvironmentLight env) { env_ = std::move(env); }

  std::size_t count() const { return spheres_.size() + directional_.size() + (env_ ? 1 : 0); }
  bool empty() const { return count() == 0; }
  const std::vector<SphereLight>& spheres() const { return spheres_; }
  const EnvironmentLight* environment() const { return env_ ? &*env_ : nullptr; }
  // Index of the environment among the lights (count() when there is none).
  std::size_t environment_index() const { return env_ ? count() - 1 : count(); }
  // The lights next-event estimation needs where the scatterer samples its own
  // f cos (a card, a fibre): indices 0 .. sampled_count() - 1, every light but a
  // constant environment. For constant L_e a vertex integrates L_e f cos V, and
  // directions drawn in proportion to f cos (exactly for a card, the lobe mixture
  // of a fibre) do at least as well as uniform ones on the sphere, so that light is
  // left to BCSDF sampling alone (docs/rendering.md, "Integrator").
  std::size_t sampled_count() const { return env_ && env_->is_constant() ? count() - 1 : count(); }
  // Whether a ray sampled by such a scatterer can reach a light that next-event
  // estimation samples too (a sphere, a varying environment), so that MIS needs the
  // ray's pdf. Directional lights cannot be hit; a constant environment is not sampled.
  bool hit_by_sampled_rays() const { return !spheres_.empty() || (env_ && !env_->is_constant()); }

  // A direction on light i as seen from p, sampled with u; pdf excludes the choice of light.
  std::optional<LightSample> sample(std::size_t i, const glm::vec3& p, const glm::vec2& u) const;
  // Every light's proxy as seen from p (resizes `out` to count()).
  void proxies(const glm::vec3& p, LightProxies& out) const;

  // The nearest sphere light along the ray closer than tmax: which, its radiance,
  // distance and the pdf that sampling that light from `o` gives that direction.
  struct Hit {
    std::size_t light;
    glm::vec3 Le;
    float t;
    float pdf;
  };
  std::optional<Hit> intersect_spheres(const glm::vec3& o, const glm::vec3& d, float tmax) const;
  // Environment radiance along d and the pdf its own sampling gives d (zero Le
  // without an environment).
  glm::vec3 environment_Le(const glm::vec3& d, float* pdf) const;

 private:
  std::vector<SphereLight> spheres_;
  std::vector<DirectionalLight> directional_;
  std::optional<EnvironmentLight> env_;
  // The lowest z of any sphere light: a ray below it heading down meets none.
  float sphere_floor_ = std::numeric_limits<float>::infinity();
  // The spheres again as structure of arrays (centre x, y, z; radius^2; radiance
  // r, g, b) for the loops over every LED.
  std::vector<float> soa_centre_[3], soa_r2_, soa_radiance_[3];
};

}  // namespace plumage
