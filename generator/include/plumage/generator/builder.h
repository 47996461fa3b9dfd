#pragma once
// Procedural feather builder: FeatherParams + seed -> Feather, in the spirit of
// the generator the seed paper used for its specimens (Baron et al. 2021 §4,
// citing Baron & Patterson, "Procedurally generating biologically driven
// feathers", LNCS 2019): one shaft curve and many branching barb curves.
// The shaft is a B-spline along a bent arc; each vane is a Catmull-Clark surface (vane_surface.h)
// spanned from the shaft to the vane edge; each barb is traced in the vane's
// (u, v) domain from its root on the shaft to the edge, leaving the shaft at the
// barb angle and turning toward the tip, and its control points are put on the
// limit surface with the limit normal there. Same params and seed, same Feather,
// bit for bit with the same maths library (random.h fixes the random numbers;
// another libm may round sin/tan differently in the last bit).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "plumage/common/feather.h"
#include "plumage/generator/feather_params.h"
#include "plumage/generator/vane_surface.h"

namespace plumage {

// A barb's samples in its vane's domain: uv[j] = (u, v) of the j-th control
// point before the phantom ends, v rising evenly from 0 (shaft) to 1 (edge).
struct BarbPath {
  VaneSide side = VaneSide::Left;
  bool loose = false;             // an afterfeather barb (lifted off the surface)
  std::vector<glm::dvec2> uv;
};

// The feather plus what it was built from, for tests, previews and debugging.
struct FeatherBuild {
  Feather feather;
  std::vector<BarbPath> paths;    // paths[k] belongs to feather.curves[k + 1]
  std::unique_ptr<VaneSurface> left, right;
  double vane_start = 0;          // arc length of the shaft where the vane begins (mm)
  double shaft_length = 0;        // arc length of the shaft B-spline (mm)
  const VaneSurface& surface(VaneSide s) const { return s == VaneSide::Right ? *right : *left; }
};

// `source` goes into Feather.provenance.source ("preset:NAME", "params:FILE").
// Validates `params` first (plumage::Error on a bad parameter).
FeatherBuild build_feather_detailed(const FeatherParams& params, std::uint64_t seed,
                                    const std::string& source = "params");
Feather build_feather(const FeatherParams& params, std::uint64_t seed, const std::string& source = "params");

}  // namespace plumage
