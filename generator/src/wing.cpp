// A wing of placed feathers (wing.h; docs/wing.md says where the numbers come from).
#include "plumage/generator/wing.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/generator/presets.h"

namespace plumage {
namespace {

double lerp(double a, double b, double t) { return a + t * (b - a); }
int lerp_count(int a, int b, double t) { return int(std::lround(lerp(double(a), double(b), t))); }

Profile blend(const Profile& a, const Profile& b, double t) {
  if (t <= 0) return a;
  if (t >= 1) return b;
  std::vector<double> xs;
  for (const auto& k : a.knots()) xs.push_back(k.x);
  for (const auto& k : b.knots()) xs.push_back(k.x);
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end(), [](double u, double v) { return std::fabs(u - v) < 1e-9; }), xs.end());
  std::vector<glm::dvec2> knots;
  for (double x : xs) knots.push_back({x, lerp(a(x), b(x), t)});
  return Profile(std::move(knots));
}

SubstructureParams blend(const SubstructureParams& a, const SubstructureParams& b, double t) {
  SubstructureParams s = a;
  s.barbules_per_side = lerp_count(a.barbules_per_side, b.barbules_per_side, t);
  s.ramus_radius = float(lerp(a.ramus_radius, b.ramus_radius, t));
  s.barbule_radius = float(lerp(a.barbule_radius, b.barbule_radius, t));
  s.elevation_deg = float(lerp(a.elevation_deg, b.elevation_deg, t));
  s.azimuth_deg = float(lerp(a.azimuth_deg, b.azimuth_deg, t));
  s.hooked_fraction = float(lerp(a.hooked_fraction, b.hooked_fraction, t));
  s.ribbon_width = float(lerp(a.ribbon_width, b.ribbon_width, t));
  return s;
}

VaneParams blend(const VaneParams& a, const VaneParams& b, double t) {
  VaneParams v = a;
  v.barbs = lerp_count(a.barbs, b.barbs, t);
  v.barb_density = lerp(a.barb_density, b.barb_density, t);
  v.width = blend(a.width, b.width, t);
  v.angle_deg = blend(a.angle_deg, b.angle_deg, t);
  v.barb_bend_deg = lerp(a.barb_bend_deg, b.barb_bend_deg, t);
  v.substructure = blend(a.substructure, b.substructure, t);
  return v;
}

// A profile with every value times k.
Profile scaled(const Profile& p, double k) {
  std::vector<glm::dvec2> knots = p.knots();
  for (auto& kn : knots) kn.y *= k;
  return Profile(std::move(knots));
}

// A key feather made from a preset: its shaft `length` mm (calamus in proportion),
// each vane's width scaled (outer = left, inner = right), barb angles scaled, barbs
// per side in proportion to the vane length (the preset's barb density kept).
FeatherParams key(const std::string& preset, double length, double outer_width, double inner_width, double angle,
                  const glm::vec3& albedo) {
  FeatherParams p = load_preset(preset);
  const double k = length / p.shaft.length;
  p.shaft.length = length;
  p.shaft.calamus_length *= k;
  p.shaft.radius_base *= std::sqrt(k);
  for (VaneSide s : {VaneSide::Left, VaneSide::Right}) {
    VaneParams& v = p.vane(s);
    v.width = scaled(v.width, k * (s == VaneSide::Left ? outer_width : inner_width));
    v.angle_deg = scaled(v.angle_deg, angle);
    v.barbs = std::max(8, int(std::lround(v.barbs * k)));
  }
  p.albedo = albedo;
  return p;
}

// Rock dove (Columba livia). Bones and feather lengths: docs/wing.md.
struct WingModel {
  double humerus, ulna, hand;            // mm
  double spread_deg[3], folded_deg[3];   // humerus, forearm, hand direction from +X (CCW, +Y toward the head)
  int primaries, secondaries;
  FeatherParams p_inner, p_outer, s_outer, s_inner, gc_outer, gc_inner, mc_outer, mc_inner;
  double body_half_width;
  std::string description;
};

WingModel rock_dove() {
  WingModel m;
  m.humerus = 40, m.ulna = 55, m.hand = 45;
  m.spread_deg[0] = 10, m.spread_deg[1] = 0, m.spread_deg[2] = -15;
  m.folded_deg[0] = -70, m.folded_deg[1] = 110, m.folded_deg[2] = -100;
  m.primaries = 10, m.secondaries = 11;
  const glm::vec3 dark(0.10f, 0.10f, 0.11f), slate(0.16f, 0.17f, 0.19f), pale(0.30f, 0.31f, 0.34f);
  // Remiges from the rock-dove secondary (the paper's specimen); coverts from the
  // osprey covert preset's shape, shortened to a dove's.
  m.p_inner = key("rock-dove-wing", 128, 0.8, 0.95, 1.0, dark);
  m.p_outer = key("rock-dove-wing", 150, 0.45, 0.8, 0.8, dark);
  m.s_outer = key("rock-dove-wing", 118, 1.0, 1.0, 1.0, slate);
  m.s_inner = key("rock-dove-wing", 100, 1.3, 1.05, 1.05, slate);
  m.gc_outer = key("osprey-wing-covert", 55, 0.55, 0.6, 1.0, slate);
  m.gc_inner = key("osprey-wing-covert", 62, 0.65, 0.7, 1.0, pale);
  m.mc_outer = key("osprey-wing-covert", 34, 0.6, 0.6, 1.0, pale);
  m.mc_inner = key("osprey-wing-covert", 38, 0.7, 0.7, 1.0, pale);
  m.body_half_width = 15;
  m.description = "Rock dove (Columba livia) right wing: 10 primaries, 11 secondaries, greater coverts over every "
                  "remex, median coverts over the secondaries (docs/wing.md)";
  return m;
}

glm::vec2 dir(double deg) { return {float(std::cos(deg * kPi / 180)), float(std::sin(deg * kPi / 180))}; }

// The placement of a feather whose base is at (x, y, z) and whose shaft (+Y in its
// own frame) points along `deg` from +X.
glm::mat4 placed(const glm::vec2& base, float z, double deg) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(base, z));
  return glm::rotate(m, float((deg - 90) * kPi / 180), glm::vec3(0, 0, 1));
}

}  // namespace

FeatherParams blend_params(const FeatherParams& a, const FeatherParams& b, double t) {
  FeatherParams p = t < 0.5 ? a : b;
  p.shaft.length = lerp(a.shaft.length, b.shaft.length, t);
  p.shaft.calamus_length = lerp(a.shaft.calamus_length, b.shaft.calamus_length, t);
  p.shaft.bend_deg = lerp(a.shaft.bend_deg, b.shaft.bend_deg, t);
  p.shaft.arch_deg = lerp(a.shaft.arch_deg, b.shaft.arch_deg, t);
  p.shaft.radius_base = lerp(a.shaft.radius_base, b.shaft.radius_base, t);
  p.shaft.radius_tip = lerp(a.shaft.radius_tip, b.shaft.radius_tip, t);
  p.shaft.control_points = lerp_count(a.shaft.control_points, b.shaft.control_points, t);
  p.left = blend(a.left, b.left, t);
  p.right = blend(a.right, b.right, t);
  p.barb.radius_root = lerp(a.barb.radius_root, b.barb.radius_root, t);
  p.barb.radius_tip = lerp(a.barb.radius_tip, b.barb.radius_tip, t);
  p.barb.control_points = lerp_count(a.barb.control_points, b.barb.control_points, t);
  p.surface.cupping = lerp(a.surface.cupping, b.surface.cupping, t);
  p.surface.twist_deg = lerp(a.surface.twist_deg, b.surface.twist_deg, t);
  p.surface.cage_columns = lerp_count(a.surface.cage_columns, b.surface.cage_columns, t);
  p.surface.cage_rows = lerp_count(a.surface.cage_rows, b.surface.cage_rows, t);
  p.afterfeather.fraction = lerp(a.afterfeather.fraction, b.afterfeather.fraction, t);
  p.afterfeather.radius = lerp(a.afterfeather.radius, b.afterfeather.radius, t);
  p.afterfeather.cover = lerp(a.afterfeather.cover, b.afterfeather.cover, t);
  p.afterfeather.wave = lerp(a.afterfeather.wave, b.afterfeather.wave, t);
  p.afterfeather.lift = lerp(a.afterfeather.lift, b.afterfeather.lift, t);
  p.afterfeather.waves = lerp(a.afterfeather.waves, b.afterfeather.waves, t);
  p.splits.count = lerp_count(a.splits.count, b.splits.count, t);
  p.splits.gap = lerp(a.splits.gap, b.splits.gap, t);
  p.splits.depth = lerp(a.splits.depth, b.splits.depth, t);
  p.jitter.angle_deg = lerp(a.jitter.angle_deg, b.jitter.angle_deg, t);
  p.jitter.spacing = lerp(a.jitter.spacing, b.jitter.spacing, t);
  p.albedo = glm::mix(a.albedo, b.albedo, float(t));
  return p;
}

const char* to_string(WingRow row) {
  switch (row) {
    case WingRow::Primary: return "primary";
    case WingRow::Secondary: return "secondary";
    case WingRow::GreaterCovert: return "greater covert";
    case WingRow::MedianCovert: return "median covert";
  }
  return "?";
}

std::vector<std::string> wing_presets() { return {"rock-dove"}; }

namespace {
// The preset's keys replaced by analysed feathers' (WingOptions::keys).
void take_keys(WingModel& m, std::vector<FeatherParams> keys) {
  std::sort(keys.begin(), keys.end(),
            [](const FeatherParams& a, const FeatherParams& b) { return a.shaft.length > b.shaft.length; });
  const double longest = keys.front().shaft.length;
  std::size_t remiges = 0;
  while (remiges < keys.size() && keys[remiges].shaft.length >= 0.4 * longest) ++remiges;
  const auto rank = [&](double q) { return keys[std::size_t(std::lround(q * double(remiges - 1)))]; };
  const double k = longest / m.p_outer.shaft.length;  // the analysed wing's size against the preset's
  m.p_outer = rank(0.0);
  m.p_inner = rank(0.25);
  m.s_outer = rank(0.5);
  m.s_inner = rank(1.0);
  m.humerus *= k, m.ulna *= k, m.hand *= k, m.body_half_width *= k;
  const glm::vec3 covert_colour = keys.back().albedo;
  for (FeatherParams* c : {&m.gc_outer, &m.gc_inner, &m.mc_outer, &m.mc_inner}) {
    *c = key("osprey-wing-covert", c->shaft.length * k, 0.6, 0.65, 1.0, covert_colour);
  }
  m.description = "Wing from " + std::to_string(keys.size()) + " analysed feathers (" + std::to_string(remiges) +
                  " long enough for remex keys, " + std::to_string(int(std::lround(longest))) +
                  " mm the longest) on the rock-dove wing's rows and bones scaled to them (docs/wing.md)";
}
}  // namespace

Wing build_wing(const WingOptions& o) {
  if (o.preset != "rock-dove") throw Error("unknown wing preset '" + o.preset + "'; known: rock-dove");
  if (!(o.fold >= 0 && o.fold <= 1)) throw Error("fold must lie in [0, 1] (0 spread, 1 folded)");
  WingModel m = rock_dove();
  if (o.keys.size() >= 2) take_keys(m, o.keys);
  double a[3];
  for (int i = 0; i < 3; ++i) a[i] = lerp(m.spread_deg[i], m.folded_deg[i], o.fold);
  const glm::vec2 shoulder(0), elbow = shoulder + float(m.humerus) * dir(a[0]), wrist = elbow + float(m.ulna) * dir(a[1]),
                  tip = wrist + float(m.hand) * dir(a[2]);
  Wing w;
  w.description = m.description + (o.fold > 0 ? ", folded " + std::to_string(int(std::lround(100 * o.fold))) + " %" : ", spread");
  // Right wing -> left wing: x -> -x about the body's midline at x = -body_half_width.
  w.mirror = glm::translate(glm::mat4(1.0f), glm::vec3(float(-2 * m.body_half_width), 0, 0)) *
             glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1));
  // Each row's feathers in order from the wrist outward (primaries) or inward
  // (secondaries); the dorsal stack rises from the wing tip toward the body, and
  // the coverts lie over the remiges.
  // A remex's direction from +X: spread, it leaves its bone pointing back and
  // fanning out along the hand; folded, every feather lies back along the body
  // (-Y) and the bones carry only the bases (a folded wing's remiges stack over
  // each other, pointing to the tail).
  const auto remex = [&](WingRow row, int i, int n) {
    const bool primary = row == WingRow::Primary;
    const double f = (i - 0.5) / n;  // 0 at the wrist
    const glm::vec2 base = primary ? wrist + float(0.95 * f) * (tip - wrist) : wrist + float(f) * (elbow - wrist);
    const double spread = primary ? m.spread_deg[2] + lerp(-80, -15, f) : m.spread_deg[1] + lerp(-80, -95, f);
    const double folded = primary ? lerp(-96, -88, f) : lerp(-96, -104, f);
    const double t = primary ? 1 - f : f;  // 0 at the outer key, 1 at the inner
    return std::tuple{base, lerp(spread, folded, o.fold), t};
  };
  const float stack = 0.6f;  // mm between neighbours in the dorsal stack
  const float reach = float(m.hand / 45.0);  // the coverts' offsets grow with the wing
  for (int i = 1; i <= m.primaries; ++i) {
    const auto [base, deg, t] = remex(WingRow::Primary, i, m.primaries);
    const float z = stack * float(m.primaries - i);
    w.feathers.push_back({WingRow::Primary, i, "P" + std::to_string(i), blend_params(m.p_outer, m.p_inner, t), placed(base, z, deg)});
    const glm::vec2 cov = base + 5.0f * reach * dir(deg + 180);  // up the feather, over its base
    w.feathers.push_back({WingRow::GreaterCovert, i, "PC" + std::to_string(i), blend_params(m.gc_outer, m.gc_inner, 0.5 * t),
                          placed(cov, z + 6.0f, deg)});
  }
  for (int i = 1; i <= m.secondaries; ++i) {
    const auto [base, deg, t] = remex(WingRow::Secondary, i, m.secondaries);
    const float z = stack * float(m.primaries + i);
    w.feathers.push_back({WingRow::Secondary, i, "S" + std::to_string(i), blend_params(m.s_outer, m.s_inner, t), placed(base, z, deg)});
    const glm::vec2 gc = base + 5.0f * reach * dir(deg + 180), mc = base + 11.0f * reach * dir(deg + 180);
    w.feathers.push_back({WingRow::GreaterCovert, i, "GC" + std::to_string(i), blend_params(m.gc_outer, m.gc_inner, 0.5 + 0.5 * t),
                          placed(gc, z + 6.0f, deg)});
    w.feathers.push_back({WingRow::MedianCovert, i, "MC" + std::to_string(i), blend_params(m.mc_outer, m.mc_inner, t),
                          placed(mc, z + 9.0f, deg + 5)});
  }
  for (WingFeather& f : w.feathers) {
    f.params.name = (o.keys.size() >= 2 ? "analysed-" : "rock-dove-") + f.name;
    validate(f.params, "wing feather " + f.name);
  }
  return w;
}

FeatherScene wing_scene(const Wing& wing, const WingOptions& options, const std::string& folder_in_scene) {
  FeatherScene s;
  for (const WingFeather& f : wing.feathers) {
    SceneFeather sf;
    sf.name = f.name;
    sf.source = SceneFeatherSource::Fcurves;
    sf.path = folder_in_scene + "/" + f.name + ".fcurves";
    s.feathers.push_back(sf);
  }
  for (std::size_t i = 0; i < wing.feathers.size(); ++i) s.placements.push_back({i, wing.feathers[i].to_world, 0});
  if (options.pair)
    for (std::size_t i = 0; i < wing.feathers.size(); ++i)
      s.placements.push_back({i, wing.mirror * wing.feathers[i].to_world, 0});
  // A scene wider than the dome is high has the zenith LED in view: leave it off.
  s.lights = "2-25";
  return s;
}

}  // namespace plumage
