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

ShadingMode parse_shading_mode(const std::string& s) {
  for (ShadingMode m : kShadingModes)
    if (s == to_string(m)) return m;
  throw Error("unknown shading mode '" + s + "': use 'hair', 'substructure', 'explicit' or 'farfield'");
}

}  // namespace plumage
