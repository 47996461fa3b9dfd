// Scene's explicit mode (DESIGN §4, docs/substructure.md "Explicit reference"):
// every kept barb's ramus and barbules, built by explicit_geometry.h, as round
// B-spline curves in one Embree geometry.
#include <string>

#include "embree_device.h"
#include "plumage/common/stats.h"

namespace plumage {
namespace {

StatCounter g_explicit_curves("Explicit/Curves built (rami and barbules)");
StatCounter g_explicit_segments("Explicit/Curve segments (Embree primitives)");
StatCounter g_explicit_bytes("Explicit/Curve data (bytes, before Embree's BVH)");

}  // namespace

// Explicit mode: every kept barb's ramus and barbules as round B-spline curves in
// one Embree geometry (no filters: there are no gaps to reject, only empty space).
void Scene::build_explicit() {
  make_vanes("--shading explicit");
  ExplicitBarbs ex;
  // The same coverage per barb as substructure mode gives its ribbon, so both modes
  // take the same coverage-compensated albedo (structure_coverage) and compare fairly.
  explicit_coverage_.assign(feather_.curves.size(), 1.0f);
  for (std::uint32_t ci = 0; ci < feather_.curves.size(); ++ci)
    if (feather_.curves[ci].kind == CurveKind::Barb && keep_[ci]) {
      const double length = add_explicit_barb(feather_.curves[ci], ci, vane_of(ci), ex);
      explicit_coverage_[ci] = float(vane_of(ci).covered_fraction(length));
    }
  explicit_bytes_ = ex.bytes();
  g_explicit_curves += std::int64_t(ex.fibres.size());
  g_explicit_segments += std::int64_t(ex.segments());
  g_explicit_bytes += std::int64_t(explicit_bytes_);
  barbs_.vertices = std::move(ex.control_points);
  for (std::uint32_t fi = 0; fi < ex.fibres.size(); ++fi) {
    const ExplicitFibre& f = ex.fibres[fi];
    for (std::uint32_t s = 0; s < f.segments(); ++s) {
      barbs_.indices.push_back(f.first_cp + s);
      barbs_.prims.push_back({f.barb, f.first_cp + s, fi});
    }
  }
  explicit_fibres_ = std::move(ex.fibres);
  commit_curves(barbs_, RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE);
}

const ExplicitFibre& Scene::explicit_fibre(const SurfaceHit& hit) const {
  return explicit_fibres_[barbs_.prims[hit.prim].fibre];
}

}  // namespace plumage
