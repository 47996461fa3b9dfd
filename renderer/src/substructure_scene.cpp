// Scene's substructure mode (DESIGN §5, docs/substructure.md): one
// BarbSubstructure per vane, the barbs as normal-oriented ribbons with a table of
// arc length per segment, the gap filter that lets rays through empty space inside
// Embree, and the structure lookups shading needs.
#include <algorithm>
#include <cmath>
#include <string>

#include "embree_device.h"
#include "plumage/common/bspline.h"
#include "plumage/common/error.h"
#include "plumage/common/stats.h"

namespace plumage {
namespace {

StatCounter g_structure_lookups("Substructure/Structure lookups at shading");
StatCounter g_gap_rejections("Substructure/Candidate hits rejected in gaps");
// Filter functions run deep inside Embree: they tally here and the query adds the
// tally to the shared counter once, instead of one atomic add per rejection.
thread_local std::int64_t t_gap_rejections = 0;

}  // namespace

void flush_gap_rejections() {
  if (t_gap_rejections) {
    g_gap_rejections += t_gap_rejections;
    t_gap_rejections = 0;
  }
}

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
      const glm::vec3 p = FilterCandidate(args, i).point();
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

void attach_gap_filter(RTCGeometry geom, const Scene* scene) {
  rtcSetGeometryUserData(geom, const_cast<Scene*>(scene));
  rtcSetGeometryIntersectFilterFunction(geom, &SubstructureFilter::reject_gaps);
  rtcSetGeometryOccludedFilterFunction(geom, &SubstructureFilter::reject_gaps);
}

// Substructure mode: one BarbSubstructure per vane (validated here, so a bad
// parameter fails before any ray is traced), the vane normals Embree orients the
// ribbons with, and per segment a table of arc length s at evenly spaced u.
void Scene::make_vanes(const char* what) {
  // Only a vane with (pennaceous) barbs: down barbs carry no substructure.
  const auto has_barbs = [&](VaneSide side) {
    return std::any_of(feather_.curves.begin(), feather_.curves.end(),
                       [&](const Curve& c) { return c.kind == CurveKind::Barb && c.side == side; });
  };
  for (VaneSide side : {VaneSide::Left, VaneSide::Right})
    if (has_barbs(side)) (side == VaneSide::Left ? left_ : right_).emplace(feather_.substructure(side), side, what);
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

void Scene::build_substructure(const char* what) {
  make_vanes(what);
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

}  // namespace plumage
