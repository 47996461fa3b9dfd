#include "plumage/generator/layout_to_params.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "plumage/common/atomic_file.h"
#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/common/median.h"
#include "plumage/common/number_text.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/shaft_pose.h"

namespace plumage {
namespace {

struct Checker {
  std::string source;
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw Error(Location{source}, where + ": " + what + " (see docs/layout-format.md; re-run `plumage analyze`)");
  }
  void finite(const std::string& where, const std::vector<double>& v) const {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i])) fail(where + "[" + std::to_string(i) + "]", "value is not a finite number");
  }
  void profile(const std::string& where, const std::vector<double>& v, const std::vector<double>& c,
               std::size_t n) const {
    if (v.size() != n || c.size() != n)
      fail(where, "expected " + std::to_string(n) + " values and confidences (one per station), got " +
                      std::to_string(v.size()) + " and " + std::to_string(c.size()));
    finite(where, v);
    finite(where + "_confidence", c);
  }
};

void check_layout(const FeatherLayout& f, const Checker& c) {
  const std::string at = "feather " + std::to_string(f.id);
  if (!std::isfinite(f.length_mm) || f.length_mm < kMinShaftLengthMm || f.length_mm > kMaxShaftLengthMm)
    c.fail(at + " shaft.length_mm", "value " + num(f.length_mm) + " is out of range; allowed [" +
                                        num(kMinShaftLengthMm) + ", " + num(kMaxShaftLengthMm) + "] mm");
  if (!f.shaft_mm.valid()) c.fail(at + " shaft.control_points_mm", "needs at least 4 control points");
  for (const auto& p : f.shaft_mm.control_points())
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) c.fail(at + " shaft.control_points_mm", "not a finite number");
  const auto& t = f.stations_t;
  if (t.size() < 2) c.fail(at + " stations_t", "needs at least 2 stations, got " + std::to_string(t.size()));
  c.finite(at + " stations_t", t);
  for (const auto& [name, v] : {std::pair{"left", &f.left}, std::pair{"right", &f.right}})
    if (!(v->afterfeather_to_t >= 0.0 && v->afterfeather_to_t <= 1.0))
      c.fail(at + " vanes." + name + ".afterfeather_to_t",
             "value " + num(v->afterfeather_to_t) + " is out of range; allowed [0, 1]");
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < 0.0 || t[i] > 1.0) c.fail(at + " stations_t[" + std::to_string(i) + "]", "must lie in [0, 1]");
    if (i > 0 && !(t[i] > t[i - 1]))
      c.fail(at + " stations_t[" + std::to_string(i) + "]", "stations must increase strictly");
  }
  for (const auto& [name, v] : {std::pair<const char*, const VaneProfile*>{"left", &f.left}, {"right", &f.right}}) {
    const std::string p = at + " vanes." + name + ".";
    c.profile(p + "width_mm", v->width_mm, v->width_confidence, t.size());
    c.profile(p + "barb_angle_deg", v->barb_angle_deg, v->barb_angle_confidence, t.size());
    c.profile(p + "barb_spacing_mm", v->barb_spacing_mm, v->barb_spacing_confidence, t.size());
  }
}

// (station t, value) pairs analysis was sure of.
std::vector<glm::dvec2> trusted(const std::vector<double>& t, const std::vector<double>& v,
                                const std::vector<double>& conf) {
  std::vector<glm::dvec2> out;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (conf[i] >= kLayoutMinConfidence) out.push_back({t[i], v[i]});
  return out;
}

// A side's widths: the stations analysis was sure of, and the stations below the
// first of them at their measured width. Width confidence is the
// share of a station's rows where that side reaches past the rachis, so a run of
// unsure stations from the base is a side that is absent there (its vane begins
// later than the other's, as on many body feathers), not a side of unknown width;
// held at the first sure width instead, such a side's vane would run down the bare
// quill (docs/cli.md, "From a photo").
std::vector<glm::dvec2> vane_widths(const std::vector<double>& t, const VaneProfile& v) {
  std::vector<glm::dvec2> out = trusted(t, v.width_mm, v.width_confidence);
  if (out.empty()) return out;
  std::vector<glm::dvec2> base;
  // (A station hidden under a shingled row's neighbour shows only part of its
  // width: the sure stations on either side of it decide there.)
  for (std::size_t i = 0; i < t.size() && t[i] < out.front().x; ++i)
    if (i >= v.width_hidden.size() || v.width_hidden[i] == 0) base.push_back({t[i], v.width_mm[i]});
  out.insert(out.begin(), base.begin(), base.end());
  return out;
}

// Linear interpolation through (t, value) pairs, held constant past the ends.
double interpolate(const std::vector<glm::dvec2>& pts, double t) {
  if (t <= pts.front().x) return pts.front().y;
  if (t >= pts.back().x) return pts.back().y;
  const auto hi = std::upper_bound(pts.begin(), pts.end(), t, [](double a, const glm::dvec2& p) { return a < p.x; });
  const auto lo = hi - 1;
  return glm::mix(lo->y, hi->y, (t - lo->x) / (hi->x - lo->x));
}

// A generator Profile over vane position x = (s - calamus) / (L - calamus) from
// measurements over shaft fraction t = s / L: knots at the stations inside the
// vane, plus both ends read off the measurements.
Profile vane_profile(const std::vector<glm::dvec2>& pts, double calamus_t, double lo, double hi) {
  std::vector<glm::dvec2> knots{{0.0, std::clamp(interpolate(pts, calamus_t), lo, hi)}};
  for (const auto& p : pts) {
    const double x = (p.x - calamus_t) / (1.0 - calamus_t);
    if (x > knots.back().x + 1e-4 && x < 1.0 - 1e-4) knots.push_back({x, std::clamp(p.y, lo, hi)});
  }
  knots.push_back({1.0, std::clamp(interpolate(pts, 1.0), lo, hi)});
  return Profile(std::move(knots));
}

// The vane closes at the tip: the last station still has width, the tip none.
Profile width_profile(const std::vector<glm::dvec2>& pts, double calamus_t, double hi) {
  Profile p = vane_profile(pts, calamus_t, 0.0, hi);
  std::vector<glm::dvec2> k = p.knots();
  k.back().y = 0.0;
  return Profile(std::move(k));
}

// Where the vane begins: the first station where either side reaches a tenth of
// the widest width; the bare calamus is below it.
double calamus_fraction(const FeatherLayout& f) {
  double widest = 0;
  for (std::size_t i = 0; i < f.stations_t.size(); ++i)
    widest = std::max({widest, f.left.width_mm[i], f.right.width_mm[i]});
  for (std::size_t i = 0; i < f.stations_t.size(); ++i)
    if (std::max(f.left.width_mm[i], f.right.width_mm[i]) >= 0.1 * widest)
      return i == 0 ? 0.0 : std::clamp(0.5 * (f.stations_t[i - 1] + f.stations_t[i]), 0.0, 0.5);
  return 0.0;
}

// What the generator can build without barbs crossing (docs/analysis.md, "From a
// layout to a feather that can exist"): a profile resampled onto the vane
// surface's cage columns and smoothed there, since the Catmull-Clark surface
// cannot follow a width that changes faster than its cage does, and a barb that
// ends on a surface edge which does not follow the profile ends off the outline.
Profile smoothed(const Profile& p, int columns, int passes) {
  std::vector<glm::dvec2> k;
  for (int i = 0; i < columns; ++i) {
    const double x = double(i) / (columns - 1);
    k.push_back({x, p(x)});
  }
  for (int it = 0; it < passes; ++it) {
    std::vector<glm::dvec2> s = k;
    for (int i = 1; i + 1 < columns; ++i) s[i].y = 0.25 * k[i - 1].y + 0.5 * k[i].y + 0.25 * k[i + 1].y;
    k = s;
  }
  return Profile(std::move(k));
}

// Repairs params built from a layout so the generator's barbs cannot cross: the
// width and angle profiles are smoothed to what the vane's cage can follow, a
// vane is kept narrower than half the shaft's radius of curvature (on the
// inside of a bend a wider one folds over itself), a barb angle does not rise
// along the shaft faster than its neighbours can stay apart, and a barb's own
// bend stays under half its angle. Each repair is named in `warnings`.
void make_buildable(FeatherParams& p, std::vector<std::string>& warnings) {
  const double lv = p.vane_length();
  // The builder bends the shaft along a circular arc and closes the vane at its
  // tip; past 45 degrees the inside of the bend cannot hold a vane wide enough to
  // see without its barbs piling up at the tip.
  constexpr double kMaxBend = 45.0;
  if (std::fabs(p.shaft.bend_deg) > kMaxBend) {
    warnings.push_back("shaft bend: " + num(p.shaft.bend_deg) + " degrees reduced to " + num(kMaxBend) +
                       " (the generator's arc-shaped shaft cannot carry a vane around a tighter bend)");
    p.shaft.bend_deg = std::copysign(kMaxBend, p.shaft.bend_deg);
  }
  const double turn = std::fabs(p.shaft.bend_deg) * kPi / 180.0;
  const double radius = turn > 1e-9 ? p.shaft.length / turn : INFINITY;
  // A finer cage than the presets' follows a measured outline (and a bent shaft)
  // closely enough that barbs end on it within a barb spacing.
  p.surface.cage_columns = std::max(p.surface.cage_columns, 48);
  p.surface.cage_rows = std::max(p.surface.cage_rows, 8);
  // Short chords between a barb's control points: on a wide, bent vane a long
  // chord cuts across its neighbour's.
  p.barb.control_points = std::max(p.barb.control_points, 16);
  const int columns = p.surface.cage_columns;
  for (VaneSide side : {VaneSide::Left, VaneSide::Right}) {
    VaneParams& v = p.vane(side);
    const std::string name = side == VaneSide::Left ? "left" : "right";
    const double before = v.width.max_value();
    Profile w = smoothed(v.width, columns, 2);
    // A straight barb rooted at r with angle theta meets a line at distance d from
    // the shaft at r + d cot(theta): neighbours keep their order out to the widest
    // width W while cot(theta) falls by less than (its change in r) / W; at half
    // that rate barbs stay at least half a spacing apart. A barb angle rising along
    // the shaft faster than that is held back.
    std::vector<glm::dvec2> ak = smoothed(v.angle_deg, columns, 1).knots();
    // A barb turns toward the tip by barb_bend_deg along its length; it ends at
    // theta - bend. Kept to half the smallest root angle, so a barb never ends
    // running along the shaft.
    double least = 90.0;
    for (const auto& q : ak) least = std::min(least, q.y);
    if (v.barb_bend_deg > 0.5 * least) {
      warnings.push_back(name + " barb bend: " + num(v.barb_bend_deg) + " degrees reduced to " + num(0.5 * least) +
                         ", half the smallest barb angle");
      v.barb_bend_deg = 0.5 * least;
    }
    const double bend = v.barb_bend_deg;
    const auto cot_end = [bend](double theta_deg) { return 1.0 / std::tan((theta_deg - bend) * kPi / 180.0); };
    // A barb keeps its angle theta while the vane's edge moves out by w' per unit
    // of shaft length only while w' < tan(theta): beyond that the edge runs away
    // from it, the builder bends it along the shaft and its neighbours pile onto
    // it. Where the vane widens faster than 0.5 tan(theta_end) (at the base of
    // most vanes, where analysis reads angles least well) the barb angle is raised,
    // as real barbs stand steeper there, up to 90 degrees.
    bool raised = false;
    for (std::size_t i = 0; i < ak.size(); ++i) {
      const double x0 = std::max(0.0, ak[i].x - 1.0 / (columns - 1)), x1 = std::min(1.0, ak[i].x + 1.0 / (columns - 1));
      const double slope = (w(x1) - w(x0)) / ((x1 - x0) * lv);
      if (!(slope > 0)) continue;
      const double need = std::min(90.0, std::atan(slope / 0.5) * 180.0 / kPi + bend);
      if (ak[i].y < need - 1e-9) ak[i].y = need, raised = true;
    }
    const double widest = std::max(w.max_value(), 1e-6);
    // A raised angle must not rise faster along the shaft than the rule below
    // allows either: the knots before it are raised with it.
    for (std::size_t i = ak.size() - 1; raised && i-- > 0;) {
      const double ds = (ak[i + 1].x - ak[i].x) * lv;
      const double cot_max = cot_end(ak[i + 1].y) + 0.5 * ds / widest;
      const double floor = std::atan(1.0 / cot_max) * 180.0 / kPi + bend;
      if (ak[i].y < floor) ak[i].y = std::min(floor, 90.0);
    }
    if (raised)
      warnings.push_back(name + " barb angle: raised where the vane widens faster than its barbs can follow");
    bool held = false, fanned = false;
    for (std::size_t i = 1; i < ak.size(); ++i) {
      const double ds = (ak[i].x - ak[i - 1].x) * lv;
      const double cot_min = cot_end(ak[i - 1].y) - 0.5 * ds / widest;
      const double limit = cot_min > 0 ? std::atan(1.0 / cot_min) * 180.0 / kPi + bend : 90.0;
      if (ak[i].y > limit + 1e-9) ak[i].y = std::min(limit, 90.0), held = true;
      // Falling along the shaft, the angle fans neighbours apart: out at W their
      // tips are (change in cot) W further apart than their roots. Held to
      // kMaxFan ds / W, the gap between tips stays within twice the spacing; a
      // fall from barbs raised at a widening base to the measured angles above
      // it is spread over the shaft instead of leaving a wedge of open card.
      const double cot_max = cot_end(ak[i - 1].y) + kMaxFan * ds / widest;
      const double floor = std::atan(1.0 / cot_max) * 180.0 / kPi + bend;
      if (ak[i].y < floor - 1e-9) ak[i].y = std::min(floor, 90.0), fanned = true;
    }
    if (fanned)
      warnings.push_back(name + " barb angle: raised where it fell along the shaft so fast that barbs would fan apart");
    for (auto& q : ak) q.y = std::clamp(q.y, 5.0, 90.0);
    v.angle_deg = Profile(std::move(ak));
    if (held)
      warnings.push_back(name + " barb angle: held back where it rose along the shaft so fast that barbs would cross");
    std::vector<glm::dvec2> k = w.knots();
    const double cap = 0.25 * radius;
    for (auto& q : k) q.y = std::min(q.y, cap);
    k.back().y = 0.0;
    // The vane closes at the tip over at least a sixth of its width: a vane that
    // stops square (a tip the segmentation cut off) makes the subdivision surface
    // bulge past its outline at that corner.
    constexpr double kMaxClosingSlope = 6.0;
    for (std::size_t i = k.size() - 1; i-- > 0;)
      k[i].y = std::min(k[i].y, k[i + 1].y + kMaxClosingSlope * (k[i + 1].x - k[i].x) * lv);
    v.width = Profile(std::move(k));
    if (v.width.max_value() < 0.95 * before)
      warnings.push_back(name + " vane width: narrowed from " + num(before) + " to " + num(v.width.max_value()) +
                         " mm so its barbs cannot cross (smoothing, bend radius " + num(radius) + " mm)");
  }
}
}  // namespace

namespace {
// A barb's control polygon in the vane plane.
std::vector<glm::dvec2> polygon(const Curve& c) {
  std::vector<glm::dvec2> out;
  for (const ControlPoint& p : c.points) out.push_back(glm::dvec2(p.p));
  return out;
}
double distance_to(const glm::dvec2& p, const std::vector<glm::dvec2>& line) {
  double best = 1e300;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const glm::dvec2 a = line[i], d = line[i + 1] - a;
    const double t = std::clamp(glm::dot(p - a, d) / std::max(glm::dot(d, d), 1e-300), 0.0, 1.0);
    best = std::min(best, glm::length(p - (a + t * d)));
  }
  return best;
}
}  // namespace

double barb_gap_mm(const Feather& feather, VaneSide side) {
  std::vector<std::vector<glm::dvec2>> barbs;
  for (const Curve& c : feather.curves)
    if (c.kind == CurveKind::Barb && c.side == side && c.points.size() >= 2) barbs.push_back(polygon(c));
  std::vector<double> gaps;
  for (std::size_t i = 0; i + 1 < barbs.size(); ++i) {
    // Half-way along the barb: its root is at the shaft (no gap), its tip may end before the neighbour's.
    const std::vector<glm::dvec2>& b = barbs[i];
    const glm::dvec2 mid = 0.5 * (b[(b.size() - 1) / 2] + b[b.size() / 2]);
    gaps.push_back(distance_to(mid, barbs[i + 1]));
  }
  if (gaps.empty()) return 0;
  std::sort(gaps.begin(), gaps.end());
  return gaps[std::min(gaps.size() - 1, std::size_t(kBarbGapQuantile * double(gaps.size())))];
}

void close_vane(Feather& feather, VaneSide side) {
  SubstructureParams& s = feather.substructure(side);
  const double gap = barb_gap_mm(feather, side);
  if (gap > 0) {
    s.ribbon_width = float(std::clamp(kBarbOverlap * gap, 4.0 * s.ramus_radius, 10.0));
    s.ramus_radius = std::min(s.ramus_radius, 0.25f * s.ribbon_width);
  }
  double longest = 0;
  for (const Curve& curve : feather.curves) {
    if (curve.kind != CurveKind::Barb || curve.side != side) continue;
    double length = 0;  // the control polygon: at least the curve's arc length
    for (std::size_t i = 1; i < curve.points.size(); ++i) length += glm::length(curve.points[i].p - curve.points[i - 1].p);
    longest = std::max(longest, length);
  }
  s.barbules_per_side = closing_barbule_count(longest, s);
}

int closing_barbule_count(double longest_barb_mm, const SubstructureParams& s) {
  if (!(s.barbule_radius > 0) || !(longest_barb_mm > 0)) return s.barbules_per_side;
  const double n = kBarbuleClosure * longest_barb_mm * std::sin(s.elevation_deg * kPi / 180.0) / (2.0 * s.barbule_radius);
  return int(std::clamp(std::ceil(n), 1.0, 100000.0));
}

namespace {
// The value at which the weights (summed in value order) reach half their total.
double weighted_median(std::vector<glm::dvec2> vw) {  // (value, weight), weights > 0
  std::sort(vw.begin(), vw.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x; });
  double total = 0;
  for (const auto& q : vw) total += q.y;
  double acc = 0;
  for (const auto& q : vw)
    if ((acc += q.y) >= 0.5 * total) return q.x;
  return vw.back().x;
}
}  // namespace

AlongShaftFit smooth_along_shaft(const std::vector<double>& x, const std::vector<double>& value,
                                 const std::vector<double>& weight, const std::vector<double>& prior,
                                 const AlongShaftOptions& o) {
  const std::size_t n = x.size();
  if (value.size() != n || weight.size() != n || prior.size() != n)
    throw Error("smooth_along_shaft: " + std::to_string(n) + " positions, " + std::to_string(value.size()) +
                " values, " + std::to_string(weight.size()) + " weights and " + std::to_string(prior.size()) +
                " prior values; give one of each per station");
  if (!(o.bandwidth > 0) || !(o.min_weight > 0) || !(o.min_scale > 0) || o.iterations < 0)
    throw Error("smooth_along_shaft: bandwidth, min_weight and min_scale must be positive, iterations >= 0");
  AlongShaftFit fit;
  fit.value = prior;
  fit.outlier.assign(n, false);
  std::vector<double> w(n, 0.0);
  double total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool ok = std::isfinite(x[i]) && std::isfinite(value[i]) && std::isfinite(weight[i]) && weight[i] > 0;
    w[i] = ok ? weight[i] : 0.0;
    total += w[i];
  }
  if (!(total > 0)) {
    fit.from_prior = true;
    return fit;
  }
  // The fit at x0 with reading weights a (w times robustness): a local weighted
  // median or a local-linear regression, within the readings' range there. The
  // window holds `min_weight` and, between readings, the nearest one on either
  // side, so a gap is bridged by a line across it; past the last reading the
  // fit holds its value.
  std::vector<std::pair<double, std::size_t>> near;
  const auto fit_at = [&](double x0, const std::vector<double>& a, bool median, double bandwidth,
                          double min_weight) -> double {
    near.clear();
    double below = INFINITY, above = INFINITY;
    for (std::size_t j = 0; j < n; ++j)
      if (a[j] > 0) {
        near.push_back({std::fabs(x[j] - x0), j});
        if (x[j] < x0) below = std::min(below, x0 - x[j]);
        if (x[j] > x0) above = std::min(above, x[j] - x0);
      }
    if (near.empty()) return NAN;
    std::sort(near.begin(), near.end());
    double acc = 0, reach = near.back().first;
    for (const auto& [d, j] : near)
      if ((acc += a[j]) >= min_weight) {
        reach = d;
        break;
      }
    if (std::isfinite(below) && std::isfinite(above)) reach = std::max(reach, std::max(below, above));
    const double h = std::max(bandwidth, 1.25 * reach);
    std::vector<glm::dvec2> vw;
    double s0 = 0, s1 = 0, s2 = 0, t0 = 0, t1 = 0, lo = INFINITY, hi = -INFINITY;
    for (const auto& [d, j] : near) {
      if (d >= h) break;
      // The median weighs every reading in the window alike (by its weight only):
      // at the end of the shaft a tricube would let the last one or two decide.
      const double u = d / h, k = median ? a[j] : a[j] * std::pow(1.0 - u * u * u, 3);
      if (!(k > 0)) continue;
      const double dx = x[j] - x0, y = value[j];
      vw.push_back({y, k});
      s0 += k, s1 += k * dx, s2 += k * dx * dx, t0 += k * y, t1 += k * dx * y;
      lo = std::min(lo, y), hi = std::max(hi, y);
    }
    if (vw.empty()) return value[near.front().second];
    if (median) return weighted_median(std::move(vw));
    const double det = s0 * s2 - s1 * s1;
    const double y = det > 1e-9 * s0 * s2 ? (s2 * t0 - s1 * t1) / det : t0 / s0;
    return std::clamp(std::isfinite(y) ? y : t0 / s0, lo, hi);
  };
  std::vector<double> robust(n, 1.0), a = w, f(n);
  // Stations at no finite position take the median of all readings.
  std::vector<glm::dvec2> all;
  for (std::size_t i = 0; i < n; ++i)
    if (w[i] > 0) all.push_back({value[i], w[i]});
  const double overall = weighted_median(all);
  const auto fit_all = [&](bool median, double bandwidth, double min_weight) {
    for (std::size_t i = 0; i < n; ++i)
      f[i] = std::isfinite(x[i]) ? fit_at(x[i], a, median, bandwidth, min_weight) : overall;
  };
  // The start: a weighted median over twice the window, which a few readings
  // of something else, even side by side, cannot move.
  fit_all(true, 2 * o.bandwidth, 2 * o.min_weight);
  for (int it = 0; it < o.iterations; ++it) {
    std::vector<glm::dvec2> res;
    for (std::size_t i = 0; i < n; ++i)
      if (w[i] > 0) res.push_back({std::fabs(value[i] - f[i]), w[i]});
    const double s = std::max(o.min_scale, weighted_median(res));
    for (std::size_t i = 0; i < n; ++i) {
      const double u = w[i] > 0 ? (value[i] - f[i]) / (6.0 * s) : 0.0;
      robust[i] = std::fabs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
      a[i] = w[i] * robust[i];
    }
    fit_all(false, o.bandwidth, o.min_weight);
  }
  for (std::size_t i = 0; i < n; ++i) {
    fit.outlier[i] = w[i] > 0 && !(robust[i] > 0);
    if (std::isfinite(f[i])) fit.value[i] = f[i];
  }
  return fit;
}

BarbAngleFit barb_angles_along_shaft(const std::vector<double>& t, const std::vector<double>& angle,
                                     const std::vector<double>& conf, double calamus_t) {
  const std::size_t n = t.size();
  if (angle.size() != n || conf.size() != n)
    throw Error("barb_angles_along_shaft: " + std::to_string(n) + " stations, " + std::to_string(angle.size()) +
                " angles and " + std::to_string(conf.size()) + " confidences; give one of each per station");
  // Near the tip barbs run almost along the shaft, so flat angles are barbs there.
  constexpr double kTipZone = 0.9;
  const double c0 = std::isfinite(calamus_t) ? std::clamp(calamus_t, 0.0, 0.99) : 0.0;
  const Profile preset = default_feather_params().left.angle_deg;
  BarbAngleFit out;
  std::vector<double> weight(n, 0.0), prior(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = (t[i] - c0) / (1.0 - c0);
    prior[i] = preset(std::isfinite(x) ? std::clamp(x, 0.0, 1.0) : 0.5);
    if (!(conf[i] >= kLayoutMinConfidence) || !std::isfinite(angle[i])) continue;
    ++out.confident;
    // Past 90 degrees a barb would point back toward the calamus; away from the
    // tip, barbs leave the rachis at 20-70 degrees, and an orientation under 15
    // there is the texture of unresolved barbs or the rachis and shaft edges
    // (spoonbill sheet at 0.86 mm/px: 5 degrees).
    if (angle[i] > 90.0) ++out.backward;
    else if (!(angle[i] > 0.0) || (angle[i] < kMinBarbAngleDeg && !(x >= kTipZone))) ++out.flat;
    else weight[i] = std::min(conf[i], 1.0);
  }
  const AlongShaftFit fit = smooth_along_shaft(t, angle, weight, prior);
  for (std::size_t i = 0; i < n; ++i) out.outliers += fit.outlier[i];
  out.angle_deg = fit.value;
  out.from_prior = fit.from_prior;
  return out;
}

LayoutParams layout_to_params(const FeatherLayout& f, const std::string& source) {
  const Checker check{source};
  check_layout(f, check);
  const FeatherParams preset = default_feather_params();
  LayoutParams out;
  FeatherParams& p = out.params;
  p = preset;
  p.name = "photo-feather-" + std::to_string(f.id);
  p.description = "feather " + std::to_string(f.id) + " of " + source;
  const double L = f.length_mm;
  const double calamus_t = calamus_fraction(f);
  p.shaft.length = L;
  p.shaft.calamus_length = calamus_t * L;
  // The builder bends its shaft along a circular arc. An arc turning by T has
  // sagitta h over chord c with h / c = tan(T / 4) / 2; reading T off the
  // midpoint rather than the end tangents keeps a hooked tip from bending the
  // whole shaft. + bend is toward +X (clockwise seen from the dorsal side).
  const glm::dvec2 p0 = f.shaft_mm.eval(0.0), p1 = f.shaft_mm.eval(1.0), pm = f.shaft_mm.eval(0.5);
  const glm::dvec2 chord = p1 - p0;
  const double c = glm::length(chord);
  const double h = c > 0 ? (chord.x * (pm - p0).y - chord.y * (pm - p0).x) / c : 0.0;  // + left of the chord
  // An anticlockwise arc bulges to the right of its chord (h < 0).
  const double turn = c > 0 ? -4.0 * std::atan(2.0 * h / c) : 0.0;
  p.shaft.bend_deg = std::isfinite(turn) ? std::clamp(-turn * 180.0 / kPi, -90.0, 90.0) : 0.0;
  const double r_base = 0.5 * f.shaft_width_mm;
  p.shaft.radius_base = std::isfinite(r_base) && r_base > 1e-3 ? std::min(r_base, 0.02 * L) : 0.004 * L;
  p.shaft.radius_tip = std::max(1e-4, kShaftTipRadiusFraction * p.shaft.radius_base);
  p.barb.radius_root = std::clamp(0.15 * p.shaft.radius_base, 1e-3, 0.2);
  p.barb.radius_tip = 0.4 * p.barb.radius_root;

  const double vane_length = L - p.shaft.calamus_length;
  const double prior = barb_spacing_prior_mm(L);
  std::optional<double> spacing[2];
  std::string refused[2];
  const VaneProfile* sides[2] = {&f.left, &f.right};
  const char* names[2] = {"left", "right"};
  for (int s = 0; s < 2; ++s) {
    BarbSpacingReading r = resolved_barb_spacing(f, s == 0 ? VaneSide::Left : VaneSide::Right);
    spacing[s] = r.mm;
    refused[s] = std::move(r.refused);
  }
  for (int s = 0; s < 2; ++s) {
    const VaneProfile& v = *sides[s];
    VaneParams& vp = p.vane(s == 0 ? VaneSide::Left : VaneSide::Right);
    const std::string side = names[s];

    // A side hidden under its shingled row's neighbours over half its stations or
    // more shows too little of itself: the prior builds it (docs/analysis.md,
    // "Shingled rows").
    const auto hidden_stations = std::count_if(v.width_hidden.begin(), v.width_hidden.end(), [](double h) { return h > 0; });
    const bool hidden = hidden_stations > 0 && 2 * std::size_t(hidden_stations) >= v.width_hidden.size();
    auto width = hidden ? std::vector<glm::dvec2>{} : vane_widths(f.stations_t, v);
    if (width.empty()) {
      const std::string why = hidden ? "hidden under the feathers of its shingled row at " +
                                           std::to_string(hidden_stations) + " of " +
                                           std::to_string(v.width_hidden.size()) + " stations"
                                     : "no station is confident";
      out.warnings.push_back(side + " vane width: " + why + "; used the default feather's profile scaled to the shaft length");
      for (const auto& k : preset.left.width.knots())
        width.push_back({calamus_t + k.x * (1 - calamus_t), k.y * L / preset.shaft.length});
    }
    vp.width = width_profile(width, calamus_t, 2.0 * L);
    if (!(vp.width.max_value() > 0)) {
      out.warnings.push_back(side + " vane width: all measured widths are 0; used 2% of the length");
      vp.width = Profile({{0.0, 0.02 * L}, {1.0, 0.02 * L}});
    }

    // Barb angles: the readings that can be barbs, smoothed along the shaft with
    // their confidences; the rest take their neighbours' value (docs/analysis.md,
    // "Barb angles along the shaft").
    // The downy base's barbs are loose, at no one angle: its readings are not the vane's.
    std::vector<double> angle_confidence = v.barb_angle_confidence;
    for (std::size_t i = 0; i < f.stations_t.size(); ++i)
      if (f.stations_t[i] < v.afterfeather_to_t) angle_confidence[i] = 0;
    const BarbAngleFit a = barb_angles_along_shaft(f.stations_t, v.barb_angle_deg, angle_confidence, calamus_t);
    if (a.backward)
      out.warnings.push_back(side + " barb angle: " + std::to_string(a.backward) +
                             " station(s) above 90 degrees ignored");
    if (a.flat)
      out.warnings.push_back(side + " barb angle: " + std::to_string(a.flat) +
                             " station(s) below 15 degrees away from the tip ignored (not barbs)");
    if (a.outliers)
      out.warnings.push_back(side + " barb angle: " + std::to_string(a.outliers) +
                             " station(s) off their neighbours along the shaft ignored");
    if (a.from_prior)
      out.warnings.push_back(side + " barb angle: no station is confident; used the default feather's profile");
    std::vector<glm::dvec2> angle;
    for (std::size_t i = 0; i < f.stations_t.size(); ++i) angle.push_back({f.stations_t[i], a.angle_deg[i]});
    if (std::any_of(angle.begin(), angle.end(), [](const glm::dvec2& q) { return q.y < 5; }))
      out.warnings.push_back(side + " barb angle: values below 5 degrees raised to 5");
    vp.angle_deg = vane_profile(angle, calamus_t, 5.0, 90.0);

    double d = 0;
    const std::string why = refused[s].empty() ? "not confident" : "not resolved (" + refused[s] + ")";
    if (spacing[s]) {
      d = *spacing[s];
    } else if (spacing[1 - s]) {
      d = *spacing[1 - s];
      out.warnings.push_back(side + " barb spacing: " + why + "; used the " + names[1 - s] + " vane's");
    } else {
      d = prior;
      out.warnings.push_back(side + " barb spacing: " + why + " on either side; used the prior " + num(d) +
                             " mm for a " + num(std::round(L)) + " mm feather (docs/analysis.md, \"Barb density\")");
    }
    // Barbs per side = vane length / spacing along the shaft (docs/layout-format.md).
    vp.barb_density = 0;
    vp.barbs = int(std::clamp(std::lround(vane_length / d), 2L, 5000L));
  }
  // A downy base: the generator's afterfeather, loose barbs over one basal
  // fraction of both vanes (the mean of the two sides', a side without one
  // counting 0), from where the vane begins.
  double downy[2];
  for (int s = 0; s < 2; ++s)
    downy[s] = std::clamp((sides[s]->afterfeather_to_t - calamus_t) / (1.0 - calamus_t), 0.0, 0.9);
  // A plume (both sides downy to the tip, docs/analysis.md "Plumes: an open vane"):
  // down barbs from base to tip.
  const bool plume = sides[0]->afterfeather_to_t >= 1.0 && sides[1]->afterfeather_to_t >= 1.0;
  if (downy[0] > 0 || downy[1] > 0) {
    p.afterfeather.enabled = true;
    p.afterfeather.fraction = plume ? 1.0 : 0.5 * (downy[0] + downy[1]);
    // The photo does not show how far loose barbs wave and lift; the default's
    // 1 mm, scaled down on feathers shorter than 10 cm.
    p.afterfeather.wave = p.afterfeather.lift = std::min(1.0, 0.01 * L);
    out.warnings.push_back(plume ? "a plume (both vanes open, " +
                                       num(std::round(50 * (sides[0]->open_share + sides[1]->open_share))) +
                                       " % of them the card) built as down barbs from base to tip"
                                 : "downy base (left " + num(std::round(100 * downy[0])) + " %, right " +
                                       num(std::round(100 * downy[1])) +
                                       " % of the vane) built as loose afterfeather barbs over " +
                                       num(std::round(100 * p.afterfeather.fraction)) + " % of both vanes");
  }
  make_buildable(p, out.warnings);
  validate(p, source);
  return out;
}

const FeatherLayout& pick_feather(const Layout& layout, std::optional<int> id, const std::string& source) {
  if (layout.feathers.empty()) throw Error(Location{source}, "the layout has no feathers; re-run `plumage analyze`");
  if (!id) return layout.feathers.front();
  std::string ids;
  for (const auto& f : layout.feathers) {
    if (f.id == *id) return f;
    ids += (ids.empty() ? "" : ", ") + std::to_string(f.id);
  }
  throw Error(Location{source}, "--feather " + std::to_string(*id) + ": no such feather; the layout has " + ids);
}

Feather layout_to_feather(const FeatherLayout& f, std::uint64_t seed, const std::filesystem::path& albedo_dir,
                          const std::filesystem::path& fcurves_dir, const std::string& source,
                          std::vector<std::string>* warnings) {
  LayoutParams lp = layout_to_params(f, source);
  Feather feather = build_feather(lp.params, seed, "layout:" + source);
  if (warnings) *warnings = lp.warnings;

  // The built shaft is an arc through the analysed calamus and tip; the analysed one
  // may bend both ways. Each vane was measured across the analysed shaft, so the
  // built feather is laid along it (shaft_pose.h), its calamus on the analysed one.
  try {
    lay_along_shaft(feather, f.shaft_mm);
  } catch (const Error& e) {  // in the layout's terms: which feather, which field
    throw Error(Location{source}, "feather " + std::to_string(f.id) + " shaft.control_points_mm: " + e.message() +
                                      "; re-run `plumage analyze` or give the shaft's points");
  }

  if (!f.albedo.file.empty()) {
    if (!(f.albedo.width_px > 0 && f.albedo.height_px > 0 && f.albedo.mm_per_texel > 0))
      throw Error(Location{source}, "feather " + std::to_string(f.id) +
                                        " albedo: width_px, height_px and mm_per_texel must be positive");
    const std::filesystem::path tex = std::filesystem::absolute(albedo_dir / f.albedo.file);
    if (!std::filesystem::exists(tex))
      throw Error(Location{source}, "feather " + std::to_string(f.id) + " albedo texture " + tex.string() +
                                        " does not exist; keep it next to the layout or re-run `plumage analyze`");
    const std::filesystem::path rel = tex.lexically_proximate(std::filesystem::absolute(fcurves_dir));
    feather.albedo.texture = rel.generic_string();
    const double s = f.albedo.mm_per_texel;
    feather.albedo.rect_min = glm::vec2(f.albedo.origin_mm.x, f.albedo.origin_mm.y - f.albedo.height_px * s);
    feather.albedo.rect_max = glm::vec2(f.albedo.origin_mm.x + f.albedo.width_px * s, f.albedo.origin_mm.y);
    feather.albedo.scale = float(f.albedo.scale);
    for (const glm::dvec3& c : f.albedo.shaft_rgb) feather.albedo.shaft.push_back(glm::vec3(c));
  }
  for (VaneSide side : {VaneSide::Left, VaneSide::Right}) close_vane(feather, side);
  feather.provenance.source = "layout:" + source;
  feather.provenance.seed = seed;
  return feather;
}

std::optional<glm::dvec3> albedo_mean(const Image& a) {
  glm::dvec3 sum(0.0);
  double weight = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const double alpha = a.channels == 4 ? a.at(x, y)[3] : 1.0;
      sum += alpha * glm::dvec3(a.rgb(x, y));
      weight += alpha;
    }
  if (!(weight > 0)) return std::nullopt;
  return sum / weight;
}

Image albedo_for_render(const Image& a, glm::vec3* mean) {
  if (a.empty()) throw Error("the albedo texture is empty");
  const std::optional<glm::dvec3> under_mask = albedo_mean(a);
  const glm::vec3 m = under_mask ? glm::vec3(*under_mask) : glm::vec3(0.5f);
  Image out(a.width, a.height, 3);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const float alpha = a.channels == 4 ? a.at(x, y)[3] : 1.0f;
      out.set_rgb(x, y, glm::mix(m, a.rgb(x, y), alpha));
    }
  if (mean) *mean = m;
  return out;
}

Feather layout_to_feather_with_albedo(const FeatherLayout& layout, std::uint64_t seed,
                                      const std::filesystem::path& albedo_dir,
                                      const std::filesystem::path& fcurves_dir,
                                      const std::filesystem::path& texture_path, const std::string& source,
                                      std::vector<std::string>* warnings, FileBatch* outputs) {
  Feather feather = layout_to_feather(layout, seed, albedo_dir, fcurves_dir, source, warnings);
  if (feather.albedo.texture.empty()) return feather;
  glm::vec3 mean;
  const Image filled = albedo_for_render(read_image(albedo_dir / layout.albedo.file), &mean);
  if (outputs) write_image(*outputs, texture_path, filled);
  else write_image(texture_path, filled);
  feather.albedo.color = mean * feather.albedo.scale;
  feather.albedo.texture = std::filesystem::absolute(texture_path)
                               .lexically_proximate(std::filesystem::absolute(fcurves_dir))
                               .generic_string();
  return feather;
}

}  // namespace plumage
