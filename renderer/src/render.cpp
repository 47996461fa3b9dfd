#include "plumage/renderer/render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <tbb/blocked_range2d.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "float_mode.h"
#include "plumage/common/error.h"
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

Film render(const Camera& camera, const PathIntegrator& integrator, const RenderSettings& settings) {
  if (settings.spp < 1) throw Error("--spp must be at least 1");
  if (settings.threads < 0) throw Error("--threads must be 0 (all cores) or more");
  if (settings.tile_size < 1) throw Error("tile size must be at least 1");
  if (settings.adaptive) {
    if (!(settings.target_error > 0)) throw Error("--target-error must be a positive fraction, e.g. 0.02");
    if (settings.min_spp < 2) throw Error("adaptive sampling needs a minimum of at least 2 samples per pixel");
    if (settings.check_every < 1) throw Error("adaptive sampling must check at least every sample");
  }
  const int W = camera.width(), H = camera.height(), T = settings.tile_size;
  const int tiles_x = (W + T - 1) / T, tiles_y = (H + T - 1) / T;
  Film film(W, H);
  ProgressBar progress("Rendering", std::uint64_t(tiles_x) * tiles_y, !settings.progress);

  const std::int64_t saved_before = g_saved.value();
  const auto start = std::chrono::steady_clock::now();
  auto render_tile = [&](int tx, int ty) {
    const detail::FtzDazScope ftz_daz;  // in every thread, whatever its mode (float_mode.h)
    PixelSampler sampler(settings.sampler, settings.seed);
    PathCounters counters;
    std::int64_t saved = 0;
    for (int y = ty * T; y < std::min(H, (ty + 1) * T); ++y)
      for (int x = tx * T; x < std::min(W, (tx + 1) * T); ++x) {
        glm::dvec3 sum(0);
        double lum = 0, lum_sq = 0;
        int n = 0;
        while (n < settings.spp) {
          sampler.start(x, y, std::uint32_t(n));
          const glm::vec4 u = sampler.next4();
          const Ray ray = camera.generate(float(x) + u.x, float(y) + u.y);
          const glm::dvec3 L(integrator.Li(ray, sampler, counters));
          sum += L;
          ++n;
          if (!settings.adaptive) continue;
          const double Y = 0.2126 * L.x + 0.7152 * L.y + 0.0722 * L.z;  // Rec. 709 luminance
          lum += Y;
          lum_sq += Y * Y;
          if (n >= settings.min_spp && n % settings.check_every == 0 && converged(lum, lum_sq, n, settings.target_error))
            break;
        }
        saved += settings.spp - n;
        film.set(x, y, glm::vec3(sum / double(n)));
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
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1), [&](const tbb::blocked_range2d<int>& r) {
      for (int ty = r.rows().begin(); ty != r.rows().end(); ++ty)
        for (int tx = r.cols().begin(); tx != r.cols().end(); ++tx) render_tile(tx, ty);
    });
  });
  progress.finish();
  g_samples += std::int64_t(W) * H * settings.spp - (g_saved.value() - saved_before);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stats_set_value("Time/Render (s)", seconds);
  stats_set_value("Renderer/Rays per second", seconds > 0 ? double(g_rays.value()) / seconds : 0.0);
  return film;
}

}  // namespace plumage
