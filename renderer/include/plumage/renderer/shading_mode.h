#pragma once
// How barbs are turned into Embree geometry and shaded (DESIGN §4-5).
//   Hair:         each barb is a ray-facing flat ribbon shaded as one hair fibre.
//   Substructure: each barb is a normal-oriented ribbon in the vane whose (u, v)
//                 locate rami and barbules (substructure.h; docs/substructure.md).
//   Explicit:     rami and barbules as real round curves (explicit_geometry.h), the
//                 reference the substructure technique is measured against.
//   Farfield:     each barb is a ribbon in the vane shaded by a table measured on its
//                 explicit geometry (farfield.h; docs/substructure.md "Far-field model").
#include <string>

namespace plumage {

enum class ShadingMode { Hair, Substructure, Explicit, Farfield };
// Every mode, in the order the CLI lists them.
inline constexpr ShadingMode kShadingModes[] = {ShadingMode::Hair, ShadingMode::Substructure, ShadingMode::Explicit,
                                                ShadingMode::Farfield};

const char* to_string(ShadingMode m);

// The geometry the scene builds for barbs in each mode (scene.h); how a barb hit is
// shaded is the mode's BarbShading (barb_shading.h).
enum class BarbGeometry {
  FacingRibbon,  // hair: a flat ribbon facing the ray
  VaneRibbon,    // substructure, farfield: a normal-oriented ribbon in the vane, with an any-hit filter
  Structures,    // explicit: rami and barbules as round curves
};
BarbGeometry barb_geometry(ShadingMode m);
// "hair", "substructure", "explicit" or "farfield"; throws plumage::Error otherwise.
ShadingMode parse_shading_mode(const std::string& s);

}  // namespace plumage
