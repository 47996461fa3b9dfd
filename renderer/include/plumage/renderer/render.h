#pragma once
// Renders an image: tiles of pixels in parallel (TBB), each pixel's samples drawn
// from its own deterministic stream, so the result for a seed does not depend on
// the number of threads or the order tiles finish in.
#include <cstdint>

#include "plumage/renderer/camera.h"
#include "plumage/renderer/film.h"
#include "plumage/renderer/path_integrator.h"
#include "plumage/renderer/sampler.h"

namespace plumage {

struct RenderSettings {
  int spp = 16;
  std::uint64_t seed = 0;
  SamplerKind sampler = SamplerKind::Sobol;
  int threads = 0;        // 0 = all cores
  int tile_size = 16;
  bool progress = true;   // a progress bar over tiles (still silent under --quiet)
};

// Throws plumage::Error for spp < 1, threads < 0 or tile_size < 1.
Film render(const Camera& camera, const PathIntegrator& integrator, const RenderSettings& settings);

}  // namespace plumage
