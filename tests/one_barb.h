#pragma once
// Substructure parameters and a one-barb feather for the substructure and explicit
// mode tests: a straight barb along +X, its vane normal +Z, and rays straight down.
#include "plumage/common/feather.h"
#include "plumage/renderer/ray.h"

namespace plumage::test {

inline SubstructureParams substructure_params(int n, double theta_deg, double r_r, double r_b, double width,
                                              double phi_deg, double hooked) {
  SubstructureParams p;
  p.barbules_per_side = n;
  p.elevation_deg = float(theta_deg);
  p.azimuth_deg = float(phi_deg);
  p.ramus_radius = float(r_r);
  p.barbule_radius = float(r_b);
  p.ribbon_width = float(width);
  p.hooked_fraction = float(hooked);
  return p;
}

// Control points at x = -4 ... 4 (8 of them), so the curve runs from
// x = -4 + 8/7 to 4 - 8/7 and its arc length is x + 4 - 8/7.
inline Feather one_barb(const SubstructureParams& p, VaneSide side = VaneSide::Right) {
  Feather f;
  Curve c;
  c.kind = CurveKind::Barb;
  c.side = side;
  for (int i = 0; i < 8; ++i) c.points.push_back({{-4.0f + 8.0f * float(i) / 7.0f, 0, 0}, 0.05f, {0, 0, 1}});
  f.curves.push_back(c);
  f.left = f.right = p;
  return f;
}

inline Ray down_at(double x, double y) {
  Ray r;
  r.o = {float(x), float(y), 10};
  r.d = {0, 0, -1};
  return r;
}

}  // namespace plumage::test
