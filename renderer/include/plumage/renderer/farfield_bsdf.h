#pragma once
// A far-field ribbon hit (farfield.h): the vane's measured table in the barb's
// frame, given that the ray was not let through.
#include <glm/glm.hpp>

#include "plumage/common/frame.h"
#include "plumage/renderer/bsdf.h"
#include "plumage/renderer/farfield.h"

namespace plumage {

class FarfieldBsdf final : public Bsdf {
 public:
  // `model` must outlive the Bsdf.
  FarfieldBsdf(const FarfieldModel& model, const Frame& frame, const glm::vec3& wo);
  glm::vec3 f_cos(const glm::vec3& wi, float* pdf) const override;
  std::optional<BsdfSample> sample(const glm::vec4& u) const override;
  // Values only (no pdfs): next-event estimation's weighing of every light.
  void estimate_weights(const LightProxies& lp, float* w) const override;
  // Its sampling is uniform within a table bin while f cos interpolates between
  // bins: it keeps light sampling of a constant environment too.
  bool samples_like_f_cos() const override { return false; }

 private:
  const FarfieldModel& model_;
  Frame frame_;
  FarfieldModel::Outgoing out_;  // what depends on wo alone, once per hit
};

}  // namespace plumage
