#include "plumage/common/feather.h"

namespace plumage {

const char* to_string(CurveKind k) { return k == CurveKind::Shaft ? "shaft" : "barb"; }

const char* to_string(VaneSide s) {
  switch (s) {
    case VaneSide::Left: return "left";
    case VaneSide::Right: return "right";
    default: return "none";
  }
}

const Curve* Feather::shaft() const {
  for (const Curve& c : curves)
    if (c.kind == CurveKind::Shaft) return &c;
  return nullptr;
}

std::size_t Feather::count(CurveKind k) const {
  std::size_t n = 0;
  for (const Curve& c : curves) n += c.kind == k;
  return n;
}

std::size_t Feather::count(VaneSide s) const {
  std::size_t n = 0;
  for (const Curve& c : curves) n += c.side == s;
  return n;
}

std::size_t Feather::num_control_points() const {
  std::size_t n = 0;
  for (const Curve& c : curves) n += c.points.size();
  return n;
}

float render_radius(const Feather& f, const Curve& c, const ControlPoint& cp) {
  if (c.kind != CurveKind::Barb) return cp.radius;
  const float w = f.substructure(c.side).ribbon_width;
  return w > 0 ? 0.5f * w : cp.radius;
}

}  // namespace plumage
