#include "plumage/renderer/explicit_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <glm/gtc/quaternion.hpp>

#include "plumage/common/bspline.h"
#include "plumage/common/constants.h"
#include "plumage/common/frame.h"
#include "plumage/common/error.h"

namespace plumage {
namespace {


// Lateral room for a barbule: from the ramus edge to the ribbon's edge.
double barbule_reach(const SubstructureParams& p) { return 0.5 * double(p.ribbon_width) - double(p.ramus_radius); }

bool has_barbules(const SubstructureParams& p) {
  return p.barbules_per_side > 0 && p.barbule_radius > 0 && barbule_reach(p) > 0;
}

// A uniform cubic B-spline that starts at points.front(), ends at points.back()
// and follows the polyline in between: the points are the control points, with a
// mirrored phantom at each end (so a straight run of evenly spaced points is
// reproduced exactly, and the curve is tangent to the first and last leg).
void add_fibre(Structure structure, std::uint32_t barb, const std::vector<glm::dvec3>& points, float radius,
               ExplicitBarbs& out) {
  ExplicitFibre f;
  f.structure = structure;
  f.barb = barb;
  f.first_cp = std::uint32_t(out.control_points.size());
  auto push = [&](const glm::dvec3& p) { out.control_points.emplace_back(glm::vec3(p), radius); };
  push(2.0 * points[0] - points[1]);
  for (const glm::dvec3& p : points) push(p);
  push(2.0 * points.back() - points[points.size() - 2]);
  f.num_cp = std::uint32_t(points.size() + 2);
  out.fibres.push_back(f);
}

// The hook of a distal barbule of unit length: the points after the straight part,
// relative to where the hook starts, its tangent t_b turning about n by sigma q pi/2
// as q runs 0 -> 1 along it (BarbSubstructure::frame's hook rotation).
std::array<glm::dvec3, kHookSegments> unit_hook(const glm::dvec3& tb, const glm::dvec3& n, double sigma) {
  constexpr int kSubsteps = 16;
  std::array<glm::dvec3, kHookSegments> pts{};
  glm::dvec3 p(0);
  for (int j = 0; j < kHookSegments; ++j) {
    for (int i = 0; i < kSubsteps; ++i) {
      const double q = (j + (i + 0.5) / kSubsteps) / kHookSegments;
      p += glm::angleAxis(sigma * q * std::numbers::pi / 2, n) * tb / double(kHookSegments * kSubsteps);
    }
    pts[std::size_t(j)] = p;
  }
  return pts;
}

}  // namespace

std::size_t ExplicitBarbs::segments() const {
  std::size_t n = 0;
  for (const ExplicitFibre& f : fibres) n += f.segments();
  return n;
}

std::size_t ExplicitBarbs::bytes() const {
  return control_points.size() * sizeof(glm::vec4) + segments() * sizeof(std::uint32_t);
}

double add_explicit_barb(const Curve& barb, std::uint32_t barb_index, const BarbSubstructure& vane,
                         ExplicitBarbs& out) {
  const SubstructureParams& p = vane.params();
  std::vector<glm::dvec3> centre, normals;
  for (const ControlPoint& cp : barb.points) {
    centre.emplace_back(cp.p);
    normals.emplace_back(safe_normalize(cp.n));
  }
  // The ramus: the barb's own curve at radius r_r.
  {
    ExplicitFibre f;
    f.barb = barb_index;
    f.first_cp = std::uint32_t(out.control_points.size());
    for (const glm::dvec3& c : centre) out.control_points.emplace_back(glm::vec3(c), p.ramus_radius);
    f.num_cp = std::uint32_t(centre.size());
    out.fibres.push_back(f);
  }
  const BSpline3 spline(centre);
  const ArcLengthTable table(spline);
  const double length = table.length();
  if (!has_barbules(p) || !(length > 0)) return length;
  const BSpline3 normal(normals);

  const double reach = barbule_reach(p);
  const double sin_theta = std::sin(double(p.elevation_deg) * kDegToRad);
  const int n = p.barbules_per_side;
  for (int k = 0; k < n; ++k) {
    const double t = table.t_at((k + 0.5) * length / n);
    const glm::dvec3 c = spline.eval(t);
    const Frame bf = frame_from_tangent_normal(glm::vec3(spline.deriv(t)), glm::vec3(normal.eval(t)));
    for (const double sigma : {1.0, -1.0}) {
      const bool distal = sigma * vane.distal_sign() > 0;
      StructureHit start;
      start.structure = distal ? Structure::Distal : Structure::Proximal;
      const glm::dvec3 tb(vane.frame(bf, start, sigma).t);  // unit; its component along b is sigma sin(theta_b)
      const double hooked = distal ? double(p.hooked_fraction) : 0.0;
      // The barbule's line crosses the ramus edge at s_k. It starts `inside` earlier,
      // hidden in the ramus, so that its round start cap does not clip the corner
      // of G_b's strip at the ramus edge (r_b cot theta_b covers it; never past the
      // barb's centreline).
      const glm::dvec3 edge = c + sigma * double(p.ramus_radius) * glm::dvec3(bf.b);
      const double inside = std::min(double(p.barbule_radius) / std::tan(double(p.elevation_deg) * kDegToRad),
                                     double(p.ramus_radius) / sin_theta);
      std::vector<glm::dvec3> pts{edge - inside * tb};
      const glm::dvec3 hook_start = edge + (1.0 - hooked) * reach / sin_theta * tb;
      if (glm::length(hook_start - pts[0]) > 1e-6 * reach || hooked <= 0) pts.push_back(hook_start);
      if (hooked > 0) {
        // Scale the unit hook so it covers the last `hooked` part of the lateral reach.
        const auto hook = unit_hook(tb, glm::dvec3(bf.n), sigma);
        const double lateral = sigma * glm::dot(hook.back(), glm::dvec3(bf.b));  // > 0 for theta_b in [1, 90]
        const double scale = hooked * reach / lateral;
        const glm::dvec3 from = pts.back();
        for (const glm::dvec3& h : hook) pts.push_back(from + scale * h);
      }
      add_fibre(start.structure, barb_index, pts, p.barbule_radius, out);
    }
  }
  return length;
}

std::size_t explicit_curve_count(const Feather& feather) {
  std::size_t n = 0;
  for (const Curve& c : feather.curves) {
    if (c.kind != CurveKind::Barb) continue;
    const SubstructureParams& p = feather.substructure(c.side);
    n += 1 + (has_barbules(p) ? 2 * std::size_t(p.barbules_per_side) : 0);
  }
  return n;
}

void check_explicit_fits(const Feather& feather) {
  const std::size_t curves = explicit_curve_count(feather);
  if (curves <= kMaxExplicitBytes / kExplicitBytesPerCurve) return;
  const double gib = double(curves) * double(kExplicitBytesPerCurve) / double(std::size_t(1) << 30);
  throw Error("explicit mode would build " + std::to_string(curves) + " curves (barbules per side " +
              std::to_string(feather.left.barbules_per_side) + " left, " +
              std::to_string(feather.right.barbules_per_side) + " right), about " + std::to_string(std::lround(gib)) +
              " GiB, above its " + std::to_string(kMaxExplicitBytes >> 30) +
              " GiB ceiling; lower the barbule count (--barbules)");
}

}  // namespace plumage
