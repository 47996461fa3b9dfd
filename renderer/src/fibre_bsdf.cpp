#include "plumage/renderer/fibre_bsdf.h"

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "plumage/common/constants.h"
#include "plumage/common/image.h"
#include "plumage/renderer/sampler.h"
#include "plumage/renderer/scene.h"

namespace plumage {
namespace {

// Plain loops over pointers, which GCC vectorises.
void to_frame(std::size_t n, const float* x, const float* y, const float* z, Frame f, float* __restrict lx,
              float* __restrict ly, float* __restrict lz) {
  for (std::size_t i = 0; i < n; ++i) {
    lx[i] = x[i] * f.t.x + y[i] * f.t.y + z[i] * f.t.z;
    ly[i] = x[i] * f.b.x + y[i] * f.b.y + z[i] * f.b.z;
    lz[i] = x[i] * f.n.x + y[i] * f.n.y + z[i] * f.n.z;
  }
}

void weigh(std::size_t n, const float* r, const float* g, const float* b, const float* fr, const float* fg,
           const float* fb, float* __restrict w) {
  for (std::size_t i = 0; i < n; ++i) w[i] = kLumR * r[i] * fr[i] + kLumG * g[i] * fg[i] + kLumB * b[i] * fb[i];
}

}  // namespace

FibreBsdf::FibreBsdf(const FibreFrame& frame, const HairParams& params, const glm::vec3& wo, bool pdf_needed)
    : ff_(frame), wo_local_(frame.frame.to_local(wo)), bcsdf_(params, frame.h, wo_local_), pdf_needed_(pdf_needed) {}

glm::vec3 FibreBsdf::f_cos(const glm::vec3& wi, float* pdf) const {
  const glm::vec3 wl = ff_.frame.to_local(wi);
  return bcsdf_.f_pdf(wo_local_, wl, pdf) * bcsdf_cos(wl);
}

// Over per-thread buffers: a path allocates nothing once they have grown.
void FibreBsdf::estimate_weights(const LightProxies& lp, float* w) const {
  thread_local std::vector<float> buf;
  const std::size_t n = lp.size();
  buf.resize(6 * n);
  float *lx = buf.data(), *ly = lx + n, *lz = ly + n;
  to_frame(n, lp.x.data(), lp.y.data(), lp.z.data(), ff_.frame, lx, ly, lz);
  float* const resp[3] = {lz + n, lz + 2 * n, lz + 3 * n};
  bcsdf_.f_cos_estimate(wo_local_, n, lx, ly, lz, resp);
  weigh(n, lp.r.data(), lp.g.data(), lp.b.data(), resp[0], resp[1], resp[2], w);
}

std::optional<BsdfSample> FibreBsdf::sample(const glm::vec4& u) const {
  if (!pdf_needed_) {
    const auto s = bcsdf_.sample_throughput(wo_local_, {u.x, u.y}, {u.z, u.w});
    if (!s) return std::nullopt;
    return BsdfSample{glm::normalize(ff_.frame.to_world(s->wi)), s->weight, 0.0f};
  }
  const auto s = bcsdf_.sample(wo_local_, {u.x, u.y}, {u.z, u.w});
  if (!s || !(s->pdf > 0)) return std::nullopt;
  return BsdfSample{glm::normalize(ff_.frame.to_world(s->wi)), s->f * (bcsdf_cos(s->wi) / s->pdf), s->pdf};
}

FibreFrame round_fibre_frame_at(const Scene& scene, const SurfaceHit& hit, const glm::vec3& wo) {
  const CurvePoint cp = scene.curve_point(hit);
  return round_fibre_frame(cp.dp, wo, cp.p, cp.radius, hit.p);
}

FibreFrame down_fibre_frame_at(const Scene& scene, const SurfaceHit& hit, const glm::vec3& wo) {
  if (scene.options().mode == ShadingMode::Hair) return round_fibre_frame_at(scene, hit, wo);
  const CurvePoint cp = scene.curve_point(hit);
  const glm::vec3 t = safe_normalize(cp.dp);
  const Frame around = frame_from_tangent_normal(t, std::fabs(t.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0));
  // Two numbers fixed by where the ray met the tube.
  std::uint32_t h = hash_combine(std::bit_cast<std::uint32_t>(hit.p.x), std::bit_cast<std::uint32_t>(hit.p.y));
  h = hash_combine(h, std::bit_cast<std::uint32_t>(hit.p.z));
  const float u1 = to_unit(h), u2 = to_unit(hash_combine(h, hit.curve));
  const float elevation = float(scene.feather().substructure(scene.feather().curves[hit.curve].side).elevation_deg * kDegToRad);
  const float azimuth = 2.0f * kPiF * u1;
  const glm::vec3 barbule = std::cos(elevation) * t + std::sin(elevation) * (std::cos(azimuth) * around.b + std::sin(azimuth) * around.n);
  return flat_fibre_frame(barbule, wo, 2.0f * u2 - 1.0f);
}

}  // namespace plumage
