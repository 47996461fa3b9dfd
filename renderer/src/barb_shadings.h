#pragma once
// The barb shading models (barb_shading.h), one per file; make_barb_shading
// chooses among them.
#include <memory>

#include "plumage/renderer/barb_shading.h"

namespace plumage::detail {

std::unique_ptr<const BarbShading> make_hair_shading(const ShadingContext& context);
std::unique_ptr<const BarbShading> make_substructure_shading(const ShadingContext& context);
std::unique_ptr<const BarbShading> make_explicit_shading(const ShadingContext& context);
std::unique_ptr<const BarbShading> make_farfield_shading(const ShadingContext& context);

}  // namespace plumage::detail
