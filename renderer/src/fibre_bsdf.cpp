#include "plumage/renderer/fibre_bsdf.h"

#include <cstddef>
#include <vector>

#include "plumage/common/image.h"
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

}  // namespace plumage
