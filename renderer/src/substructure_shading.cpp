// Substructure mode (Baron et al. 2021): a barb hit is resolved to the ramus or
// barbule the ray met inside the ribbon (Scene::structure_at, substructure.h), which
// is shaded as a fibre in its own frame (Eq. 1), its albedo compensated for the
// ribbon's uncovered share.
#include "barb_shadings.h"
#include "plumage/renderer/fibre_bsdf.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/substructure.h"

namespace plumage::detail {
namespace {

class SubstructureShading final : public BarbShading {
 public:
  explicit SubstructureShading(const ShadingContext& c) : c_(c) {}
  ShadingMode mode() const override { return ShadingMode::Substructure; }
  const Bsdf& at(const SurfaceHit& hit, const glm::vec3& wo, BsdfSlot& slot) const override {
    const StructureSample ss = c_.scene.structure_at(hit);
    return slot.emplace<FibreBsdf>(structure_fibre_frame(ss.frame, ss.hit.h, wo),
                                   c_.material.at(hit.p, c_.scene.structure_coverage(hit), c_.scene.ribbon_layers(hit)),
                                   wo, c_.pdf_needed);
  }

 private:
  ShadingContext c_;
};

}  // namespace

std::unique_ptr<const BarbShading> make_substructure_shading(const ShadingContext& context) {
  return std::make_unique<SubstructureShading>(context);
}

}  // namespace plumage::detail
