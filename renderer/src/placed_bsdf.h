#pragma once
// The Bsdf of a hit on a placed feather (world.h), in world directions: the
// feather's own Bsdf was built in its frame, and a placement's rotation R (a
// similarity's, mirrored or not) carries local directions to world ones. R is
// orthonormal, so it keeps angles, cosines and solid angles: f, the projection
// cosine and pdfs are the same numbers in both frames, and the wrapper only turns
// directions.
#include <glm/glm.hpp>

#include "plumage/renderer/bsdf.h"

namespace plumage {

class PlacedBsdf final : public Bsdf {
 public:
  // `local` must outlive this (it lives in another BsdfSlot of the same vertex).
  PlacedBsdf(const Bsdf& local, const glm::mat3& rotation)
      : local_(local), to_world_(rotation), to_local_(glm::transpose(rotation)) {}

  glm::vec3 f_cos(const glm::vec3& wi, float* pdf) const override { return local_.f_cos(to_local_ * wi, pdf); }

  std::optional<BsdfSample> sample(const glm::vec4& u) const override {
    std::optional<BsdfSample> s = local_.sample(u);
    if (s) s->wi = to_world_ * s->wi;
    return s;
  }

  void estimate_weights(const LightProxies& lp, float* w) const override {
    thread_local LightProxies turned;  // per thread, reused: a path allocates nothing once warm
    turned = lp;
    for (std::size_t i = 0; i < lp.size(); ++i) {
      const glm::vec3 d = to_local_ * lp.wi(i);
      turned.x[i] = d.x, turned.y[i] = d.y, turned.z[i] = d.z;
    }
    local_.estimate_weights(turned, w);
  }

  bool samples_like_f_cos() const override { return local_.samples_like_f_cos(); }

 private:
  const Bsdf& local_;
  glm::mat3 to_world_, to_local_;
};

}  // namespace plumage
