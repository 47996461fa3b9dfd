#include "plumage/renderer/barb_shading.h"

#include "barb_shadings.h"
#include "plumage/common/error.h"
#include "plumage/renderer/scene.h"

namespace plumage {

std::unique_ptr<const BarbShading> make_barb_shading(const ShadingContext& context) {
  switch (context.scene.options().mode) {
    case ShadingMode::Hair: return detail::make_hair_shading(context);
    case ShadingMode::Substructure: return detail::make_substructure_shading(context);
    case ShadingMode::Explicit: return detail::make_explicit_shading(context);
    case ShadingMode::Farfield: return detail::make_farfield_shading(context);
  }
  throw Error("internal: a shading mode with no barb shading model");
}

}  // namespace plumage
