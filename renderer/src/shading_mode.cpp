#include "plumage/renderer/shading_mode.h"

#include "plumage/common/error.h"

namespace plumage {

const char* to_string(ShadingMode m) { return m == ShadingMode::Hair ? "hair" : "substructure"; }

ShadingMode parse_shading_mode(const std::string& s) {
  if (s == "hair") return ShadingMode::Hair;
  if (s == "substructure") return ShadingMode::Substructure;
  throw Error("unknown shading mode '" + s + "': use 'hair' or 'substructure'");
}

}  // namespace plumage
