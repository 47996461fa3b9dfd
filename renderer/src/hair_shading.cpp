// Hair mode (Marschner et al. 2003; d'Eon et al. 2011; Chiang et al. 2016): a barb
// is one fibre across its ray-facing ribbon, h from where the ray crossed it.
#include "barb_shadings.h"
#include "plumage/renderer/fibre_bsdf.h"
#include "plumage/renderer/scene.h"

namespace plumage::detail {
namespace {

class HairShading final : public BarbShading {
 public:
  explicit HairShading(const ShadingContext& c) : c_(c) {}
  ShadingMode mode() const override { return ShadingMode::Hair; }
  const Bsdf& at(const SurfaceHit& hit, const glm::vec3& wo, BsdfSlot& slot) const override {
    const CurvePoint cp = c_.scene.curve_point(hit);
    // A whole fibre: no coverage to compensate (structure_coverage is 1).
    return slot.emplace<FibreBsdf>(flat_fibre_frame(cp.dp, wo, hit.v),
                                   c_.material.at(hit.p, 1.0f, c_.scene.ribbon_layers(hit)), wo, c_.pdf_needed);
  }

 private:
  ShadingContext c_;
};

}  // namespace

std::unique_ptr<const BarbShading> make_hair_shading(const ShadingContext& context) {
  return std::make_unique<HairShading>(context);
}

}  // namespace plumage::detail
