#include "plumage/renderer/render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include <tbb/blocked_range2d.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "float_mode.h"
#include "plumage/common/error.h"
#include "plumage/common/interrupt.h"
#include "plumage/common/progress.h"
#include "plumage/common/stats.h"

namespace plumage {
namespace {
StatCounter g_rays("Renderer/Rays traced");
StatCounter g_shadow_rays("Renderer/Shadow rays");
StatCounter g_hits("Renderer/Ray hits");
StatCounter g_bad("Renderer/NaN or Inf samples dropped");
StatCounter g_samples("Renderer/Camera samples");
StatCounter g_saved("Renderer/Camera samples saved by adaptive sampling");

// Relative standard error of a mean from n samples' sum and sum of squares.
bool converged(double sum, double sum_sq, int n, double target) {
  const double mean = sum / n;
  const double var = std::max(0.0, (sum_sq - sum * mean) / (n - 1));
  return std::sqrt(var / n) <= target * mean || (mean <= 0 && var <= 0);
}
}  // namespace

const char* to_string(SampleAllocation a) { return a == SampleAllocation::Uniform ? "uniform" : "variance"; }

SampleAllocation parse_sample_allocation(const std::string& name) {
  for (SampleAllocation a : kSampleAllocations)
    if (name == to_string(a)) return a;
  throw Error("unknown sample allocation '" + name + "'; choose uniform or variance");
}

std::vector<int> allocate_samples(const std::vector<double>& variance, const std::vector<double>& cost, int W, int H,
                                  int spp, int pilot) {
  const std::size_t P = std::size_t(W) * std::size_t(H);
  auto at = [&](const std::vector<double>& v, int x, int y) { return std::max(0.0, v[std::size_t(y) * W + x]); };
  auto neighbours = [&](int x, int y, auto&& f) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if ((dx != 0 || dy != 0) && nx >= 0 && ny >= 0 && nx < W && ny < H) f(nx, ny);
      }
  };
  // Per pixel, its neighbours' (3x3 without the centre) summed variance and cost.
  std::vector<double> vsum(P, 0.0), csum(P, 0.0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      neighbours(x, y, [&](int nx, int ny) {
        vsum[std::size_t(y) * W + x] += at(variance, nx, ny);
        csum[std::size_t(y) * W + x] += at(cost, nx, ny);
      });
  // sigma / sqrt(cost) from the sums (the count cancels); 0 where nothing is known.
  auto weight = [](double v, double c) { return v > 0 && c > 0 ? std::sqrt(v / c) : 0.0; };
  std::vector<double> w(P);
  double total = 0;
  for (std::size_t i = 0; i < P; ++i) total += (w[i] = weight(vsum[i], csum[i]));
  const double budget = double(spp - pilot) * double(P);
  std::vector<int> n(P, spp);
  if (!(budget > 0)) return n;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t i = std::size_t(y) * W + x;
      // The total as it would be without pixel i's own figures: its neighbours'
      // weights recomputed without them (theirs are the only ones that saw them).
      double total_without = total;
      neighbours(x, y, [&](int nx, int ny) {
        const std::size_t j = std::size_t(ny) * W + nx;
        total_without += weight(vsum[j] - at(variance, x, y), csum[j] - at(cost, x, y)) - w[j];
      });
      // No noise anywhere near: the pixel keeps the plain spp.
      if (!(total_without > 0) || !std::isfinite(total_without)) continue;
      // At most 16x spp in one pixel, so a single hot pixel cannot take the budget.
      n[i] = pilot + int(std::lround(std::min(budget * w[i] / total_without, 16.0 * spp)));
    }
  return n;
}

TileRows tile_rows(int height, int index, int count) {
  const auto at = [&](int k) { return int((std::int64_t(height) * k) / count); };
  return {at(index), at(index + 1)};
}

Image merge_tiles(const std::vector<Image>& parts) {
  if (parts.empty()) throw Error("no parts to merge");
  const Image& first = parts.front();
  Image out(first.width, first.height, first.channels);
  const int n = int(parts.size());
  for (int k = 0; k < n; ++k) {
    const Image& p = parts[std::size_t(k)];
    const std::string which = "part " + std::to_string(k + 1) + " of " + std::to_string(n);
    if (p.width != first.width || p.height != first.height || p.channels != first.channels)
      throw Error(which + " is " + std::to_string(p.width) + "x" + std::to_string(p.height) + " with " +
                  std::to_string(p.channels) + " channels, part 1 " + std::to_string(first.width) + "x" +
                  std::to_string(first.height) + " with " + std::to_string(first.channels) +
                  ": merge the parts of one render");
    const TileRows rows = tile_rows(p.height, k, n);
    for (int y = 0; y < p.height; ++y) {
      const bool mine = y >= rows.first && y < rows.last;
      for (int x = 0; x < p.width; ++x)
        for (int c = 0; c < p.channels; ++c) {
          const float v = p.at(x, y)[c];
          if (mine)
            out.at(x, y)[c] = v;
          else if (v != 0)
            throw Error(which + " has a pixel at row " + std::to_string(y + 1) + ", outside its rows " +
                        std::to_string(rows.first + 1) + "-" + std::to_string(rows.last) +
                        ": give the parts in the order I = 1..N of --tile I/N, all with the same N");
        }
    }
  }
  return out;
}

Film render(const Camera& camera, const PathIntegrator& integrator, const RenderSettings& settings) {
  if (settings.spp < 1) throw Error("--spp must be at least 1");
  if (settings.threads < 0) throw Error("--threads must be 0 (all cores) or more");
  if (settings.tile_size < 1) throw Error("tile size must be at least 1");
  if (!(settings.tile_count >= 1 && settings.tile_index >= 0 && settings.tile_index < settings.tile_count))
    throw Error("--tile I/N needs 1 <= I <= N");
  if (settings.adaptive) {
    if (!(settings.target_error > 0)) throw Error("--target-error must be a positive fraction, e.g. 0.02");
    if (settings.min_spp < 2) throw Error("adaptive sampling needs a minimum of at least 2 samples per pixel");
    if (settings.check_every < 1) throw Error("adaptive sampling must check at least every sample");
  }
  const int W = camera.width(), H = camera.height(), T = settings.tile_size;
  const int tiles_x = (W + T - 1) / T, tiles_y = (H + T - 1) / T;
  const std::size_t P = std::size_t(W) * std::size_t(H);
  const bool allocate = settings.allocation == SampleAllocation::Variance && !settings.adaptive && settings.spp >= 8;
  const int pilot = allocate ? settings.spp / 4 : settings.spp;
  const TileRows rows = tile_rows(H, settings.tile_index, settings.tile_count);
  const auto outside = [&](std::size_t i) { return int(i / std::size_t(W)) < rows.first || int(i / std::size_t(W)) >= rows.last; };
  Film film(W, H, settings.keep_variance);
  ProgressBar progress("Rendering", std::uint64_t(tiles_x) * tiles_y * (allocate ? 2 : 1), !settings.progress);

  // Per pixel: the radiance sum, the samples taken, and (pilot) luminance moments.
  std::vector<glm::dvec3> sum(P, glm::dvec3(0)), sum_sq(settings.keep_variance ? P : 0, glm::dvec3(0));
  std::vector<int> taken(P, 0);
  std::vector<double> variance(allocate ? P : 0), cost(allocate ? P : 0);
  std::vector<int> target(P, pilot);
  // A part renders its rows only, but the pilot everywhere (allocation needs it all).
  if (!allocate)
    for (std::size_t i = 0; i < P; ++i)
      if (outside(i)) target[i] = 0;

  const auto start = std::chrono::steady_clock::now();
  // Takes pixel samples taken[i] .. target[i]-1 over one tile.
  auto render_tile = [&](int tx, int ty, bool first_pass) {
    check_interrupted();  // SIGINT or SIGTERM: stop here, unwinding (interrupt.h)
    const detail::FtzDazScope ftz_daz;  // in every thread, whatever its mode (float_mode.h)
    PixelSampler sampler(settings.sampler, settings.seed);
    PathCounters counters;
    std::int64_t saved = 0;
    for (int y = ty * T; y < std::min(H, (ty + 1) * T); ++y)
      for (int x = tx * T; x < std::min(W, (tx + 1) * T); ++x) {
        const std::size_t i = std::size_t(y) * W + x;
        glm::dvec3 s = sum[i], s2 = settings.keep_variance ? sum_sq[i] : glm::dvec3(0);
        double lum = 0, lum_sq = 0;
        int n = taken[i];
        const std::int64_t rays_before = counters.rays + counters.shadow_rays;
        while (n < target[i]) {
          sampler.start(x, y, std::uint32_t(n));
          const glm::vec4 u = sampler.next4();
          const Ray ray = camera.generate(float(x) + u.x, float(y) + u.y);
          const glm::dvec3 L(integrator.Li(ray, sampler, counters));
          s += L;
          s2 += L * L;
          ++n;
          if (!settings.adaptive && !(allocate && first_pass)) continue;
          const double Y = 0.2126 * L.x + 0.7152 * L.y + 0.0722 * L.z;  // Rec. 709 luminance
          lum += Y;
          lum_sq += Y * Y;
          if (settings.adaptive && n >= settings.min_spp && n % settings.check_every == 0 &&
              converged(lum, lum_sq, n, settings.target_error))
            break;
        }
        if (settings.adaptive) saved += settings.spp - n;
        if (allocate && first_pass && n > 1) {
          variance[i] = std::max(0.0, (lum_sq - lum * lum / n) / (n - 1));
          cost[i] = double(counters.rays + counters.shadow_rays - rays_before) / n;  // rays per sample
        }
        sum[i] = s;
        if (settings.keep_variance) sum_sq[i] = s2;
        taken[i] = n;
      }
    g_saved += saved;
    g_rays += counters.rays + counters.shadow_rays;
    g_shadow_rays += counters.shadow_rays;
    g_hits += counters.hits;
    g_bad += counters.bad_samples;
    progress.advance();
  };

  // More threads than cores buys nothing, and TBB would print a warning of its own.
  tbb::task_arena arena(settings.threads > 0 ? std::min(settings.threads, tbb::info::default_concurrency())
                                             : tbb::task_arena::automatic);
  auto pass = [&](bool first_pass) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1), [&](const tbb::blocked_range2d<int>& r) {
        for (int ty = r.rows().begin(); ty != r.rows().end(); ++ty)
          for (int tx = r.cols().begin(); tx != r.cols().end(); ++tx) render_tile(tx, ty, first_pass);
      });
    });
  };
  pass(true);
  if (allocate) {
    target = allocate_samples(variance, cost, W, H, settings.spp, pilot);
    for (std::size_t i = 0; i < P; ++i)
      if (outside(i)) target[i] = 0;
    pass(false);
  }
  progress.finish();
  std::int64_t samples = 0;
  for (std::size_t i = 0; i < P; ++i) {
    samples += taken[i];
    if (outside(i)) continue;
    const int x = int(i % std::size_t(W)), y = int(i / std::size_t(W)), n = taken[i];
    const glm::dvec3 mean = sum[i] / double(std::max(n, 1));
    film.set(x, y, glm::vec3(mean));
    if (settings.keep_variance && n > 1)  // the samples' variance (Bessel-corrected) over n: the variance of the mean
      film.set_variance(x, y, glm::vec3(glm::max(sum_sq[i] - double(n) * mean * mean, glm::dvec3(0)) / (double(n) * (n - 1))));
  }
  g_samples += samples;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Over every render of the run (compare and photo-to-feather render two), as the ray count is.
  const double total = stats_add_value("Time/Render (s)", seconds);
  stats_set_value("Renderer/Rays per second", total > 0 ? double(g_rays.value()) / total : 0.0);
  return film;
}

}  // namespace plumage
