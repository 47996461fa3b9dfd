// The virtual gonioreflectometer of the far-field barb model (farfield.h): a
// straight explicit barb (ramus and barbules as round fibres, explicit_geometry.h,
// as polylines by default: FarfieldFitSettings::polylines)
// lit by parallel light from each direction bin; every path is followed through
// the structures with the hair BCSDF until it leaves, and where it leaves is binned.
//
// The barb runs along +X with its vane normal +Z on the right vane, so its frame
// (t, b' = distal side, n) is the world's (X, Y, Z). Rays are aimed at uniform
// points of a window of the ribbon's plane, |w| <= W/2 and s within the middle of
// the barb; the barb reaches kMargin beyond the window on both sides so that rays
// at grazing angles meet the structures they would on a longer barb.
//
// Each bin's paths are two independent halves (even and odd paths), each an
// Owen-scrambled Sobol sequence (sampler.h; the bin and half pick the scramble):
// the first 4D pattern places the path (direction within the bin, point of the
// window), each later one draws a bounce. The halves give the split-half noise;
// the path's first ray, the one that crosses or meets the patch, also counts
// toward the straight transmittance, so T and F come from the same paths and a
// transmittance-only fit traces exactly the first rays of a BSDF fit.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "plumage/common/error.h"
#include "plumage/common/interrupt.h"
#include "plumage/renderer/farfield.h"
#include "plumage/renderer/fibre_frame.h"
#include "plumage/renderer/sampler.h"
#include "plumage/renderer/scene.h"

namespace plumage {
namespace {

constexpr float kMargin = 1.5f;   // mm of barb beyond the window, each side
constexpr float kHeight = 1.0f;   // mm: rays start this far from the plane, above every structure

// The patch: one straight barb of the right vane, its barbules at `period`.
Feather patch_barb(const FarfieldGeometry& g, float* window_lo, float* window_hi) {
  const float W = g.params.ribbon_width;
  const float window = std::max({16.0f * g.period, 2.0f * W, 0.5f});
  const float L = window + 2 * kMargin;
  Feather f;
  Curve c;
  c.kind = CurveKind::Barb;
  c.side = VaneSide::Right;
  // 8 evenly spaced collinear control points h apart: the uniform B-spline runs
  // from the second to the second-last, so its arc length is exactly L.
  const float h = L / 5;
  for (int i = 0; i < 8; ++i) c.points.push_back({{-L / 2 - h + h * float(i), 0, 0}, W / 2, {0, 0, 1}});
  f.curves.push_back(c);
  SubstructureParams p = g.params;
  p.barbules_per_side = g.period > 0 && p.barbules_per_side > 0 ? std::max(1, int(std::lround(L / g.period))) : 0;
  f.left = f.right = p;
  *window_lo = -window / 2;
  *window_hi = window / 2;
  return f;
}

struct BinTally {
  std::vector<glm::dvec3> half[2];  // per outgoing bin, even and odd paths
  std::int64_t rays = 0;
};

}  // namespace

FarfieldModel measure_farfield(const FarfieldGeometry& g, const HairParams* material, const FarfieldFitSettings& s) {
  if (s.bins.nu < 1 || s.bins.nphi < 2 || s.bins.nphi % 2) throw Error("far-field bins: nu >= 1 and an even nphi >= 2");
  if (s.paths_per_bin < 2) throw Error("far-field fit: at least 2 paths per bin");
  if (material) validate(*material, "far-field fit material");
  const auto t0 = std::chrono::steady_clock::now();
  float lo, hi;
  const Feather patch = patch_barb(g, &lo, &hi);
  SceneOptions so;
  so.mode = ShadingMode::Explicit;
  so.explicit_polylines = s.polylines;
  const Scene scene(patch, so);
  const float W = g.params.ribbon_width;

  FarfieldModel m;
  m.bins = s.bins;
  const int n = s.bins.count();
  const float omega = s.bins.solid_angle();
  std::vector<double> T(std::size_t(n), 0.0);
  std::vector<BinTally> tally(material ? std::size_t(n) : 0);
  tbb::task_arena arena(s.threads > 0 ? s.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(0, n, [&](int b) {
      check_interrupted();  // SIGINT or SIGTERM: stop here, unwinding (interrupt.h)
      BinTally* bt = material ? &tally[std::size_t(b)] : nullptr;
      if (bt) {
        bt->half[0].assign(std::size_t(n), glm::dvec3(0));
        bt->half[1].assign(std::size_t(n), glm::dvec3(0));
      }
      PixelSampler px(SamplerKind::Sobol, s.seed);
      int through = 0;
      for (int k = 0; k < s.paths_per_bin; ++k) {
        px.start(b, k & 1, std::uint32_t(k >> 1));
        const glm::vec4 u0 = px.next4();
        const glm::vec3 wi = s.bins.direction(b, {u0.x, u0.y});
        const glm::vec3 p0(lo + (hi - lo) * u0.z, W * (u0.w - 0.5f), 0);
        Ray ray;
        ray.o = p0 + kHeight / std::max(std::fabs(wi.z), 1e-3f) * wi;
        ray.d = -wi;
        SurfaceHit hit;
        const bool met = scene.intersect(ray, hit);
        if (!met) ++through;  // straight transmittance: the share of rays that meet nothing
        if (!bt) continue;
        ++bt->rays;
        if (!met) continue;
        glm::vec3 beta(1);
        for (int depth = 0; depth < s.max_depth; ++depth) {
          const glm::vec3 wo = -ray.d;
          const CurvePoint cp = scene.curve_point(hit);
          const FibreFrame ff = round_fibre_frame(cp.dp, wo, cp.p, cp.radius, hit.p);
          const glm::vec3 wo_local = ff.frame.to_local(wo);
          const HairBCSDF bcsdf(*material, ff.h, wo_local);
          const glm::vec4 u = px.next4();
          const auto smp = bcsdf.sample(wo_local, {u.x, u.y}, {u.z, u.w});
          if (!smp || !(smp->pdf > 0)) break;
          beta *= smp->f * (bcsdf_cos(smp->wi) / smp->pdf);
          if (!(beta.x > 0 || beta.y > 0 || beta.z > 0) || !std::isfinite(beta.x + beta.y + beta.z)) break;
          ray = scene.spawn(hit, glm::normalize(ff.frame.to_world(smp->wi)));
          ++bt->rays;
          if (!scene.intersect(ray, hit)) {
            const int O = s.bins.bin(ray.d);
            if (O >= 0) bt->half[k & 1][std::size_t(O)] += glm::dvec3(beta);
            break;
          }
        }
      }
      T[std::size_t(b)] = double(through) / s.paths_per_bin;
    });
  });

  // Straight transmittance is the same both ways along a line.
  m.T.assign(std::size_t(n), 0.0f);
  for (int b = 0; b < n; ++b) m.T[std::size_t(b)] = float(0.5 * (T[std::size_t(b)] + T[std::size_t(s.bins.antipode(b))]));
  m.report.paths = std::int64_t(n) * s.paths_per_bin;
  m.report.T_min = *std::min_element(m.T.begin(), m.T.end());
  m.report.T_max = *std::max_element(m.T.begin(), m.T.end());
  m.finish();  // the bins' mean cosines

  if (material) {
    // F[I][O] = P[I][O] / (Omega cbar_O), P the fraction of the power from I leaving into O.
    const std::size_t N = std::size_t(n);
    std::vector<glm::dvec3> F(N * N), Fa(N * N), Fb(N * N);
    const double half = 0.5 * s.paths_per_bin;
    for (std::size_t I = 0; I < N; ++I) {
      m.report.rays += tally[I].rays;
      for (std::size_t O = 0; O < N; ++O) {
        const double norm = 1.0 / (double(omega) * m.mean_cos(int(O)));  // the bin average, read as its centre's value
        const glm::dvec3 a = tally[I].half[0][O] / half * norm, b = tally[I].half[1][O] / half * norm;
        Fa[I * N + O] = a;
        Fb[I * N + O] = b;
        F[I * N + O] = 0.5 * (a + b);
      }
    }
    // Noise: the split-half estimate of the mean's standard error, E[(a - b)^2] / 4;
    // asymmetry: (F - F^T) / 2, which noise alone makes about noise / sqrt(2).
    double sq = 0, diff = 0, asym = 0;
    for (std::size_t I = 0; I < N; ++I)
      for (std::size_t O = 0; O < N; ++O) {
        const glm::dvec3 f = F[I * N + O], d = Fa[I * N + O] - Fb[I * N + O], t = F[I * N + O] - F[O * N + I];
        sq += glm::dot(f, f);
        diff += glm::dot(d, d) / 4;
        asym += glm::dot(t, t) / 4;
      }
    m.report.noise = sq > 0 ? std::sqrt(diff / sq) : 0.0;
    m.report.asymmetry = sq > 0 ? std::sqrt(asym / sq) : 0.0;

    // Reciprocal: the mean of F and F^T (also halves the noise).
    m.F.assign(N * N, glm::vec3(0));
    for (std::size_t I = 0; I < N; ++I)
      for (std::size_t O = 0; O < N; ++O) m.F[I * N + O] = glm::vec3(0.5 * (F[I * N + O] + F[O * N + I]));
    // Energy bound: row I may scatter at most 1 - T_I. Scaling entry (I, O) by
    // min(s_I, s_O) keeps the table symmetric and every row within its bound.
    std::vector<float> scale(N, 1.0f);
    for (std::size_t I = 0; I < N; ++I) {
      const glm::vec3 a = m.albedo(int(I));
      const float amax = std::max({a.x, a.y, a.z});
      if (amax > 1 - m.T[I]) scale[I] = std::max(0.0f, 1 - m.T[I]) / amax;
      m.report.clamped = std::max(m.report.clamped, double(1 - scale[I]));
    }
    for (std::size_t I = 0; I < N; ++I)
      for (std::size_t O = 0; O < N; ++O) m.F[I * N + O] *= std::min(scale[I], scale[O]);
    m.report.albedo_min = 1e30;
    m.report.albedo_max = 0;
    for (std::size_t I = 0; I < N; ++I) {
      const glm::vec3 a = m.albedo(int(I));
      const double amax = std::max({a.x, a.y, a.z});
      m.report.albedo_min = std::min(m.report.albedo_min, amax);
      m.report.albedo_max = std::max(m.report.albedo_max, amax);
    }
    m.finish();  // the sampling tables
  }
  m.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return m;
}

}  // namespace plumage
