// Builds the Embree scene of a feather: validates the curves, bounds them, leaves
// out culled ones, and commits the shaft and barbs in the mode's curve types
// (the other modes' parts live beside this file; scene.h lists them).
#include "plumage/renderer/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/task_arena.h>

#include "embree_device.h"
#include "float_mode.h"
#include "plumage/common/error.h"
#include "plumage/common/finite.h"
#include "plumage/common/stats.h"
#include "plumage/renderer/view_cull.h"

namespace plumage {
namespace {


StatCounter g_culled("Scene/Curves culled (outside the view and its shadow reach)");

}  // namespace

Scene::Scene(const Feather& feather, const SceneOptions& options) : Scene(feather, options, nullptr) {}

Scene::Scene(const Feather& feather, const SceneOptions& options, std::shared_ptr<const RibbonLayers> layers)
    : feather_(feather), options_(options), rtc_(std::make_unique<Embree>()), ribbon_layers_(std::move(layers)) {
  for (std::size_t i = 0; i < feather_.curves.size(); ++i) {
    const Curve& c = feather_.curves[i];
    const std::string which = std::string(to_string(c.kind)) + " curve #" + std::to_string(i);
    if (c.points.size() < 4)
      throw Error(which + " has " + std::to_string(c.points.size()) +
                  " control points; a cubic B-spline needs at least 4");
    for (const ControlPoint& cp : c.points)
      if (!all_finite(cp.p) || !std::isfinite(cp.radius) || cp.radius < 0)
        throw Error(which + " has a non-finite position or a negative radius; fix the curve file");
  }
  if (feather_.curves.empty()) throw Error("the feather has no curves to render");

  RTCDevice device = shared_device();
  rtc_->scene = rtcNewScene(device);
  rtcSetSceneFlags(rtc_->scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(rtc_->scene, RTC_BUILD_QUALITY_HIGH);

  // Convex-hull property: the control points' box (grown by the radius) holds the curve.
  std::vector<Bounds3f> curve_boxes(feather_.curves.size());
  // The vane's lowest point and widest ribbon place the card under it: its
  // pennaceous barbs', or a plume's down barbs' when it has no others (down barbs
  // that wave below a closed vane lie on the card, not under it).
  float lo_z[2] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()};
  float widest[2] = {0, 0};  // [0] barbs, [1] down barbs
  for (std::size_t i = 0; i < feather_.curves.size(); ++i) {
    const Curve& c = feather_.curves[i];
    const std::vector<float> radii = plumage::render_radii(feather_, c);
    for (std::size_t k = 0; k < c.points.size(); ++k) {
      const ControlPoint& cp = c.points[k];
      const float r = radii[k];
      curve_boxes[i].extend(cp.p - glm::vec3(r));
      curve_boxes[i].extend(cp.p + glm::vec3(r));
      max_radius_ = std::max(max_radius_, r);
      if (c.kind != CurveKind::Shaft) {
        max_barb_radius_ = std::max(max_barb_radius_, r);
        const int down = c.kind == CurveKind::Down;
        widest[down] = std::max(widest[down], r);
        lo_z[down] = std::min(lo_z[down], cp.p.z - r);
      }
    }
    bounds_.extend(curve_boxes[i]);
  }
  if (options_.backdrop.enabled) {
    // Just under the feather or its vane (backdrop.h).
    const glm::vec3 s = bounds_.size();
    const int by = std::isfinite(lo_z[0]) ? 0 : 1;
    const bool vane = options_.backdrop.placement == BackdropPlacement::Vane && std::isfinite(lo_z[by]);
    const float lo = vane ? lo_z[by] : bounds_.lo.z, r = vane ? widest[by] : max_radius_;
    backdrop_z_ = lo - std::max(4.0f * r, 1e-3f * std::max(s.x, s.y));
  }
  // Bounds, camera framing and backdrop stay those of the whole feather, so a
  // culled scene renders the same view as the full one.
  keep_ = keep_curves(options_.cull, curve_boxes, bounds_, options_.backdrop.enabled ? backdrop_z_ : bounds_.lo.z);
  culled_ = std::size_t(std::count(keep_.begin(), keep_.end(), 0));
  g_culled += std::int64_t(culled_);

  if (!feather_.albedo.texture.empty() && !ribbon_layers_) ribbon_layers_ = std::make_shared<const RibbonLayers>(feather_);
  if (options_.mode == ShadingMode::Substructure) build_substructure("--shading substructure");
  if (options_.mode == ShadingMode::Farfield) build_farfield();

  add_curves(shaft_, CurveKind::Shaft, RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE);
  build_down();
  switch (barb_geometry(options_.mode)) {
    case BarbGeometry::Structures: build_explicit(); break;
    case BarbGeometry::VaneRibbon:
      barbs_.filter = options_.mode == ShadingMode::Farfield ? CurveGeometry::Filter::Farfield : CurveGeometry::Filter::Gaps;
      add_curves(barbs_, CurveKind::Barb, RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BSPLINE_CURVE);
      break;
    case BarbGeometry::FacingRibbon: add_curves(barbs_, CurveKind::Barb, RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE); break;
  }
  scene_bounds_ = bounds_;
  if (options_.backdrop.enabled) add_backdrop();
  // A few float ulps at the scene's coordinates: spawn's margins (once, not per ray).
  const float scale = std::max({std::fabs(scene_bounds_.lo.x), std::fabs(scene_bounds_.lo.y),
                                std::fabs(scene_bounds_.lo.z), std::fabs(scene_bounds_.hi.x),
                                std::fabs(scene_bounds_.hi.y), std::fabs(scene_bounds_.hi.z), 1.0f});
  spawn_eps_ = 1e-5f * scale;

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

void Scene::add_curves(CurveGeometry& g, CurveKind kind, int rtc_type) {
  for (std::uint32_t ci = 0; ci < feather_.curves.size(); ++ci) {
    const Curve& c = feather_.curves[ci];
    if (c.kind != kind || !keep_[ci]) continue;
    const auto first = std::uint32_t(g.vertices.size());
    first_cp_.resize(feather_.curves.size(), 0);
    first_cp_[ci] = first;
    const std::vector<float> radii = plumage::render_radii(feather_, c);
    for (std::size_t k = 0; k < c.points.size(); ++k) g.vertices.emplace_back(c.points[k].p, radii[k]);
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
  if (!g.flags.empty())
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, g.flags.data(), 0,
                               sizeof(std::uint8_t), g.flags.size());
  if (rtc_type == RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BSPLINE_CURVE)
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, barb_normals_.data(), 0,
                               sizeof(glm::vec3), barb_normals_.size());
  switch (g.filter) {
    case CurveGeometry::Filter::Gaps: attach_gap_filter(geom, this); break;
    case CurveGeometry::Filter::Farfield: attach_farfield_filter(geom, this); break;
    case CurveGeometry::Filter::Down: attach_down_filter(geom, this); break;
    case CurveGeometry::Filter::None: break;
  }
  rtcCommitGeometry(geom);
  g.id = rtcAttachGeometry(rtc_->scene, geom);
  rtcReleaseGeometry(geom);
}

const Scene::CurveGeometry* Scene::curve_geometry(std::uint32_t geom) const {
  if (geom == barbs_.id) return &barbs_;
  if (geom == shaft_.id) return &shaft_;
  if (geom == down_.id) return &down_;
  return nullptr;
}

void* Scene::embree_scene() const { return rtc_->scene; }

int Scene::ribbon_layers(const SurfaceHit& hit) const {
  return hit.kind == HitKind::Barb && ribbon_layers_ ? ribbon_layers_->at({hit.p.x, hit.p.y}) : 1;
}

}  // namespace plumage
