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
  // Adaptive sampling (off by default; docs/skip-work.md): a pixel stops once the
  // standard error of its mean luminance, relative to that mean, is at most
  // target_error, checked every check_every samples from min_spp on; spp is the cap.
  // Stopping on the pixel's own estimate biases it slightly toward early agreement.
  bool adaptive = false;
  float target_error = 0.02f;
  int min_spp = 16;
  int check_every = 8;
};

// Throws plumage::Error for spp < 1, threads < 0, tile_size < 1 or bad adaptive settings.
Film render(const Camera& camera, const PathIntegrator& integrator, const RenderSettings& settings);

}  // namespace plumage
