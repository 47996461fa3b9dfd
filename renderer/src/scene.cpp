// Builds the Embree scene of a feather and answers ray queries against it.
// One Embree device serves the whole process (creating one starts a thread pool).
#include "plumage/renderer/scene.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <string>

#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include "float_mode.h"

#include "plumage/common/bspline.h"
#include "plumage/common/error.h"
#include "plumage/common/stats.h"

namespace plumage {
namespace {

std::mutex g_device_mu;
std::string g_device_error;

void on_device_error(void*, RTCError code, const char* msg) {
  std::lock_guard lock(g_device_mu);
  g_device_error = "Embree error " + std::to_string(int(code)) + ": " + (msg ? msg : "");
}

RTCDevice shared_device() {
  static RTCDevice device = [] {
    RTCDevice d = rtcNewDevice(nullptr);
    if (!d) throw Error("cannot create the Embree device (is the CPU supported by this Embree build?)");
    rtcSetDeviceErrorFunction(d, on_device_error, nullptr);
    return d;
  }();
  return device;
}

void throw_if_device_error(const char* during) {
  std::lock_guard lock(g_device_mu);
  if (g_device_error.empty()) return;
  std::string msg = std::move(g_device_error);
  g_device_error.clear();
  throw Error(std::string(during) + ": " + msg);
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

StatCounter g_culled("Scene/Curves culled (outside the view and its shadow reach)");
StatCounter g_structure_lookups("Substructure/Structure lookups at shading");
StatCounter g_gap_rejections("Substructure/Candidate hits rejected in gaps");
StatCounter g_explicit_curves("Explicit/Curves built (rami and barbules)");
StatCounter g_explicit_segments("Explicit/Curve segments (Embree primitives)");
StatCounter g_explicit_bytes("Explicit/Curve data (bytes, before Embree's BVH)");
// Filter functions run deep inside Embree: they tally here and the query adds the
// tally to the shared counter once, instead of one atomic add per rejection.
thread_local std::int64_t t_gap_rejections = 0;

void flush_gap_rejections() {
  if (t_gap_rejections) {
    g_gap_rejections += t_gap_rejections;
    t_gap_rejections = 0;
  }
}

// Ray id bit: keep hits in the gaps (the structure AOV wants to see them).
constexpr unsigned kKeepGapsId = 1u;

}  // namespace

// Substructure mode's intersection and occlusion filter on the barb ribbons: a
// candidate hit in empty space (G_b = empty, Eq. 1's T with eta = 1) is rejected,
// so Embree continues traversal past it; no shading and no re-trace are spent on
// it, and shadow rays pass through gaps.
struct SubstructureFilter {
  static void reject_gaps(const RTCFilterFunctionNArguments* args) {
    const auto* scene = static_cast<const Scene*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
      if (!args->valid[i]) continue;
      if (RTCRayN_id(args->ray, args->N, i) & kKeepGapsId) continue;
      const glm::vec3 o(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                        RTCRayN_org_z(args->ray, args->N, i));
      const glm::vec3 d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                        RTCRayN_dir_z(args->ray, args->N, i));
      // During filtering Embree stores the candidate hit distance in tfar.
      const glm::vec3 p = o + RTCRayN_tfar(args->ray, args->N, i) * d;
      const std::uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
      const StructureSample ss = scene->ribbon_point(prim, RTCHitN_u(args->hit, args->N, i), p, false);
      const Scene::RibbonSegment& rs = scene->ribbon_segments_[prim];
      if (rs.vane->classify(ss.s, ss.w, rs.length).structure == Structure::Empty) {
        args->valid[i] = 0;
        ++t_gap_rejections;
      }
    }
  }
};

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

struct Scene::Embree {
  RTCScene scene = nullptr;
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
  }
};

Scene::Scene(const Feather& feather, const SceneOptions& options)
    : feather_(feather), options_(options), rtc_(std::make_unique<Embree>()) {
  for (std::size_t i = 0; i < feather_.curves.size(); ++i) {
    const Curve& c = feather_.curves[i];
    const std::string which = std::string(to_string(c.kind)) + " curve #" + std::to_string(i);
    if (c.points.size() < 4)
      throw Error(which + " has " + std::to_string(c.points.size()) +
                  " control points; a cubic B-spline needs at least 4");
    for (const ControlPoint& cp : c.points)
      if (!finite(cp.p) || !std::isfinite(cp.radius) || cp.radius < 0)
        throw Error(which + " has a non-finite position or a negative radius; fix the curve file");
  }
  if (feather_.curves.empty()) throw Error("the feather has no curves to render");

  RTCDevice device = shared_device();
  rtc_->scene = rtcNewScene(device);
  rtcSetSceneFlags(rtc_->scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(rtc_->scene, RTC_BUILD_QUALITY_HIGH);

  // Convex-hull property: the control points' box (grown by the radius) holds the curve.
  std::vector<AxisBox> curve_boxes(feather_.curves.size());
  bounds_.lo = glm::vec3(std::numeric_limits<float>::infinity());
  bounds_.hi = -bounds_.lo;
  for (std::size_t i = 0; i < feather_.curves.size(); ++i) {
    const Curve& c = feather_.curves[i];
    curve_boxes[i] = {glm::vec3(std::numeric_limits<float>::infinity()), glm::vec3(-std::numeric_limits<float>::infinity())};
    for (const ControlPoint& cp : c.points) {
      const float r = render_radius(c, cp);
      curve_boxes[i].lo = glm::min(curve_boxes[i].lo, cp.p - glm::vec3(r));
      curve_boxes[i].hi = glm::max(curve_boxes[i].hi, cp.p + glm::vec3(r));
      max_radius_ = std::max(max_radius_, r);
      if (c.kind == CurveKind::Barb) max_barb_radius_ = std::max(max_barb_radius_, r);
    }
    bounds_.lo = glm::min(bounds_.lo, curve_boxes[i].lo);
    bounds_.hi = glm::max(bounds_.hi, curve_boxes[i].hi);
  }
  if (options_.backdrop.enabled) {
    // Just under the feather, but farther than any curve's near-origin culling distance.
    const glm::vec3 s = bounds_.size();
    backdrop_z_ = bounds_.lo.z - std::max(4.0f * max_radius_, 1e-3f * std::max(s.x, s.y));
  }
  // Bounds, camera framing and backdrop stay those of the whole feather, so a
  // culled scene renders the same view as the full one.
  keep_.assign(feather_.curves.size(), 1);
  if (options_.cull) {
    const CurveKeep keep = options_.cull(bounds_, options_.backdrop.enabled ? backdrop_z_ : bounds_.lo.z);
    for (std::size_t i = 0; i < keep_.size(); ++i)
      if (!keep(curve_boxes[i])) {
        keep_[i] = 0;
        ++culled_;
      }
    g_culled += std::int64_t(culled_);
  }

  if (options_.mode == ShadingMode::Substructure) build_substructure();

  add_curves(shaft_, CurveKind::Shaft, RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE);
  if (options_.mode == ShadingMode::Explicit)
    build_explicit();
  else
    add_curves(barbs_, CurveKind::Barb,
               options_.mode == ShadingMode::Substructure ? RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BSPLINE_CURVE
                                                          : RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE);
  scene_bounds_ = bounds_;
  if (options_.backdrop.enabled) add_backdrop();

  {
    // TBB gives a thread's tasks the FTZ/DAZ mode the thread had when it first
    // used TBB. Meet TBB with the caller's own mode, then build in an arena of its
    // own with FTZ/DAZ on (float_mode.h): neither mode outlives the build.
    tbb::task_arena build_arena;
    build_arena.initialize();
    const detail::FtzDazScope ftz_daz;
    build_arena.execute([&] { rtcCommitScene(rtc_->scene); });
  }
  throw_if_device_error("building the Embree scene");
}

Scene::~Scene() = default;

// DESIGN §4: hair and substructure modes draw a barb with the same centreline and
// width, the barb's full width W (ramus plus barbules) from its vane's parameters,
// so the two shadings cover the same area and differ only in what the ribbon holds.
// A vane without a ribbon width falls back to the curve's own radius.
float Scene::render_radius(const Curve& c, const ControlPoint& cp) const {
  if (c.kind != CurveKind::Barb) return cp.radius;
  const float w = feather_.substructure(c.side).ribbon_width;
  return w > 0 ? 0.5f * w : cp.radius;
}

void Scene::add_curves(CurveGeometry& g, CurveKind kind, int rtc_type) {
  for (std::uint32_t ci = 0; ci < feather_.curves.size(); ++ci) {
    const Curve& c = feather_.curves[ci];
    if (c.kind != kind || !keep_[ci]) continue;
    const auto first = std::uint32_t(g.vertices.size());
    for (const ControlPoint& cp : c.points) g.vertices.emplace_back(cp.p, render_radius(c, cp));
    for (std::uint32_t s = 0; s + 3 < c.points.size(); ++s) {
      g.indices.push_back(first + s);
      g.prims.push_back({ci, first + s, ci});
    }
  }
  commit_curves(g, rtc_type);
}

void Scene::commit_curves(CurveGeometry& g, int rtc_type) {
  if (g.indices.empty()) return;
  RTCGeometry geom = rtcNewGeometry(shared_device(), RTCGeometryType(rtc_type));
  // Shared buffers: Embree reads our vectors in place, so they must outlive the scene (they do).
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, g.vertices.data(), 0,
                             sizeof(glm::vec4), g.vertices.size());
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, g.indices.data(), 0,
                             sizeof(std::uint32_t), g.indices.size());
  if (rtc_type == RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BSPLINE_CURVE) {
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, barb_normals_.data(), 0,
                               sizeof(glm::vec3), barb_normals_.size());
    rtcSetGeometryUserData(geom, const_cast<Scene*>(this));
    rtcSetGeometryIntersectFilterFunction(geom, &SubstructureFilter::reject_gaps);
    rtcSetGeometryOccludedFilterFunction(geom, &SubstructureFilter::reject_gaps);
  }
  rtcCommitGeometry(geom);
  g.id = rtcAttachGeometry(rtc_->scene, geom);
  rtcReleaseGeometry(geom);
}

void Scene::add_backdrop() {
  const glm::vec3 c = bounds_.centre(), s = bounds_.size();
  const float half = 0.5f * options_.backdrop.extent * std::max({s.x, s.y, 1e-3f});
  static const float kQuad[4][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  RTCGeometry geom = rtcNewGeometry(shared_device(), RTC_GEOMETRY_TYPE_QUAD);
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4));
  for (int i = 0; i < 4; ++i) {
    v[3 * i + 0] = c.x + half * kQuad[i][0];
    v[3 * i + 1] = c.y + half * kQuad[i][1];
    v[3 * i + 2] = backdrop_z_;
  }
  auto* idx = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), 1));
  for (unsigned i = 0; i < 4; ++i) idx[i] = i;
  rtcCommitGeometry(geom);
  backdrop_id_ = rtcAttachGeometry(rtc_->scene, geom);
  rtcReleaseGeometry(geom);
  scene_bounds_.lo = glm::min(bounds_.lo, glm::vec3(c.x - half, c.y - half, backdrop_z_));
  scene_bounds_.hi = glm::max(bounds_.hi, glm::vec3(c.x + half, c.y + half, backdrop_z_));
}

const Scene::CurveGeometry* Scene::curve_geometry(std::uint32_t geom) const {
  if (geom == barbs_.id) return &barbs_;
  if (geom == shaft_.id) return &shaft_;
  return nullptr;
}

void* Scene::embree_scene() const { return rtc_->scene; }

bool Scene::intersect(const Ray& ray, SurfaceHit& hit, bool keep_gaps) const {
  SceneFilter ctx(this, &ray);
  RTCRayHit rh;
  rh.ray.org_x = ray.o.x; rh.ray.org_y = ray.o.y; rh.ray.org_z = ray.o.z;
  rh.ray.dir_x = ray.d.x; rh.ray.dir_y = ray.d.y; rh.ray.dir_z = ray.d.z;
  rh.ray.tnear = ray.tnear;
  rh.ray.tfar = ray.tfar;
  rh.ray.time = 0;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = keep_gaps ? kKeepGapsId : 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
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
    hit.kind = g == &shaft_ ? HitKind::Shaft : HitKind::Barb;
  } else {
    hit.curve = kNoId;
    hit.kind = HitKind::Backdrop;
  }
  return true;
}

bool Scene::occluded(const Ray& ray) const {
  SceneFilter ctx(this, &ray);
  RTCRay r;
  r.org_x = ray.o.x; r.org_y = ray.o.y; r.org_z = ray.o.z;
  r.dir_x = ray.d.x; r.dir_y = ray.d.y; r.dir_z = ray.d.z;
  r.tnear = ray.tnear;
  r.tfar = ray.tfar;
  r.time = 0;
  r.mask = 0xffffffffu;
  r.id = 0;
  r.flags = 0;
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
  const float scale = std::max({std::fabs(scene_bounds_.lo.x), std::fabs(scene_bounds_.lo.y),
                                std::fabs(scene_bounds_.lo.z), std::fabs(scene_bounds_.hi.x),
                                std::fabs(scene_bounds_.hi.y), std::fabs(scene_bounds_.hi.z), 1.0f});
  const float eps = 1e-5f * scale;  // a few float ulps at the scene's coordinates
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
  const bool in_vane = from.kind == HitKind::Barb && options_.mode == ShadingMode::Substructure;
  if (!in_vane) {
    // 2 % on the radius covers the tube's bend over the few radii the ray crosses.
    const float exit = tube_exit_distance(from.p, d, cp.p, cp.dp, 1.02f * cp.radius + eps);
    inside = std::max(inside, exit);
  }
  r.skip_until = D + inside + 4 * eps;
  return r;
}

CurvePoint Scene::curve_point(const SurfaceHit& hit) const {
  const CurveGeometry* g = curve_geometry(hit.geom);
  const glm::vec4* cp = &g->vertices[g->prims[hit.prim].first_cp];
  const auto b = CubicBSplineBasis::eval(hit.u);
  const auto db = CubicBSplineBasis::deriv(hit.u);
  glm::vec4 p(0), dp(0);
  for (int i = 0; i < 4; ++i) {
    p += float(b[i]) * cp[i];
    dp += float(db[i]) * cp[i];
  }
  return {glm::vec3(p), glm::vec3(dp), p.w};
}

// Substructure mode: one BarbSubstructure per vane (validated here, so a bad
// parameter fails before any ray is traced), the vane normals Embree orients the
// ribbons with, and per segment a table of arc length s at evenly spaced u.
void Scene::make_vanes(const char* what) {
  for (VaneSide side : {VaneSide::Left, VaneSide::Right})
    if (feather_.count(side) > 0)
      (side == VaneSide::Left ? left_ : right_).emplace(feather_.substructure(side), side, what);
  for (std::uint32_t ci = 0; ci < feather_.curves.size(); ++ci) {
    const Curve& c = feather_.curves[ci];
    if (c.kind == CurveKind::Barb && keep_[ci] && c.side == VaneSide::None)
      throw Error("barb curve #" + std::to_string(ci) + " belongs to no vane; " + what +
                  " needs 'left' or 'right' to tell distal from proximal");
  }
}

const BarbSubstructure& Scene::vane_of(std::uint32_t curve) const {
  return feather_.curves[curve].side == VaneSide::Right ? *right_ : *left_;
}

void Scene::build_substructure() {
  make_vanes("--shading substructure");
  for (std::uint32_t ci = 0; ci < feather_.curves.size(); ++ci) {
    const Curve& c = feather_.curves[ci];
    if (c.kind != CurveKind::Barb || !keep_[ci]) continue;
    std::vector<glm::dvec3> pts;
    for (const ControlPoint& cp : c.points) {
      pts.emplace_back(cp.p);
      barb_normals_.push_back(safe_normalize(cp.n));
    }
    const BSpline3 spline(pts);
    const ArcLengthTable table(spline);
    const std::size_t segs = spline.num_segments();
    for (std::size_t seg = 0; seg < segs; ++seg) {
      ribbon_segments_.push_back({&vane_of(ci), std::uint32_t(arc_s_.size()), float(table.length())});
      for (int j = 0; j <= kArcSamples; ++j)
        arc_s_.push_back(float(table.s_at((double(seg) + double(j) / kArcSamples) / double(segs))));
    }
  }
}

StructureSample Scene::ribbon_point(std::uint32_t prim, float u, const glm::vec3& p, bool full_frame) const {
  const std::uint32_t first = barbs_.prims[prim].first_cp;
  const glm::vec4* cp = &barbs_.vertices[first];
  const glm::vec3* np = &barb_normals_[first];
  const auto bu = CubicBSplineBasis::eval(u);
  const auto db = CubicBSplineBasis::deriv(u);
  glm::vec3 c(0), dc(0), n(0);
  for (int i = 0; i < 4; ++i) {
    c += float(bu[i]) * glm::vec3(cp[i]);
    dc += float(db[i]) * glm::vec3(cp[i]);
    n += float(bu[i]) * np[i];
  }
  StructureSample ss;
  if (full_frame) {
    ss.barb = frame_from_tangent_normal(dc, n);
    ss.w = glm::dot(p - c, ss.barb.b);
  } else {
    // The filter needs only w: b = n x t without building the whole frame. The vane
    // normal is never along the barb, so the cross product does not vanish.
    const glm::vec3 b = glm::cross(n, dc);
    ss.w = glm::dot(p - c, b) / std::sqrt(std::fmax(glm::dot(b, b), 1e-30f));
  }
  const float x = std::clamp(u, 0.0f, 1.0f) * kArcSamples;
  const int j = std::min(int(x), kArcSamples - 1);
  const float* s = &arc_s_[ribbon_segments_[prim].arc + j];
  ss.s = s[0] + (x - float(j)) * (s[1] - s[0]);
  return ss;
}

float Scene::structure_coverage(const SurfaceHit& hit) const {
  if (hit.kind != HitKind::Barb) return 1.0f;
  if (options_.mode == ShadingMode::Explicit) return explicit_coverage_[barbs_.prims[hit.prim].curve];
  if (options_.mode != ShadingMode::Substructure) return 1.0f;
  const RibbonSegment& rs = ribbon_segments_[hit.prim];
  return float(rs.vane->covered_fraction(rs.length));
}

StructureSample Scene::structure_at(const SurfaceHit& hit) const {
  // Proof that hair mode never reaches substructure code (skip_work_test).
  ++g_structure_lookups;
  StructureSample ss = ribbon_point(hit.prim, hit.u, hit.p, true);
  const RibbonSegment& rs = ribbon_segments_[hit.prim];
  ss.hit = rs.vane->classify(ss.s, ss.w, rs.length);
  ss.frame = rs.vane->frame(ss.barb, ss.hit, ss.w);
  return ss;
}

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
