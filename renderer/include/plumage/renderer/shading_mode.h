#pragma once
// How barbs are turned into Embree geometry and shaded (DESIGN §4-5).
//   Hair:         each barb is a ray-facing flat ribbon shaded as one hair fibre.
//   Substructure: each barb is a normal-oriented ribbon in the vane whose (u, v)
//                 locate rami and barbules (substructure.h; docs/substructure.md).
//   Explicit:     rami and barbules as real round curves (explicit_geometry.h), the
//                 reference the substructure technique is measured against.
#include <string>

namespace plumage {

enum class ShadingMode { Hair, Substructure, Explicit };
// Every mode, in the order the CLI lists them.
inline constexpr ShadingMode kShadingModes[] = {ShadingMode::Hair, ShadingMode::Substructure, ShadingMode::Explicit};

const char* to_string(ShadingMode m);
// "hair", "substructure" or "explicit"; throws plumage::Error otherwise.
ShadingMode parse_shading_mode(const std::string& s);

}  // namespace plumage
