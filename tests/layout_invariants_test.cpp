// A generator that never builds an impossible feather, from any layout: random
// ones, and adversarial ones a person might write by hand. layout -> params
// either repairs what it is given (with a warning) or rejects it naming the
// value; whatever it accepts builds a feather whose barbs
//  * leave the rachis toward the tip at an angle in (0, 90] degrees, on their own side,
//  * never cross the shaft (stay on their own side of it) or their neighbours,
//  * end on the vane's outline (the width profile) within one barb spacing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>
#include <string>

#include "plumage/common/bspline.h"
#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/common/feather.h"
#include "plumage/analysis/analyze.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/layout_to_params.h"

using namespace plumage;

namespace {


BSpline3 spline(const Curve& c) {
  std::vector<glm::dvec3> v;
  for (const auto& p : c.points) v.push_back(glm::dvec3(p.p));
  return BSpline3(v);
}

// 2D polyline of a curve (feather coordinates, seen from the dorsal side).
std::vector<glm::dvec2> polyline(const BSpline3& c, int n) {
  std::vector<glm::dvec2> out;
  for (int i = 0; i <= n; ++i) out.push_back(glm::dvec2(c.eval(double(i) / n)));
  return out;
}

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

bool segments_cross(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a);
  const double d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

// The first crossing as "i/j" (segment of a, segment of b), or "".
std::string polylines_cross(const std::vector<glm::dvec2>& a, const std::vector<glm::dvec2>& b) {
  for (std::size_t i = 0; i + 1 < a.size(); ++i)
    for (std::size_t j = 0; j + 1 < b.size(); ++j)
      if (segments_cross(a[i], a[i + 1], b[j], b[j + 1]))
        return std::to_string(i) + "/" + std::to_string(j) + " at (" + std::to_string(a[i].x) + ", " +
               std::to_string(a[i].y) + ")";
  return "";
}

// Nearest point of the shaft polyline: its index, arc length and signed side
// (+ right of the shaft, i.e. +X when the tip is up).
struct ShaftHit {
  double s = 0, side = 0;
  glm::dvec2 tangent{0.0};
};
ShaftHit nearest(const std::vector<glm::dvec2>& shaft, const std::vector<double>& arc, glm::dvec2 p) {
  ShaftHit best;
  double d2 = 1e300;
  for (std::size_t i = 0; i + 1 < shaft.size(); ++i) {
    const glm::dvec2 a = shaft[i], e = shaft[i + 1] - a;
    const double len2 = glm::dot(e, e);
    const double u = len2 > 0 ? std::clamp(glm::dot(p - a, e) / len2, 0.0, 1.0) : 0.0;
    const glm::dvec2 q = a + u * e;
    const double dd = glm::dot(p - q, p - q);
    if (dd < d2) {
      d2 = dd;
      best.s = arc[i] + u * (arc[i + 1] - arc[i]);
      best.tangent = len2 > 0 ? e / std::sqrt(len2) : glm::dvec2(0, 1);
      best.side = -cross(best.tangent, p - q);  // right of the direction of travel is +
    }
  }
  return best;
}

struct Violation {
  std::string what;
};

// Checks the invariants on a built feather; returns the first broken one.
std::string check_feather(const FeatherParams& p, const Feather& f) {
  const Curve* sc = f.shaft();
  if (!sc) return "no shaft";
  const BSpline3 shaft3 = spline(*sc);
  const std::vector<glm::dvec2> shaft = polyline(shaft3, 400);
  std::vector<double> arc{0.0};
  for (std::size_t i = 1; i < shaft.size(); ++i) arc.push_back(arc.back() + glm::length(shaft[i] - shaft[i - 1]));
  const double L = arc.back(), s0 = p.shaft.calamus_length, lv = L - s0;
  for (VaneSide side : {VaneSide::Left, VaneSide::Right}) {
    const double sign = side == VaneSide::Right ? 1.0 : -1.0;
    const int n = p.barb_count(side);
    const double spacing = lv / std::max(1, n);
    const VaneParams& vane = p.vane(side);
    std::vector<std::vector<glm::dvec2>> barbs;
    for (const Curve& c : f.curves) {
      if (c.kind == CurveKind::Shaft || c.side != side) continue;  // barbs and down barbs alike
      const BSpline3 b = spline(c);
      const std::vector<glm::dvec2> line = polyline(b, 24);
      const std::string id = std::string(side == VaneSide::Right ? "right" : "left") + " barb " +
                             std::to_string(barbs.size()) + " (root " + std::to_string(c.root) + ")";
      // A stub shorter than the gap to its neighbour (where the vane has no width
      // yet, below the first barbs the photo shows) has no direction to check.
      double length = 0;
      for (std::size_t i = 1; i < line.size(); ++i) length += glm::length(line[i] - line[i - 1]);
      if (length < spacing) {
        barbs.push_back(std::vector<glm::dvec2>(line.begin() + 1, line.end()));
        continue;
      }
      // Leaves the rachis toward the tip, at (0, 90] degrees, on its own side.
      const ShaftHit root = nearest(shaft, arc, line[0]);
      const glm::dvec2 d = glm::normalize(line[2] - line[0]);
      const double angle = std::acos(std::clamp(glm::dot(d, root.tangent), -1.0, 1.0)) * 180 / kPi;
      if (!(angle > 0.0 && angle <= 90.5)) return id + ": leaves the shaft at " + std::to_string(angle) + " deg";
      if (-sign * cross(root.tangent, d) <= 0)
        return id + ": leaves toward the other vane (length " + std::to_string(length) + " mm, at " +
               std::to_string(line[0].x) + ", " + std::to_string(line[0].y) + ")";
      // Stays on its own side of the shaft (never crosses it).
      for (std::size_t i = 2; i < line.size(); ++i)
        if (sign * nearest(shaft, arc, line[i]).side < -std::max(1e-3 * L, double(c.points[1].radius)))
          return id + ": crosses the shaft at sample " + std::to_string(i);
      // Ends on the outline: at the vane's half-width for where it ends, within
      // one barb spacing plus 5 % of the widest width (how closely the vane's
      // subdivision surface follows its width profile on a strongly bent or
      // abruptly changing vane), or at the tip, where the vane closes.
      const ShaftHit end = nearest(shaft, arc, line.back());
      const double x = std::clamp((end.s - s0) / lv, 0.0, 1.0);
      // The outline is a curve: where it falls steeply (a blunt tip) the distance
      // to it is measured along the shaft as well, within two spacings.
      const double reach = std::fabs(end.side), want = vane.width(x);
      double off = std::fabs(reach - want);
      for (double dx = -2 * spacing; dx <= 2 * spacing; dx += 0.1 * spacing)
        off = std::min(off, std::fabs(reach - vane.width(std::clamp(x + dx / lv, 0.0, 1.0))));
      if (off > spacing + 0.05 * vane.width.max_value() && end.s < L - spacing)
        return id + ": ends " + std::to_string(reach) + " mm from the shaft, the outline is at " +
               std::to_string(want) + " mm (spacing " + std::to_string(spacing) + ")";
      barbs.push_back(std::vector<glm::dvec2>(line.begin() + 1, line.end()));
    }
    if (int(barbs.size()) != n) return "barb count " + std::to_string(barbs.size()) + " != " + std::to_string(n);
    // Never crosses its neighbours (barbs come out in root order).
    for (std::size_t k = 1; k < barbs.size(); ++k)
      if (const std::string at = polylines_cross(barbs[k - 1], barbs[k]); !at.empty())
        return std::string(side == VaneSide::Right ? "right" : "left") + " barbs " + std::to_string(k - 1) +
               " and " + std::to_string(k) + " cross, segments " + at;
  }
  return "";
}

// A layout with `n` stations of the given profiles and a shaft bent by `bend_deg`.
FeatherLayout make_layout(double length, double bend_deg, int n) {
  FeatherLayout f;
  f.id = 1;
  const double turn = bend_deg * kPi / 180.0;
  std::vector<glm::dvec2> pts;
  for (int i = 0; i < 8; ++i) {
    const double s = double(i - 1) / 5.0;
    const double a = turn * (s - 0.5);
    pts.push_back(turn == 0.0 ? glm::dvec2(0.0, length * s)
                              : glm::dvec2((std::cos(a) - std::cos(0.5 * turn)) * length / turn,
                                           (std::sin(a) + std::sin(0.5 * turn)) * length / turn));
  }
  f.shaft_mm = BSpline2(pts);
  f.length_mm = length;
  f.shaft_width_mm = 0.01 * length;
  f.feather_from_image = glm::dmat3x2(glm::dvec2(0.05, 0), glm::dvec2(0, -0.05), glm::dvec2(0));
  f.image_from_feather = glm::dmat3x2(glm::dvec2(20, 0), glm::dvec2(0, -20), glm::dvec2(0));
  for (int i = 0; i < n; ++i) f.stations_t.push_back((i + 0.5) / n);
  for (VaneProfile* v : {&f.left, &f.right}) {
    v->width_mm.assign(n, 0.0);
    v->width_confidence.assign(n, 1.0);
    v->barb_angle_deg.assign(n, 45.0);
    v->barb_angle_confidence.assign(n, 0.9);
    v->barb_spacing_mm.assign(n, 0.5);
    v->barb_spacing_confidence.assign(n, 0.8);
  }
  return f;
}

// Repaired (built and checked) or rejected with a message naming the layout.
void expect_sound(const FeatherLayout& f, const std::string& name) {
  LayoutParams lp;
  try {
    lp = layout_to_params(f, name);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    return;
  }
  const Feather built = build_feather(lp.params, 7, name);
  const std::string broken = check_feather(lp.params, built);
  EXPECT_EQ(broken, "") << name << ": L " << lp.params.shaft.length << " bend " << lp.params.shaft.bend_deg
                        << " w " << lp.params.left.width.max_value() << "/" << lp.params.right.width.max_value()
                        << " angles " << lp.params.left.angle_deg.min_value() << "-" << lp.params.left.angle_deg.max_value()
                        << " jitter " << lp.params.jitter.angle_deg << "/" << lp.params.jitter.spacing << " barb bend " << lp.params.left.barb_bend_deg << " barbs " << lp.params.barb_count(VaneSide::Left) << "/" << lp.params.barb_count(VaneSide::Right);
}

}  // namespace

// Layouts as analysis reports them: a vane outline from a bare calamus to a
// closed tip, barb angles falling toward the tip, measurement noise, and stations
// analysis was unsure of holding anything at all (confidence under 0.5).
TEST(LayoutInvariants, RandomLayoutsBuildPossibleFeathers) {
  std::mt19937_64 rng(2026), downy_rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int unsure_values = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const double length = 10.0 + 290.0 * U(rng);
    const int n = 6 + int(30 * U(rng));
    FeatherLayout f = make_layout(length, -60.0 + 120.0 * U(rng), n);
    const double bare = 0.25 * U(rng), power = 0.3 + 0.7 * U(rng);
    for (VaneProfile* v : {&f.left, &f.right}) {
      const double W = length * (0.03 + 0.3 * U(rng)), a0 = 30 + 40 * U(rng), a1 = 15 + (a0 - 15) * U(rng);
      for (int i = 0; i < n; ++i) {
        const double t = f.stations_t[i];
        const double x = (t - bare) / (1 - bare);
        v->width_mm[i] = x <= 0 ? 0.0 : W * std::pow(std::sin(kPi * x), power) * (1 + 0.1 * (U(rng) - 0.5));
        v->barb_angle_deg[i] = a0 + (a1 - a0) * std::clamp(x, 0.0, 1.0) + 6 * (U(rng) - 0.5);
        v->barb_spacing_mm[i] = barb_spacing_prior_mm(length) * (1 + 0.2 * (U(rng) - 0.5));
        for (double* c : {&v->width_confidence[i], &v->barb_angle_confidence[i], &v->barb_spacing_confidence[i]})
          *c = U(rng) < 0.8 ? 0.5 + 0.5 * U(rng) : 0.5 * U(rng);
        if (v->width_confidence[i] < 0.5) v->width_mm[i] = 3 * W * U(rng), ++unsure_values;
        if (v->barb_angle_confidence[i] < 0.5) v->barb_angle_deg[i] = 180 * U(rng), ++unsure_values;
        if (v->barb_spacing_confidence[i] < 0.5) v->barb_spacing_mm[i] = 20 * U(rng), ++unsure_values;
      }
    }
    // A third of them with a downy base on either side, from its own stream so
    // the rest of each layout stays as it was.
    if (trial % 3 == 0)
      for (VaneProfile* v : {&f.left, &f.right}) v->afterfeather_to_t = 0.6 * U(downy_rng);
    expect_sound(f, "random" + std::to_string(trial) + ".json");
  }
  EXPECT_GT(unsure_values, 500);  // the unsure stations were exercised
}

TEST(LayoutInvariants, AdversarialLayoutsAreRepairedOrRejected) {
  const int n = 24;
  struct Case {
    std::string name;
    std::function<void(FeatherLayout&)> edit;
  };
  auto all = [](FeatherLayout& f, auto fn) {
    for (VaneProfile* v : {&f.left, &f.right}) fn(*v);
  };
  const std::vector<Case> cases = {
      {"backward-angles", [&](FeatherLayout& f) { all(f, [](VaneProfile& v) { std::fill(v.barb_angle_deg.begin(), v.barb_angle_deg.end(), 179.0); }); }},
      {"zero-angles", [&](FeatherLayout& f) { all(f, [](VaneProfile& v) { std::fill(v.barb_angle_deg.begin(), v.barb_angle_deg.end(), 0.0); }); }},
      {"alternating-angles", [&](FeatherLayout& f) { all(f, [](VaneProfile& v) { for (std::size_t i = 0; i < v.barb_angle_deg.size(); ++i) v.barb_angle_deg[i] = i % 2 ? 5.0 : 90.0; }); }},
      {"wide-vane-tight-bend", [&](FeatherLayout& f) {
         f = make_layout(100.0, 90.0, n);
         all(f, [](VaneProfile& v) { std::fill(v.width_mm.begin(), v.width_mm.end(), 150.0); });
       }},
      {"spiky-width", [&](FeatherLayout& f) { all(f, [](VaneProfile& v) { for (std::size_t i = 0; i < v.width_mm.size(); ++i) v.width_mm[i] = i % 2 ? 0.0 : 60.0; }); }},
      {"width-step-at-tip", [&](FeatherLayout& f) { all(f, [](VaneProfile& v) { std::fill(v.width_mm.begin(), v.width_mm.end(), 1.0); v.width_mm.back() = 80.0; }); }},
      {"tiny-spacing", [&](FeatherLayout& f) { all(f, [](VaneProfile& v) { std::fill(v.barb_spacing_mm.begin(), v.barb_spacing_mm.end(), 1e-4); }); }},
      {"huge-spacing", [&](FeatherLayout& f) { all(f, [](VaneProfile& v) { std::fill(v.barb_spacing_mm.begin(), v.barb_spacing_mm.end(), 1e4); }); }},
      {"nan-angle", [&](FeatherLayout& f) { f.left.barb_angle_deg[3] = std::nan(""); }},
      {"two-stations", [&](FeatherLayout& f) {
         f = make_layout(80.0, 10.0, 2);
         all(f, [](VaneProfile& v) { v.width_mm = {10.0, 10.0}; });
       }},
      {"stations-out-of-order", [&](FeatherLayout& f) { std::swap(f.stations_t[3], f.stations_t[4]); }},
      {"short-profile", [&](FeatherLayout& f) { f.right.width_mm.pop_back(); }},
      {"downy-everywhere", [&](FeatherLayout& f) { all(f, [](VaneProfile& v) { v.afterfeather_to_t = 1.0; }); }},
      {"downy-one-side", [&](FeatherLayout& f) { f.right.afterfeather_to_t = 0.6; }},
      {"downy-nan", [&](FeatherLayout& f) { f.left.afterfeather_to_t = std::nan(""); }},
      {"downy-negative", [&](FeatherLayout& f) { f.left.afterfeather_to_t = -0.2; }},
  };
  for (const Case& c : cases) {
    FeatherLayout f = make_layout(120.0, 8.0, n);
    all(f, [](VaneProfile& v) {
      for (std::size_t i = 0; i < v.width_mm.size(); ++i) v.width_mm[i] = 20.0 * std::sin(kPi * (i + 0.5) / v.width_mm.size());
    });
    c.edit(f);
    expect_sound(f, c.name + ".json");
  }
}

// The checker itself can fail: a feather whose barbs are mirrored onto the other
// side of the shaft, and one whose neighbours are swapped, are caught.
TEST(LayoutInvariants, TheCheckerCatchesCrossingAndBackwardBarbs) {
  FeatherLayout f = make_layout(100.0, 0.0, 12);
  for (VaneProfile* v : {&f.left, &f.right})
    for (std::size_t i = 0; i < v->width_mm.size(); ++i) v->width_mm[i] = 15.0 * std::sin(kPi * (i + 0.5) / 12);
  const LayoutParams lp = layout_to_params(f, "check.json");
  const Feather good = build_feather(lp.params, 3, "check");
  ASSERT_EQ(check_feather(lp.params, good), "");
  Feather mirrored = good;
  for (Curve& c : mirrored.curves)
    if (c.kind == CurveKind::Barb && c.side == VaneSide::Left)
      for (ControlPoint& cp : c.points) cp.p.x = -cp.p.x;
  EXPECT_NE(check_feather(lp.params, mirrored), "");
  Feather backward = good;
  for (Curve& c : backward.curves)
    if (c.kind == CurveKind::Barb)
      for (std::size_t i = 1; i < c.points.size(); ++i)
        c.points[i].p.y = 2 * c.points[1].p.y - c.points[i].p.y;  // reflect about the root row
  EXPECT_NE(check_feather(lp.params, backward), "");
  Feather crossed = good;
  int k = 0;
  Curve* prev = nullptr;
  for (Curve& c : crossed.curves)
    if (c.kind == CurveKind::Barb && c.side == VaneSide::Right) {
      if (prev && ++k == 5)  // neighbours' outer halves swapped
        for (std::size_t i = c.points.size() / 2; i < c.points.size(); ++i) std::swap(c.points[i].p, prev->points[i].p);
      prev = &c;
    }
  EXPECT_NE(check_feather(lp.params, crossed), "");
}

// Every feather analysed on the photos in ../shared/photos builds without a
// crossing or backward barb (skipped when the photos are absent).
TEST(LayoutInvariants, FeathersFromThePhotosArePossible) {
  const std::filesystem::path dir = std::filesystem::path(PLUMAGE_SHARED_DIR) / "photos";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no " << dir << " (shared photos absent)";
  int checked = 0;
  for (const char* name : {"spoonbill-wing-sheet.png", "blue-jay-feather-sheet.jpg", "peregrine-falcon-feather-sheet.jpg",
                           "european-robin-feather-sheet.jpg", "european-goldfinch-feather-sheet.jpg",
                           "pink-contour-feather.jpg"}) {
    if (!std::filesystem::exists(dir / name)) continue;
    AnalyzeOptions opt;
    if (std::string(name).find("spoonbill") != std::string::npos) opt.grid_mm = 20;
    const PhotoAnalysis A = analyze_photo(dir / name, opt);
    for (const FeatherLayout& f : A.layout.feathers) {
      const std::string id = std::string(name) + " feather " + std::to_string(f.id);
      LayoutParams lp;
      try {
        lp = layout_to_params(f, id);
      } catch (const Error& e) {
        ADD_FAILURE() << id << ": an analysed feather was rejected: " << e.what();
        continue;
      }
      const Feather built = build_feather(lp.params, 1, id);
      EXPECT_EQ(check_feather(lp.params, built), "") << id;
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);
}

// No outline shape at all: every value of every station drawn independently.
TEST(LayoutInvariants, IndependentlyRandomStationsBuildPossibleFeathers) {
  std::mt19937_64 rng(2027);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int trial = 0; trial < 60; ++trial) {
    const double length = 10.0 + 290.0 * U(rng);
    const int n = 2 + int(30 * U(rng));
    FeatherLayout f = make_layout(length, -90.0 + 180.0 * U(rng), n);
    const double wmax = length * (0.02 + 0.6 * U(rng));
    for (VaneProfile* v : {&f.left, &f.right})
      for (int i = 0; i < n; ++i) {
        v->width_mm[i] = wmax * U(rng);
        v->width_confidence[i] = U(rng);
        v->barb_angle_deg[i] = 180.0 * U(rng);
        v->barb_angle_confidence[i] = U(rng);
        v->barb_spacing_mm[i] = std::exp(std::log(0.05) + std::log(200.0) * U(rng));
        v->barb_spacing_confidence[i] = U(rng);
      }
    expect_sound(f, "jagged" + std::to_string(trial) + ".json");
  }
}
