#include "plumage/renderer/farfield_bsdf.h"

#include "plumage/common/image.h"

namespace plumage {

FarfieldBsdf::FarfieldBsdf(const FarfieldModel& model, const Frame& frame, const glm::vec3& wo)
    : model_(model), frame_(frame), out_(model.outgoing(frame.to_local(wo))) {}

glm::vec3 FarfieldBsdf::f_cos(const glm::vec3& wi, float* pdf) const {
  return model_.f_cos(out_, frame_.to_local(wi), pdf);
}

void FarfieldBsdf::estimate_weights(const LightProxies& lp, float* w) const {
  for (std::size_t i = 0; i < lp.size(); ++i)
    w[i] = luminance(lp.strength(i) * model_.f_cos_estimate(out_, frame_.to_local(lp.wi(i))));
}

std::optional<BsdfSample> FarfieldBsdf::sample(const glm::vec4& u) const {
  BsdfSample s;
  glm::vec3 wl;
  if (!model_.sample(out_, {u.x, u.y, u.z}, &wl, &s.weight, &s.pdf)) return std::nullopt;
  s.wi = glm::normalize(frame_.to_world(wl));
  return s;
}

}  // namespace plumage
