#pragma once
// The card under the feather (backdrop.h): Lambertian, seen from either side,
// sampled by the cosine.
#include <glm/glm.hpp>

#include "plumage/renderer/bsdf.h"

namespace plumage {

class DiffuseBsdf final : public Bsdf {
 public:
  // `normal`: either of the card's normals; the one facing wo is used.
  DiffuseBsdf(const glm::vec3& normal, const glm::vec3& wo, const glm::vec3& albedo);
  glm::vec3 f_cos(const glm::vec3& wi, float* pdf) const override;
  std::optional<BsdfSample> sample(const glm::vec4& u) const override;
  void estimate_weights(const LightProxies& lp, float* w) const override;

 private:
  glm::vec3 n_, albedo_;
};

}  // namespace plumage
