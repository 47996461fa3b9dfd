#pragma once
// Renders an image: tiles of pixels in parallel (TBB), each pixel's samples drawn
// from its own deterministic stream, so the result for a seed does not depend on
// the number of threads or the order tiles finish in.
#include <cstdint>
#include <string>
#include <vector>

#include "plumage/common/image.h"
#include "plumage/renderer/camera.h"
#include "plumage/renderer/film.h"
#include "plumage/renderer/path_integrator.h"
#include "plumage/renderer/sampler.h"

namespace plumage {

// How a render spreads its samples over the pixels (docs/skip-work.md, "Sample
// allocation").
enum class SampleAllocation {
  Uniform,   // every pixel takes spp samples
  Variance,  // a pilot of spp/4 per pixel, then the rest of the budget in proportion
             // to the noise the pilot found around each pixel; unbiased
};
inline constexpr SampleAllocation kSampleAllocations[] = {SampleAllocation::Variance, SampleAllocation::Uniform};
const char* to_string(SampleAllocation a);
// "uniform" or "variance"; throws plumage::Error naming the choices otherwise.
SampleAllocation parse_sample_allocation(const std::string& name);

// Variance allocation's per-pixel sample counts from the pilot's per-pixel
// luminance variance and cost (rays per sample), row-major, width x height: pilot
// plus a share of the remaining (spp - pilot) x pixels samples in proportion to
// sigma / sqrt(cost) (which minimises the summed variance for the time spent),
// both taken as the means over the pixel's 3x3 neighbours with itself left out.
// A pixel's count is computed without its own figures, in the normalisation too,
// so a pixel's samples never decide how many it gets: its mean stays unbiased.
std::vector<int> allocate_samples(const std::vector<double>& variance, const std::vector<double>& cost, int width,
                                  int height, int spp, int pilot);

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
  // Ignored with `adaptive`, and below 8 spp (too few for a pilot).
  SampleAllocation allocation = SampleAllocation::Variance;
  // A split render (docs/rendering.md, "Split renders"): part tile_index of
  // tile_count renders only the rows tile_rows() gives it; every other pixel is 0.
  // Its pixels are the single render's, bit for bit: each pixel's samples come from
  // its own stream, and variance allocation's pilot still covers the whole image
  // (each part pays that quarter of the samples everywhere).
  int tile_index = 0;
  int tile_count = 1;
  // Keep each pixel's variance of the mean in the film (Film::developed_variance),
  // for a filter that needs it (denoise.h): 24 more bytes a pixel while rendering.
  bool keep_variance = false;
};

// The rows [first, last) part `index` of `count` renders of an image `height` rows tall.
struct TileRows {
  int first, last;
};
TileRows tile_rows(int height, int index, int count);
// The image the parts make together: part k (in the order given, k = 0 .. N-1)
// gives the rows tile_rows(H, k, N). Throws plumage::Error for no parts, parts of
// different sizes or channels, or a part with a non-zero pixel outside its rows
// (parts out of order, or from another N), naming the part.
Image merge_tiles(const std::vector<Image>& parts);

// Throws plumage::Error for spp < 1, threads < 0, tile_size < 1, a tile outside
// 0 <= tile_index < tile_count or bad adaptive settings.
Film render(const Camera& camera, const PathIntegrator& integrator, const RenderSettings& settings);

}  // namespace plumage
