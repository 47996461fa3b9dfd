// Explicit mode: rami and barbules are real round curves (explicit_geometry.h),
// each shaded like the shaft, as a round fibre with h from where the ray met the
// tube, with the same coverage-compensated albedo as substructure mode.
#include "barb_shadings.h"
#include "plumage/renderer/fibre_bsdf.h"
#include "plumage/renderer/scene.h"

namespace plumage::detail {
namespace {

class ExplicitShading final : public BarbShading {
 public:
  explicit ExplicitShading(const ShadingContext& c) : c_(c) {}
  ShadingMode mode() const override { return ShadingMode::Explicit; }
  const Bsdf& at(const SurfaceHit& hit, const glm::vec3& wo, BsdfSlot& slot) const override {
    return slot.emplace<FibreBsdf>(round_fibre_frame_at(c_.scene, hit, wo),
                                   c_.material.at(hit.p, c_.scene.structure_coverage(hit), c_.scene.ribbon_layers(hit)),
                                   wo, c_.pdf_needed);
  }

 private:
  ShadingContext c_;
};

}  // namespace

std::unique_ptr<const BarbShading> make_explicit_shading(const ShadingContext& context) {
  return std::make_unique<ExplicitShading>(context);
}

}  // namespace plumage::detail
