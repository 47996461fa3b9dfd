// TEMPORARY: lets `plumage render` link before the fcurves branch lands the real
// read_fcurves in common/src (delete this file then). Weak, so the real definition
// wins wherever its object file is linked in.
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"

namespace plumage {

[[gnu::weak]] Feather read_fcurves(const std::filesystem::path& path) {
  throw Error(Location{path.string()}, "this build cannot read .fcurves files yet (the reader lands with the fcurves work)");
}

}  // namespace plumage
