#pragma once
// Unidirectional path tracing (Kajiya 1986) with next-event estimation and
// multiple importance sampling between light sampling and BCSDF sampling (Veach &
// Guibas 1995, power heuristic), and Russian roulette. Every hit is shaded through
// a Bsdf (bsdf.h): barbs by the shading mode's model (barb_shading.h), the shaft as
// a round fibre, the backdrop as a two-sided lambertian card.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/renderer/barb_shading.h"
#include "plumage/renderer/bsdf.h"
#include "plumage/renderer/fibre_material.h"
#include "plumage/renderer/light_set.h"
#include "plumage/renderer/sampler.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/world.h"

namespace plumage {

struct IntegratorSettings {
  int max_depth = 16;  // scattering events; 1 = direct lighting only
  int rr_depth = 3;    // Russian roulette from this many bounces on
  // How next-event estimation chooses its light (docs/rendering.md, "Lights").
  LightPick light_pick = LightPick::Estimate;
  // Estimate and Uniform: lights sampled per vertex (at most the number of
  // lights), stratified over the choice's pmf (pick k draws from [k, k+1)/picks),
  // each a shadow ray; MIS counts the light strategy's density picks times
  // (docs/rendering.md, "Lights").
  int light_picks = 4;
};

// Per-thread tallies, added to the global StatCounters once per tile.
struct PathCounters {
  std::int64_t rays = 0, shadow_rays = 0, hits = 0, bad_samples = 0;
};

class PathIntegrator {
 public:
  // Throws plumage::Error for settings.light_picks < 1. In farfield mode, fits (or
  // reads from the cache) each vane's table for the material at the feather's centre.
  PathIntegrator(const Scene& scene, const LightSet& lights, const FibreMaterial& material,
                 const IntegratorSettings& settings);
  // The same over a world of placed feathers (world.h), each shaded with its own
  // material; farfield mode fits each distinct feather's tables.
  PathIntegrator(const World& world, const LightSet& lights, const IntegratorSettings& settings);

  // Radiance arriving along -ray.d at ray.o. Non-finite or negative estimates are
  // counted in `counters.bad_samples` and returned as zero.
  glm::vec3 Li(Ray ray, PixelSampler& sampler, PathCounters& counters) const;

 private:
  // The hit's Bsdf in world directions; a placed feather's is built in `local`
  // and wrapped in `slot` (placed_bsdf.h).
  const Bsdf& bsdf_at(const WorldHit& hit, const glm::vec3& wo, BsdfSlot& slot, BsdfSlot& local) const;
  void make_shadings();

  std::unique_ptr<const World> own_world_;  // the one-feather world of the Scene constructor
  const World& world_;
  const LightSet& lights_;
  IntegratorSettings settings_;
  bool bsdf_pdf_needed_;  // MIS weighs BCSDF-sampled rays that reach a light (LightSet::hit_by_sampled_rays)
  std::vector<std::unique_ptr<const BarbShading>> barbs_;  // per distinct feather: its shading mode's model
};

// Veach's power heuristic (beta = 2) for one sample of each of two strategies.
inline float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0 ? a / (a + b) : 0.0f;
}

}  // namespace plumage
