// Scene's down barbs (CurveKind::Down; docs/curve-format.md, "Down"): round tubes,
// the reach of each barb's barbules around its ramus, that its fibres fill to
// Feather::down_cover. Their filter lets a ray through a tube where it meets no
// fibre, in every shading mode.
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

void Scene::build_down() {
  add_curves(down_, {CurveKind::Down}, RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE);
}

}  // namespace plumage
