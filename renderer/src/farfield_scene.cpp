// Scene's farfield mode (farfield.h, docs/substructure.md "Far-field model"): the
// barbs are substructure mode's in-vane ribbons; a filter lets a ray through a
// ribbon with the probability T(d) that the vane's table gives for straight
// passage through the gaps, so camera, path and shadow rays all see the barb's
// measured transmittance, and a hit that is kept is shaded by the table.
#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <vector>

#include "embree_device.h"
#include "plumage/common/error.h"
#include "plumage/renderer/sampler.h"

namespace plumage {

// Each candidate passes with the far-field transmittance toward the ray, decided
// by FilterCandidate::uniform (the same for the same ray and candidate, whoever asks).
struct FarfieldFilter {
  static void pass_through(const RTCFilterFunctionNArguments* args) {
    const auto* scene = static_cast<const Scene*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
      if (!args->valid[i]) continue;
      if (RTCRayN_id(args->ray, args->N, i) & kKeepGapsId) continue;
      const FilterCandidate c(args, i);
      const std::uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
      const StructureSample ss = scene->ribbon_point(prim, RTCHitN_u(args->hit, args->N, i), c.point(), true);
      const BarbSubstructure& vane = *scene->ribbon_segments_[prim].vane;
      Frame f = ss.barb;
      f.b *= vane.distal_sign();
      const FarfieldModel& m = *scene->farfield_T_[vane.side() == VaneSide::Right][scene->farfield_class_[prim]];
      const float T = m.transmittance(f.to_local(c.d));
      if (T > 0 && c.uniform(prim) < T) args->valid[i] = 0;
    }
  }
};

void attach_farfield_filter(RTCGeometry geom, const Scene* scene) {
  rtcSetGeometryUserData(geom, const_cast<Scene*>(scene));
  rtcSetGeometryIntersectFilterFunction(geom, &FarfieldFilter::pass_through);
  rtcSetGeometryOccludedFilterFunction(geom, &FarfieldFilter::pass_through);
}

// Substructure mode's ribbons, and per vane the geometries its tables are fitted
// for. The curve file's N is per barb, so the barbule period L/N falls with the
// barb's length L: a vane's barbs are put in up to kMaxClasses classes spaced
// evenly in log period, each with its own table at the class's central period.
// Periods below half the one at which barbules cover the whole ribbon
// (2 r_b / sin theta_b) all share the lowest class.
void Scene::build_farfield() {
  constexpr int kMaxClasses = 4;
  constexpr double kClassRatio = 1.5;  // at least this ratio of periods per class
  build_substructure("--shading farfield");
  struct Barb {
    std::size_t first_prim, prims;
    double period;
  };
  std::vector<Barb> barbs[2];
  std::size_t seg = 0;
  for (std::uint32_t ci = 0; ci < feather_.curves.size(); ++ci) {
    const Curve& c = feather_.curves[ci];
    if (c.kind != CurveKind::Barb || !keep_[ci]) continue;
    const int n = feather_.substructure(c.side).barbules_per_side;
    const std::size_t prims = c.points.size() - 3;
    barbs[c.side == VaneSide::Right].push_back({seg, prims, n > 0 ? ribbon_segments_[seg].length / double(n) : 0.0});
    seg += prims;
  }
  farfield_class_.assign(seg, 0);
  for (int side = 0; side < 2; ++side) {
    if (barbs[side].empty()) continue;
    const SubstructureParams p = feather_.substructure(side ? VaneSide::Right : VaneSide::Left);
    const double saturated = 2 * double(p.barbule_radius) / std::sin(double(p.elevation_deg) * std::numbers::pi / 180);
    double lo = 1e30, hi = 0;
    for (const Barb& b : barbs[side]) {
      lo = std::min(lo, std::max(b.period, 0.5 * saturated));
      hi = std::max(hi, std::max(b.period, 0.5 * saturated));
    }
    const bool periodic = p.barbules_per_side > 0 && p.barbule_radius > 0 && hi > 0;
    const int classes =
        periodic ? std::clamp(int(std::ceil(std::log(hi / lo) / std::log(kClassRatio))), 1, kMaxClasses) : 1;
    const double span = classes > 1 ? std::log(hi / lo) : 1.0;
    for (int k = 0; k < classes; ++k) {
      FarfieldGeometry g;
      g.params = p;
      g.period = periodic ? float(lo * std::exp(span * (k + 0.5) / classes)) : 0.0f;
      if (classes == 1 && periodic) g.period = float(std::sqrt(lo * hi));
      farfield_geometry_[side].push_back(g);
      farfield_T_[side].push_back(farfield_model(g, nullptr));
    }
    for (const Barb& b : barbs[side]) {
      const double x = classes > 1 ? std::log(std::max(b.period, lo) / lo) / span * classes : 0.0;
      const auto k = std::uint8_t(std::clamp(int(x), 0, classes - 1));
      std::fill_n(farfield_class_.begin() + std::ptrdiff_t(b.first_prim), b.prims, k);
    }
  }
}

Frame Scene::farfield_frame(const SurfaceHit& hit) const {
  Frame f = ribbon_point(hit.prim, hit.u, hit.p, true).barb;
  f.b *= ribbon_segments_[hit.prim].vane->distal_sign();
  return f;
}

}  // namespace plumage
