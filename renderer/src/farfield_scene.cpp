// Scene's farfield mode (farfield.h, docs/substructure.md "Far-field model"): the
// barbs are substructure mode's in-vane ribbons; a filter lets a ray through a
// ribbon with the probability T(d) that the vane's table gives for straight
// passage through the gaps, so camera, path and shadow rays all see the barb's
// measured transmittance, and a hit that is kept is shaded by the table.
#include <algorithm>
#include <bit>
#include <vector>

#include "embree_device.h"
#include "plumage/common/error.h"
#include "plumage/renderer/sampler.h"

namespace plumage {

// A stochastic decision must be the same for the same ray and candidate, whoever
// asks, and independent between rays: a hash of the ray, the primitive and the
// candidate's distance.
struct FarfieldFilter {
  static float uniform(const glm::vec3& o, const glm::vec3& d, float t, std::uint32_t prim) {
    std::uint32_t h = hash_combine(std::bit_cast<std::uint32_t>(o.x), std::bit_cast<std::uint32_t>(o.y));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(o.z));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(d.x));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(d.y));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(d.z));
    h = hash_combine(h, std::bit_cast<std::uint32_t>(t));
    h = hash_combine(h, prim);
    return float(h >> 8) * 0x1p-24f;
  }

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
      const float T = scene->farfield_T_[vane.side() == VaneSide::Right]->transmittance(f.to_local(c.d));
      if (T > 0 && uniform(c.o, c.d, c.t, prim) < T) args->valid[i] = 0;
    }
  }
};

void attach_farfield_filter(RTCGeometry geom, const Scene* scene) {
  rtcSetGeometryUserData(geom, const_cast<Scene*>(scene));
  rtcSetGeometryIntersectFilterFunction(geom, &FarfieldFilter::pass_through);
  rtcSetGeometryOccludedFilterFunction(geom, &FarfieldFilter::pass_through);
}

// Substructure mode's ribbons, and per vane the geometry its table is fitted for:
// the vane's parameters and its barbule period, the median barb length over N.
void Scene::build_farfield() {
  build_substructure("--shading farfield");
  std::vector<float> lengths[2];
  std::size_t seg = 0;
  for (std::uint32_t ci = 0; ci < feather_.curves.size(); ++ci) {
    const Curve& c = feather_.curves[ci];
    if (c.kind != CurveKind::Barb || !keep_[ci]) continue;
    lengths[c.side == VaneSide::Right].push_back(ribbon_segments_[seg].length);
    seg += c.points.size() - 3;
  }
  for (int side = 0; side < 2; ++side) {
    if (lengths[side].empty()) continue;
    std::vector<float>& l = lengths[side];
    std::nth_element(l.begin(), l.begin() + l.size() / 2, l.end());
    FarfieldGeometry& g = farfield_geometry_[side];
    g.params = feather_.substructure(side ? VaneSide::Right : VaneSide::Left);
    g.period = g.params.barbules_per_side > 0 ? l[l.size() / 2] / float(g.params.barbules_per_side) : 0.0f;
    farfield_T_[side] = farfield_model(g, nullptr);
  }
}

Frame Scene::farfield_frame(const SurfaceHit& hit) const {
  Frame f = ribbon_point(hit.prim, hit.u, hit.p, true).barb;
  f.b *= ribbon_segments_[hit.prim].vane->distal_sign();
  return f;
}

}  // namespace plumage
