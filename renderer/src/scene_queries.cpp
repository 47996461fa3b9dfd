// Ray queries against a Scene: the closest hit, occlusion, and the rule for
// secondary rays (spawn) with the context filter that carries it into Embree.
#include <algorithm>
#include <cmath>

#include "embree_device.h"
#include "plumage/common/bspline.h"

namespace plumage {

// What a ray query hands to the context filter: Embree passes our context
// pointer through, so the ray's skip rule travels with it.
struct SceneFilter {
  RTCIntersectContext rtc;
  const Scene* scene;
  const Ray* ray;

  // Rejects hits on the primitive a secondary ray left (see Scene::spawn).
  static void skip_origin(const RTCFilterFunctionNArguments* args) {
    const auto* self = reinterpret_cast<const SceneFilter*>(args->context);
    const Ray& r = *self->ray;
    for (unsigned i = 0; i < args->N; ++i) {
      if (!args->valid[i]) continue;
      const unsigned geom = RTCHitN_geomID(args->hit, args->N, i);
      // During filtering Embree stores the candidate hit distance in tfar.
      if (geom != r.skip_geom || RTCRayN_tfar(args->ray, args->N, i) >= r.skip_until) continue;
      const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
      const Scene::CurveGeometry* g = self->scene->curve_geometry(geom);
      const std::uint32_t id = g ? g->prims[prim].fibre : prim;
      if (id == r.skip_curve) args->valid[i] = 0;
    }
  }

  SceneFilter(const Scene* s, const Ray* r) : scene(s), ray(r) {
    rtcInitIntersectContext(&rtc);
    // Primary rays skip nothing and pay for no callback.
    rtc.filter = r->skip_geom == kNoId ? nullptr : &SceneFilter::skip_origin;
  }
};

bool Scene::intersect(const Ray& ray, SurfaceHit& hit, bool keep_gaps) const {
  SceneFilter ctx(this, &ray);
  RTCRayHit rh = rtc_ray_hit(ray, keep_gaps ? kKeepGapsId : 0);
  rtcIntersect1(rtc_->scene, &ctx.rtc, &rh);
  flush_gap_rejections();
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
    hit.kind = HitKind::None;
    return false;
  }
  hit.t = rh.ray.tfar;
  hit.p = ray.o + hit.t * ray.d;
  hit.ng = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  hit.geom = rh.hit.geomID;
  hit.prim = rh.hit.primID;
  if (const CurveGeometry* g = curve_geometry(hit.geom)) {
    hit.curve = g->prims[hit.prim].curve;
    hit.kind = g == &shaft_ ? HitKind::Shaft : g == &down_ ? HitKind::Down : HitKind::Barb;
  } else {
    hit.curve = kNoId;
    hit.kind = HitKind::Backdrop;
  }
  return true;
}

bool Scene::occluded(const Ray& ray) const {
  SceneFilter ctx(this, &ray);
  RTCRay r = rtc_ray(ray);
  rtcOccluded1(rtc_->scene, &ctx.rtc, &r);
  flush_gap_rejections();
  return r.tfar < 0;  // Embree sets tfar = -inf on occlusion
}

// Debian's Embree is built with EMBREE_CURVE_SELF_INTERSECTION_AVOIDANCE_FACTOR = 2:
// it drops flat-curve hits closer to the ray origin than 2x the curve radius. A ray
// leaving a barb would then pass through a neighbouring barb that touches it, and
// light would leak between barbs. So the ray starts a distance D (more than twice
// the largest barb radius) *behind* the hit point with tnear = D: everything at or
// beyond the hit point lies farther than 2r from the origin and is found.
//
// The fibre the ray left is skipped (context filter) until the ray is out of it,
// since the fibre's BCSDF already accounts for light crossing it (DESIGN §4). A
// round fibre, and a ray-facing ribbon (which Embree turns to face every ray, so it
// lies within the same tube), holds the ray for up to 2r / cos(theta), theta its
// angle to the fibre's normal plane: the skip runs to the exit from the tube around
// the fibre's tangent line at the hit (tube_exit_distance), never less than 2r. A
// normal-oriented ribbon lies in the vane, so a ray leaves it at once.
Ray Scene::spawn(const SurfaceHit& from, const glm::vec3& d, float tmax) const {
  const float eps = spawn_eps_;
  const float D = 2.05f * max_barb_radius_ + eps;
  Ray r;
  r.o = from.p - D * d;
  r.d = d;
  r.tnear = D;
  r.tfar = D + tmax;
  r.skip_geom = from.geom;
  if (from.kind == HitKind::Backdrop) {
    r.skip_curve = from.prim;
    r.skip_until = D + 4 * eps;
    return r;
  }
  r.skip_curve = curve_geometry(from.geom)->prims[from.prim].fibre;
  const CurvePoint cp = curve_point(from);
  float inside = 2.05f * cp.radius;
  const bool in_vane = from.kind == HitKind::Barb && barb_geometry(options_.mode) == BarbGeometry::VaneRibbon;
  if (!in_vane) {
    // 2 % on the radius covers the tube's bend over the few radii the ray crosses.
    const float exit = tube_exit_distance(from.p, d, cp.p, cp.dp, 1.02f * cp.radius + eps);
    inside = std::max(inside, exit);
  }
  r.skip_until = D + inside + 4 * eps;
  return r;
}

float Scene::curve_parameter(const SurfaceHit& hit) const {
  const Primitive& prim = curve_geometry(hit.geom)->prims[hit.prim];
  const float segments = float(feather_.curves[prim.curve].points.size() - 3);
  return std::clamp((float(prim.first_cp - first_cp_[prim.curve]) + hit.u) / segments, 0.0f, 1.0f);
}

CurvePoint Scene::curve_point(const SurfaceHit& hit) const {
  const CurveGeometry* g = curve_geometry(hit.geom);
  const glm::vec4* cp = &g->vertices[g->prims[hit.prim].first_cp];
  if (g->linear) {
    const glm::vec4 p = cp[0] + hit.u * (cp[1] - cp[0]);
    return {glm::vec3(p), glm::vec3(cp[1] - cp[0]), p.w};
  }
  const auto b = CubicBSplineBasis::eval(hit.u);
  const auto db = CubicBSplineBasis::deriv(hit.u);
  glm::vec4 p(0), dp(0);
  for (int i = 0; i < 4; ++i) {
    p += float(b[i]) * cp[i];
    dp += float(db[i]) * cp[i];
  }
  return {glm::vec3(p), glm::vec3(dp), p.w};
}

}  // namespace plumage
