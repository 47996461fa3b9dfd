#include "plumage/renderer/diffuse_bsdf.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "plumage/common/constants.h"
#include "plumage/common/frame.h"
#include "plumage/common/image.h"

namespace plumage {
namespace {

// A plain loop over pointers, which GCC vectorises: lum(strength f cos).
void weigh(std::size_t count, const float* x, const float* y, const float* z, const float* r, const float* g,
           const float* b, glm::vec3 n, glm::vec3 f, float* __restrict w) {
  const float kr = kLumR * f.x, kg = kLumG * f.y, kb = kLumB * f.z;
  for (std::size_t i = 0; i < count; ++i) {
    const float c = x[i] * n.x + y[i] * n.y + z[i] * n.z;
    w[i] = std::max(c, 0.0f) * (kr * r[i] + kg * g[i] + kb * b[i]);
  }
}

}  // namespace

DiffuseBsdf::DiffuseBsdf(const glm::vec3& normal, const glm::vec3& wo, const glm::vec3& albedo)
    : n_(glm::dot(normal, wo) < 0 ? -normal : normal), albedo_(albedo) {}

glm::vec3 DiffuseBsdf::f_cos(const glm::vec3& wi, float* pdf) const {
  const float c = glm::dot(wi, n_);
  *pdf = c > 0 ? c / kPiF : 0.0f;
  return c > 0 ? albedo_ * (c / kPiF) : glm::vec3(0);
}

void DiffuseBsdf::estimate_weights(const LightProxies& lp, float* w) const {
  weigh(lp.size(), lp.x.data(), lp.y.data(), lp.z.data(), lp.r.data(), lp.g.data(), lp.b.data(), n_, albedo_ / kPiF,
        w);
}

std::optional<BsdfSample> DiffuseBsdf::sample(const glm::vec4& u) const {
  // Cosine-weighted hemisphere (Malley's method).
  const float r = std::sqrt(u.x), phi = 2 * kPiF * u.y;
  const float z = std::sqrt(std::fmax(0.0f, 1.0f - u.x));
  if (!(z > 0)) return std::nullopt;
  const Frame f = frame_from_normal(n_);
  return BsdfSample{glm::normalize(f.to_world({r * std::cos(phi), r * std::sin(phi), z})), albedo_, z / kPiF};
}

}  // namespace plumage
