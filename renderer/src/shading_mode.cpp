#include "plumage/renderer/shading_mode.h"

#include "plumage/common/error.h"

namespace plumage {

const char* to_string(ShadingMode m) {
  switch (m) {
    case ShadingMode::Substructure: return "substructure";
    case ShadingMode::Explicit: return "explicit";
    case ShadingMode::Farfield: return "farfield";
    case ShadingMode::Hair: break;
  }
  return "hair";
}

BarbGeometry barb_geometry(ShadingMode m) {
  switch (m) {
    case ShadingMode::Substructure:
    case ShadingMode::Farfield: return BarbGeometry::VaneRibbon;
    case ShadingMode::Explicit: return BarbGeometry::Structures;
    case ShadingMode::Hair: break;
  }
  return BarbGeometry::FacingRibbon;
}

ShadingMode parse_shading_mode(const std::string& s) {
  for (ShadingMode m : kShadingModes)
    if (s == to_string(m)) return m;
  throw Error("unknown shading mode '" + s + "': use 'hair', 'substructure', 'explicit' or 'farfield'");
}

}  // namespace plumage
