// Farfield mode (docs/substructure.md "Far-field model"): a barb hit that was not
// let through (the ribbon's any-hit filter) is shaded by its vane's table, one per
// vane and barb class, measured on the explicit geometry.
#include <memory>
#include <vector>

#include "barb_shadings.h"
#include "plumage/renderer/farfield_bsdf.h"
#include "plumage/renderer/scene.h"

namespace plumage::detail {
namespace {

class FarfieldShading final : public BarbShading {
 public:
  // One table per vane and barb class, for the material where the feather's middle
  // is (a texture's variation over the feather is not fitted).
  explicit FarfieldShading(const ShadingContext& c) : scene_(c.scene) {
    const HairParams hp = c.material.at(scene_.feather_bounds().centre());
    for (VaneSide side : {VaneSide::Left, VaneSide::Right})
      for (const FarfieldGeometry& g : scene_.farfield_geometries(side))
        models_[side == VaneSide::Right].push_back(farfield_model(g, &hp));
  }
  ShadingMode mode() const override { return ShadingMode::Farfield; }
  const Bsdf& at(const SurfaceHit& hit, const glm::vec3& wo, BsdfSlot& slot) const override {
    const bool right = scene_.feather().curves[hit.curve].side == VaneSide::Right;
    return slot.emplace<FarfieldBsdf>(*models_[right][scene_.farfield_class(hit)], scene_.farfield_frame(hit), wo);
  }

 private:
  const Scene& scene_;
  std::vector<std::shared_ptr<const FarfieldModel>> models_[2];  // left, right vane, per class
};

}  // namespace

std::unique_ptr<const BarbShading> make_farfield_shading(const ShadingContext& context) {
  return std::make_unique<FarfieldShading>(context);
}

}  // namespace plumage::detail
