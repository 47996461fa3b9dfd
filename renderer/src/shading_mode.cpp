#include "plumage/renderer/shading_mode.h"

#include "plumage/common/error.h"

namespace plumage {

const char* to_string(ShadingMode m) {
  switch (m) {
    case ShadingMode::Substructure: return "substructure";
    case ShadingMode::Explicit: return "explicit";
    case ShadingMode::Hair: break;
  }
  return "hair";
}

ShadingMode parse_shading_mode(const std::string& s) {
  if (s == "hair") return ShadingMode::Hair;
  if (s == "substructure") return ShadingMode::Substructure;
  if (s == "explicit") return ShadingMode::Explicit;
  throw Error("unknown shading mode '" + s + "': use 'hair', 'substructure' or 'explicit'");
}

}  // namespace plumage
