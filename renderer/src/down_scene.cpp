// Scene's down barbs (CurveKind::Down; docs/curve-format.md, "Down"): round tubes,
// the reach of each barb's barbules around its ramus, that its fibres fill to
// Feather::down_cover. Their filter lets a ray through a tube where it meets no
// fibre, in every shading mode.
#include <vector>

#include "embree_device.h"

namespace plumage {

// A ray crossing a down barb's tube surface meets a fibre there with probability
// down_cover, decided by FilterCandidate::uniform: the same for the same ray and
// candidate, whoever asks (intersection and occlusion agree), independent between
// rays. The structure AOV's rays see the tubes whole.
struct DownFilter {
  static void pass_open(const RTCFilterFunctionNArguments* args) {
    const auto* scene = static_cast<const Scene*>(args->geometryUserPtr);
    const float cover = scene->feather_.down_cover;
    for (unsigned i = 0; i < args->N; ++i) {
      if (!args->valid[i]) continue;
      if (RTCRayN_id(args->ray, args->N, i) & kKeepGapsId) continue;
      const FilterCandidate c(args, i);
      if (c.uniform(RTCHitN_primID(args->hit, args->N, i)) >= cover) args->valid[i] = 0;
    }
  }
};

void attach_down_filter(RTCGeometry geom, const Scene* scene) {
  rtcSetGeometryUserData(geom, const_cast<Scene*>(scene));
  rtcSetGeometryIntersectFilterFunction(geom, &DownFilter::pass_open);
  rtcSetGeometryOccludedFilterFunction(geom, &DownFilter::pass_open);
}

// As chains of round linear pieces within kPolylineTolerance of the B-spline: wide,
// overlapping round B-spline curves cost Embree far more to intersect.
void Scene::build_down() {
  down_.linear = true;
  if (feather_.down_cover < 1.0f) down_.filter = CurveGeometry::Filter::Down;
  std::vector<glm::vec4> cps;
  for (std::uint32_t ci = 0; ci < feather_.curves.size(); ++ci) {
    const Curve& c = feather_.curves[ci];
    if (c.kind != CurveKind::Down || !keep_[ci]) continue;
    const std::vector<float> radii = plumage::render_radii(feather_, c);
    cps.clear();
    for (std::size_t k = 0; k < c.points.size(); ++k) cps.emplace_back(c.points[k].p, radii[k]);
    append_polyline(down_, cps.data(), cps.size() - 3, ci, ci);
  }
  commit_curves(down_, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
}

}  // namespace plumage
