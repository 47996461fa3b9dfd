#pragma once
// One fibre hit — a barb in hair mode, a ramus or barbule in substructure and
// explicit mode, the shaft in every mode — shaded with the hair BCSDF
// (hair_bcsdf.h) in its fibre frame (fibre_frame.h). The cosine is that of the
// longitudinal angle, cos(theta_i) = sqrt(1 - wi.x^2) (Chiang et al. 2016 eq. 2;
// bcsdf_cos).
#include <glm/glm.hpp>

#include "plumage/renderer/bsdf.h"
#include "plumage/renderer/fibre_frame.h"
#include "plumage/renderer/hair_bcsdf.h"

namespace plumage {

class Scene;
struct SurfaceHit;

class FibreBsdf final : public Bsdf {
 public:
  // `pdf_needed` false: sample() weighs by lobe selection (HairBCSDF::sample_throughput)
  // and gives no pdf, for paths whose BCSDF-sampled rays need no MIS weight.
  FibreBsdf(const FibreFrame& frame, const HairParams& params, const glm::vec3& wo, bool pdf_needed);
  glm::vec3 f_cos(const glm::vec3& wi, float* pdf) const override;
  std::optional<BsdfSample> sample(const glm::vec4& u) const override;
  // The float estimate (HairBCSDF::f_cos_estimate) in the fibre frame.
  void estimate_weights(const LightProxies& lp, float* w) const override;

 private:
  FibreFrame ff_;
  glm::vec3 wo_local_;
  HairBCSDF bcsdf_;
  bool pdf_needed_;
};

// The frame of a round curve (the shaft, explicit mode's rami and barbules) at a hit:
// h from where the hit lies across the tube.
FibreFrame round_fibre_frame_at(const Scene& scene, const SurfaceHit& hit, const glm::vec3& wo);
// The fibre a ray meets inside a down barb's tube (hit.kind == HitKind::Down): in
// hair mode the barb itself (round_fibre_frame_at); in the modes that simulate
// barbules, one of its barbules (docs/curve-format.md, "Down"): at the vane's
// barbule elevation theta_b from the barb's tangent, turned about the tangent by an
// azimuth, and met at an offset h, both uniform and fixed by the hit point (a
// plumulaceous barbule has no vane to lie in).
FibreFrame down_fibre_frame_at(const Scene& scene, const SurfaceHit& hit, const glm::vec3& wo);

}  // namespace plumage
