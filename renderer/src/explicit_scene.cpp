// Scene's explicit mode (DESIGN §4, docs/substructure.md "Explicit reference"):
// every kept barb's ramus and barbules, built by explicit_geometry.h, as round
// B-spline curves in one Embree geometry (or, for the far-field fit's patch, as
// chains of round linear pieces: SceneOptions::explicit_polylines).
#include <algorithm>
#include <cmath>
#include <string>

#include "embree_device.h"
#include "plumage/common/bspline.h"
#include "plumage/common/stats.h"

namespace plumage {
namespace {

StatCounter g_explicit_curves("Explicit/Curves built (rami and barbules)");
StatCounter g_explicit_segments("Explicit/Curve segments (Embree primitives)");
StatCounter g_explicit_bytes("Explicit/Curve data (bytes, before Embree's BVH)");

// A uniform cubic B-spline segment (four control points: x, y, z, radius) at u.
glm::vec4 bspline_point(const glm::vec4* cp, float u) {
  const auto b = CubicBSplineBasis::eval(u);
  glm::vec4 p(0);
  for (int i = 0; i < 4; ++i) p += float(b[i]) * cp[i];
  return p;
}

// The fewest pieces (1, 2, 4, ... 64) whose polyline, checked at 16 points of each
// piece, stays within kPolylineTolerance of the radius from the segment in
// position and radius (SceneOptions::explicit_polylines).
int polyline_pieces(const glm::vec4* cp) {
  for (int pieces = 1;; pieces *= 2) {
    float worst = 0, radius = 1e30f;
    for (int k = 0; k < pieces; ++k) {
      const float u0 = float(k) / float(pieces), u1 = float(k + 1) / float(pieces);
      const glm::vec4 a = bspline_point(cp, u0), b = bspline_point(cp, u1);
      for (int j = 0; j <= 16; ++j) {
        const float t = float(j) / 16;
        const glm::vec4 on_curve = bspline_point(cp, u0 + t * (u1 - u0)), d = on_curve - (a + t * (b - a));
        worst = std::max(worst, glm::length(glm::vec3(d)) + std::fabs(d.w));
        radius = std::min(radius, std::max(on_curve.w, 0.0f));
      }
    }
    if (worst <= kPolylineTolerance * radius || pieces >= 64) return pieces;
  }
}

}  // namespace

// One chain of vertices per curve, so that each piece's neighbours are the vertices
// before and after it (RTCCurveFlags) and the joints are smooth.
void Scene::append_polyline(CurveGeometry& g, const glm::vec4* cps, std::size_t segments, std::uint32_t curve,
                            std::uint32_t fibre) {
  const std::size_t first_piece = g.indices.size();
  g.vertices.push_back(bspline_point(cps, 0.0f));
  for (std::size_t s = 0; s < segments; ++s) {
    const glm::vec4* cp = cps + s;
    const int pieces = polyline_pieces(cp);
    for (int k = 1; k <= pieces; ++k) {
      const auto start = std::uint32_t(g.vertices.size() - 1);
      g.vertices.push_back(bspline_point(cp, float(k) / float(pieces)));
      g.indices.push_back(start);
      g.prims.push_back({curve, start, fibre});
    }
  }
  for (std::size_t k = first_piece; k < g.indices.size(); ++k)
    g.flags.push_back(std::uint8_t((k > first_piece ? RTC_CURVE_FLAG_NEIGHBOR_LEFT : 0) |
                                   (k + 1 < g.indices.size() ? RTC_CURVE_FLAG_NEIGHBOR_RIGHT : 0)));
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
  g_explicit_bytes += std::int64_t(explicit_bytes_);
  if (options_.explicit_polylines) {
    barbs_.linear = true;
    for (std::uint32_t fi = 0; fi < ex.fibres.size(); ++fi) {
      const ExplicitFibre& f = ex.fibres[fi];
      append_polyline(barbs_, &ex.control_points[f.first_cp], f.segments(), f.barb, fi);
    }
    explicit_fibres_ = std::move(ex.fibres);
    g_explicit_segments += std::int64_t(barbs_.indices.size());
    commit_curves(barbs_, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    return;
  }
  barbs_.vertices = std::move(ex.control_points);
  for (std::uint32_t fi = 0; fi < ex.fibres.size(); ++fi) {
    const ExplicitFibre& f = ex.fibres[fi];
    for (std::uint32_t s = 0; s < f.segments(); ++s) {
      barbs_.indices.push_back(f.first_cp + s);
      barbs_.prims.push_back({f.barb, f.first_cp + s, fi});
    }
  }
  explicit_fibres_ = std::move(ex.fibres);
  g_explicit_segments += std::int64_t(barbs_.indices.size());
  commit_curves(barbs_, RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE);
}

const ExplicitFibre& Scene::explicit_fibre(const SurfaceHit& hit) const {
  return explicit_fibres_[barbs_.prims[hit.prim].fibre];
}

}  // namespace plumage
