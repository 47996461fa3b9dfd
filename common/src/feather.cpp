#include "plumage/common/feather.h"

#include <algorithm>

#include <cmath>

#include "float_text.h"

namespace plumage {

namespace {
std::string number_text(float v) {
  std::string s;
  detail::append_float(s, v);
  return s;
}
}  // namespace

std::optional<SubstructureProblem> substructure_problem(const SubstructureParams& p) {
  auto outside = [](const char* setting, float v, const std::string& range) {
    return SubstructureProblem{setting, "value " + number_text(v) + " is outside " + range};
  };
  auto in = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  if (!(p.barbules_per_side >= 0 && p.barbules_per_side <= 100000))
    return outside("barbules", float(p.barbules_per_side), "[0, 100000] barbules per side");
  if (!in(p.ramus_radius, 0.0, 5.0)) return outside("ramus_radius", p.ramus_radius, "[0, 5] mm");
  if (!in(p.barbule_radius, 0.0, 1.0)) return outside("barbule_radius", p.barbule_radius, "[0, 1] mm");
  if (!in(p.elevation_deg, kMinBarbuleElevationDeg, 90.0))
    return outside("elevation", p.elevation_deg,
                   "[1, 90] degrees: below 1 degree a barbule lies along the ramus");
  if (!(std::isfinite(p.azimuth_deg) && std::fabs(p.azimuth_deg) < 90.0))
    return outside("azimuth", p.azimuth_deg, "(-90, 90) degrees: at 90 a barbule stands on the vane edge-on");
  if (!in(p.hooked_fraction, 0.0, 1.0)) return outside("hooked_fraction", p.hooked_fraction, "[0, 1]");
  if (!in(p.ribbon_width, 0.0, 10.0)) return outside("ribbon_width", p.ribbon_width, "[0, 10] mm");
  if (p.ribbon_width > 0 && p.ramus_radius > 0.5f * p.ribbon_width)
    return SubstructureProblem{"ramus_radius", "value " + number_text(p.ramus_radius) +
                                                   " exceeds half the ribbon_width (" +
                                                   number_text(0.5f * p.ribbon_width) +
                                                   "); the ramus must fit inside the ribbon"};
  return std::nullopt;
}

const char* to_string(CurveKind k) {
  switch (k) {
    case CurveKind::Shaft: return "shaft";
    case CurveKind::Down: return "down";
    default: return "barb";
  }
}

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

std::vector<float> render_radii(const Feather& f, const Curve& c) {
  std::vector<float> r(c.points.size());
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = c.points[i].radius;
  const float w = c.kind == CurveKind::Barb ? f.substructure(c.side).ribbon_width : 0.0f;
  if (!(w > 0)) return r;
  // Arc length of the control polygon up to each point.
  std::vector<float> s(r.size(), 0.0f);
  for (std::size_t i = 1; i < r.size(); ++i) s[i] = s[i - 1] + glm::length(c.points[i].p - c.points[i - 1].p);
  const float total = s.empty() ? 0.0f : s.back(), taper = kBarbTipTaper * total;
  if (c.points.size() <= 4 || !(std::isfinite(taper) && taper > 0)) {  // no room, or no length to taper over
    std::fill(r.begin(), r.end(), 0.5f * w);
    return r;
  }
  for (std::size_t i = 0; i < r.size(); ++i) {
    const float to_tip = total - s[i];
    const float t = std::clamp(to_tip / taper, 0.0f, 1.0f);
    const float k = t * t * (3.0f - 2.0f * t);  // smoothstep: 0 at the tip, 1 from kBarbTipTaper on
    const float own = std::min(c.points[i].radius, 0.5f * w);
    r[i] = t >= 1.0f ? 0.5f * w : std::min(own + k * (0.5f * w - own), 0.5f * w);
  }
  return r;
}

glm::vec3 shaft_colour_at(const std::vector<glm::vec3>& shaft, float fraction) {
  const float n = float(shaft.size());
  const float x = std::clamp(fraction, 0.0f, 1.0f) * n - 0.5f;  // in station indices
  if (!(x > 0.0f)) return shaft.front();
  const std::size_t k = std::min(std::size_t(x), shaft.size() - 1);
  if (k + 1 >= shaft.size()) return shaft.back();
  return glm::mix(shaft[k], shaft[k + 1], x - float(k));
}

}  // namespace plumage
