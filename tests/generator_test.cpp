// Properties of procedurally generated feathers (issue 3): counts, roots on the
// shaft, barbs ordered in the vane domain, tips on the width profile, normals on
// the limit surface, determinism, presets.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "plumage/common/bspline.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/generator/builder.h"
#include "plumage/generator/presets.h"
#include "plumage/generator/random.h"

using namespace plumage;

namespace {

BSpline3 spline_of(const Curve& c) {
  std::vector<glm::dvec3> cp;
  for (const auto& p : c.points) cp.push_back(glm::dvec3(p.p));
  return BSpline3(cp);
}

// Closest point of a curve to q: dense sampling, then golden-section refinement.
struct Closest {
  double t, distance;
};
Closest closest_point(const BSpline3& c, const glm::dvec3& q, bool xy_only = false) {
  auto dist = [&](double t) {
    glm::dvec3 d = c.eval(t) - q;
    if (xy_only) d.z = 0;
    return glm::length(d);
  };
  const int n = 2000;
  int best = 0;
  double best_d = dist(0);
  for (int i = 1; i <= n; ++i)
    if (const double d = dist(double(i) / n); d < best_d) best = i, best_d = d;
  double a = std::max(0.0, (best - 1.0) / n), b = std::min(1.0, (best + 1.0) / n);
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 80; ++it) {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    if (dist(x1) < dist(x2)) b = x2;
    else a = x1;
  }
  return {0.5 * (a + b), dist(0.5 * (a + b))};
}

// Arc length by composite Simpson on many panels (independent of the generator's table).
double arc_length_to(const BSpline3& c, double t1) {
  const int n = 2000;
  double s = 0;
  for (int i = 0; i < n; ++i) {
    const double a = t1 * i / n, b = t1 * (i + 1) / n;
    s += (b - a) / 6 *
         (glm::length(c.deriv(a)) + 4 * glm::length(c.deriv(0.5 * (a + b))) + glm::length(c.deriv(b)));
  }
  return s;
}

// Everything switched on, to make the properties hard to keep.
FeatherParams busy_params() {
  FeatherParams p = default_feather_params();
  p.left.barbs = 120;
  p.right.barbs = 150;
  p.shaft.bend_deg = 25;
  p.shaft.arch_deg = 15;
  p.surface.cupping = 0.3;
  p.surface.twist_deg = 30;
  p.afterfeather.enabled = true;
  p.afterfeather.fraction = 0.3;
  p.splits.count = 6;
  p.splits.gap = 3;
  p.jitter.angle_deg = 8;
  p.jitter.spacing = 0.8;
  return p;
}

std::vector<FeatherParams> all_presets() {
  std::vector<FeatherParams> out;
  for (const auto& n : list_presets()) out.push_back(load_preset(n));
  return out;
}

}  // namespace

TEST(Generator, BarbCountIsExact) {
  FeatherParams p = default_feather_params();
  p.left.barbs = 37;
  p.right.barbs = 53;
  Feather f = build_feather(p, 1);
  EXPECT_EQ(f.count(CurveKind::Shaft), 1u);
  EXPECT_EQ(f.count(VaneSide::Left), 37u);
  EXPECT_EQ(f.count(VaneSide::Right), 53u);
  EXPECT_EQ(f.curves.front().kind, CurveKind::Shaft);

  p.right.barb_density = 2.5;  // per mm of the 85 mm vane
  f = build_feather(p, 1);
  EXPECT_EQ(f.count(VaneSide::Right), std::size_t(std::lround(2.5 * p.vane_length())));
  EXPECT_EQ(f.count(VaneSide::Left), 37u);
}

// Afterfeather barbs are down barbs (docs/generator.md): exactly the barbs rooted in
// the basal `fraction` of the vane, at the afterfeather's radius (narrowing to a
// quarter at the tip), with the feather's
// down cover; the rest keep the barb radius; a fraction of 1 is a plume, all down.
TEST(Generator, AfterfeatherBarbsAreDownBarbsAndAFractionOfOneIsAPlume) {
  FeatherParams p = default_feather_params();
  p.left.barbs = p.right.barbs = 60;
  p.afterfeather.enabled = true;
  p.afterfeather.fraction = 0.25;
  p.afterfeather.radius = 0.4;
  p.afterfeather.cover = 0.45;
  const Feather f = build_feather(p, 3);
  const double vane_start = p.shaft.calamus_length / p.shaft.length;
  std::size_t down = 0;
  for (const Curve& c : f.curves) {
    if (c.kind == CurveKind::Shaft) continue;
    const double x = (c.root - vane_start) / (1.0 - vane_start);  // where along the vane it leaves the shaft
    if (c.kind == CurveKind::Down) {
      ++down;
      EXPECT_LT(x, 0.25 + 1e-3);
      EXPECT_FLOAT_EQ(c.points.front().radius, 0.4f);  // narrowing to a quarter at the tip
      EXPECT_NEAR(c.points.back().radius, 0.1f, 1e-6f);
      for (std::size_t k = 1; k < c.points.size(); ++k) EXPECT_LE(c.points[k].radius, c.points[k - 1].radius);
    } else {
      EXPECT_GT(x, 0.25 - 1e-3);
      EXPECT_LE(c.points[1].radius, float(p.barb.radius_root) + 1e-6f);
    }
  }
  // A quarter of 60 barbs per side leave the shaft in the basal quarter (+-1 for jitter-free rounding).
  EXPECT_NEAR(double(down), 30.0, 2.0);
  EXPECT_FLOAT_EQ(f.down_cover, 0.45f);

  p.afterfeather.fraction = 1.0;
  const Feather plume = build_feather(p, 3);
  EXPECT_EQ(plume.count(CurveKind::Barb), 0u);
  EXPECT_EQ(plume.count(CurveKind::Down), 120u);

  p.afterfeather.enabled = false;
  const Feather closed = build_feather(p, 3);
  EXPECT_EQ(closed.count(CurveKind::Down), 0u);
  EXPECT_EQ(closed.down_cover, 1.0f);
}

TEST(Generator, BarbsStartOnTheShaftAtTheirRoot) {
  auto cases = all_presets();
  cases.push_back(busy_params());
  for (const auto& p : cases) {
    const Feather f = build_feather(p, 11);
    const BSpline3 shaft = spline_of(*f.shaft());
    const double L = arc_length_to(shaft, 1.0);
    double worst = 0, worst_root = 0;
    for (const Curve& c : f.curves) {
      if (c.kind != CurveKind::Barb) continue;
      const glm::dvec3 start = spline_of(c).eval(0);
      const Closest cl = closest_point(shaft, start);
      worst = std::max(worst, cl.distance);
      // root is the arc-length fraction of that shaft point.
      worst_root = std::max(worst_root, std::abs(arc_length_to(shaft, cl.t) / L - c.root));
      EXPECT_GE(c.root * L, p.shaft.calamus_length - 1e-3) << p.name << ": barb on the calamus";
    }
    EXPECT_LT(worst, 1e-3) << p.name;
    EXPECT_LT(worst_root, 1e-4) << p.name;
  }
}

TEST(Generator, NeighbouringBarbsNeverCrossInTheVaneDomain) {
  auto cases = all_presets();
  cases.push_back(busy_params());
  FeatherParams extreme = busy_params();  // stress: the most disorder the validator allows
  extreme.left.barbs = extreme.right.barbs = 2000;
  extreme.jitter = {30, 0.9};
  extreme.splits = {100, 5, 50, 1.0};
  extreme.afterfeather = {true, 1.0, 50, 50, 20, 5, 1};
  cases.push_back(extreme);
  for (const auto& p : cases) {
    const FeatherBuild b = build_feather_detailed(p, 5);
    ASSERT_EQ(b.paths.size() + 1, b.feather.curves.size());
    for (VaneSide side : {VaneSide::Left, VaneSide::Right}) {
      const BarbPath* prev = nullptr;
      int crossings = 0;
      for (const BarbPath& path : b.paths) {
        if (path.side != side) continue;
        ASSERT_EQ(int(path.uv.size()), p.barb.control_points);
        for (const auto& uv : path.uv) {
          EXPECT_GE(uv.x, 0.0);
          EXPECT_LE(uv.x, 1.0);
        }
        // Both polylines sample the same v stations, so strict order at every
        // station means the segments between them cannot cross either.
        if (prev)
          for (std::size_t j = 0; j < path.uv.size(); ++j) {
            ASSERT_EQ(path.uv[j].y, prev->uv[j].y);
            crossings += !(path.uv[j].x > prev->uv[j].x);
          }
        prev = &path;
      }
      EXPECT_EQ(crossings, 0) << p.name << " " << to_string(side);
    }
  }
}

TEST(Generator, BarbTipsFollowTheWidthProfile) {
  FeatherParams p = default_feather_params();
  p.left.width = Profile({{0, 4}, {0.3, 16}, {0.8, 10}, {1, 0}});
  p.right.width = Profile({{0, 8}, {0.5, 20}, {1, 0}});
  p.shaft.bend_deg = 20;
  p.surface.cupping = 0.25;  // the drop is along z; the width is measured in XY
  p.splits.count = 3;        // splits move tips along the edge, not off it
  p.jitter = {5, 0.5};
  for (const auto& params : {p, load_preset("rock-dove-wing")}) {
    FeatherParams q = params;
    q.shaft.arch_deg = 0;
    q.surface.twist_deg = 0;
    q.afterfeather.enabled = false;
    const Feather f = build_feather(q, 3);
    const BSpline3 shaft = spline_of(*f.shaft());
    const double L = arc_length_to(shaft, 1.0);
    double worst = 0;
    for (const Curve& c : f.curves) {
      if (c.kind != CurveKind::Barb) continue;
      const glm::dvec3 tip = spline_of(c).eval(1);
      const Closest cl = closest_point(shaft, tip, /*xy_only=*/true);
      const double x = (arc_length_to(shaft, cl.t) - q.shaft.calamus_length) / (L - q.shaft.calamus_length);
      const double expected = q.vane(c.side).width(x);
      worst = std::max(worst, std::abs(cl.distance - expected));
      // The tip is on its own side of the shaft.
      const glm::dvec3 t = shaft.deriv(cl.t);
      const double side = glm::cross(t, tip - shaft.eval(cl.t)).z;
      EXPECT_EQ(side < 0, c.side == VaneSide::Right);
    }
    EXPECT_LT(worst, 0.01 * q.shaft.length) << q.name;
  }
}

TEST(Generator, NormalsAreUnitAndOnTheLimitSurface) {
  auto cases = all_presets();
  cases.push_back(busy_params());
  for (const auto& p : cases) {
    const FeatherBuild b = build_feather_detailed(p, 9);
    double worst_n = 0, worst_p = 0, worst_tangent = 0;
    for (std::size_t k = 0; k < b.paths.size(); ++k) {
      const Curve& c = b.feather.curves[k + 1];
      const BarbPath& path = b.paths[k];
      const VaneSurface& s = b.surface(path.side);
      for (std::size_t j = 0; j < path.uv.size(); ++j) {
        const ControlPoint& cp = c.points[j + 1];  // skip the phantom end
        EXPECT_NEAR(glm::length(cp.n), 1.0, 1e-5);
        const auto smp = s.eval(path.uv[j].x, path.uv[j].y);
        worst_n = std::max(worst_n, glm::length(glm::dvec3(cp.n) - smp.n));
        if (!path.loose && j > 0) worst_p = std::max(worst_p, glm::length(glm::dvec3(cp.p) - smp.p));
        // The normal is perpendicular to the surface (central differences).
        const double h = 1e-4;
        const glm::dvec3 du = s.eval(path.uv[j].x + h, path.uv[j].y).p - s.eval(path.uv[j].x - h, path.uv[j].y).p;
        const glm::dvec3 dv = s.eval(path.uv[j].x, path.uv[j].y + h).p - s.eval(path.uv[j].x, path.uv[j].y - h).p;
        if (glm::length(du) > 1e-9 && glm::length(dv) > 1e-9 && path.uv[j].x + h < 1 && path.uv[j].x - h > 0 &&
            path.uv[j].y + h < 1 && path.uv[j].y - h > 0)
          worst_tangent = std::max({worst_tangent, std::abs(glm::dot(smp.n, glm::normalize(du))),
                                    std::abs(glm::dot(smp.n, glm::normalize(dv)))});
      }
    }
    EXPECT_LT(worst_n, 1e-5) << p.name;
    EXPECT_LT(worst_p, 1e-3) << p.name << ": barb control points must lie on the limit surface";
    EXPECT_LT(worst_tangent, 1e-3) << p.name;
  }
}

TEST(Generator, NormalsAreDorsalOnAFlatFeather) {
  FeatherParams p = default_feather_params();
  p.surface.cupping = 0.2;
  const Feather f = build_feather(p, 2);
  for (const Curve& c : f.curves)
    for (const ControlPoint& cp : c.points) EXPECT_GT(cp.n.z, 0.8f) << to_string(c.side);
}

TEST(Generator, SameSeedSameFeatherDifferentSeedDifferent) {
  const FeatherParams p = busy_params();
  const Feather a = build_feather(p, 42, "test"), b = build_feather(p, 42, "test"), c = build_feather(p, 43, "test");
  EXPECT_TRUE(a == b);
  EXPECT_FALSE(a == c);
  EXPECT_EQ(a.provenance.seed, std::optional<std::uint64_t>(42));
  EXPECT_EQ(a.provenance.source, "test");
  // A fixed split seed keeps the splits where they are when the feather seed changes.
  FeatherParams q = default_feather_params();
  q.splits = {2, 77, 4, 0.8};
  FeatherParams q_other_split = q;
  q_other_split.splits.seed = 78;
  EXPECT_TRUE(build_feather(q, 1).curves == build_feather(q, 2).curves);
  EXPECT_FALSE(build_feather(q, 1).curves == build_feather(q_other_split, 1).curves);
}

TEST(Generator, ExtremeParametersGiveFiniteGeometry) {
  FeatherParams p = default_feather_params();
  p.shaft = {2000, 1800, 90, -90, 20, 1e-4, 256};
  p.left.width = Profile({{0, 0}, {0.5, 4000}, {1, 0}});
  p.left.angle_deg = Profile({{0, 5}, {1, 90}});
  p.left.barb_bend_deg = 80;
  p.right.barbs = 2;
  p.right.width = Profile({{0, 1e-3}, {1, 1e-3}});
  p.surface = {1.0, 180, 4, 2};
  p.barb.control_points = 64;
  for (const FeatherParams& q : {p, [&] { auto r = p; r.shaft = {1, 0, -90, 90, 1e-4, 20, 4}; r.left.width = Profile({{0, 0}, {0.5, 2}, {1, 0}}); r.surface = {-1, -180, 256, 64}; return r; }()}) {
    const Feather f = build_feather(q, 0);
    EXPECT_NO_THROW(validate_feather(f));  // the .fcurves rules hold even here
    for (const Curve& c : f.curves)
      for (const ControlPoint& cp : c.points) {
        ASSERT_TRUE(std::isfinite(cp.p.x) && std::isfinite(cp.p.y) && std::isfinite(cp.p.z));
        ASSERT_NEAR(glm::length(cp.n), 1.0f, 1e-4f);
        ASSERT_GT(cp.radius, 0.0f);
      }
  }
}

TEST(Presets, TheThreeSpecimensLoadAndBuild) {
  const auto names = list_presets();
  for (const char* want : {"osprey-wing-covert", "turkey-vulture-back-covert", "rock-dove-wing"})
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
  for (const auto& n : names) {
    const FeatherParams p = load_preset(n);
    EXPECT_EQ(p.name, n);
    const Feather f = build_feather(p, 1, "preset:" + n);
    EXPECT_EQ(f.count(VaneSide::Left), std::size_t(p.barb_count(VaneSide::Left)));
    EXPECT_EQ(f.count(VaneSide::Right), std::size_t(p.barb_count(VaneSide::Right)));
    EXPECT_EQ(f.left, p.left.substructure);
    EXPECT_EQ(f.right, p.right.substructure);
    // Round trip through JSON keeps every parameter.
    EXPECT_TRUE(params_from_json(params_to_json(p)) == p) << n;
  }
  EXPECT_THROW(load_preset("ostrich"), Error);
  try {
    load_preset("osprey");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("osprey-wing-covert"), std::string::npos) << e.what();
  }
}

TEST(Generator, VaneSurfaceHugsTheShaft) {
  // The cage is fitted so that the limit surface passes through the intended
  // vane: its inner edge runs along the shaft centreline.
  for (const auto& p : all_presets()) {
    const FeatherBuild b = build_feather_detailed(p, 1);
    const BSpline3 shaft = spline_of(*b.feather.shaft());
    double worst = 0;
    for (VaneSide side : {VaneSide::Left, VaneSide::Right})
      for (int i = 0; i <= 50; ++i)
        worst = std::max(worst, closest_point(shaft, b.surface(side).eval(i / 50.0, 0).p).distance);
    EXPECT_LT(worst, 2e-3 * p.shaft.length) << p.name;
  }
}

TEST(Generator, RandomValidParametersKeepEveryInvariant) {
  // Stress: parameter sets drawn across the whole allowed ranges.
  Rng r(2024);
  for (int trial = 0; trial < 30; ++trial) {
    FeatherParams p = default_feather_params();
    p.shaft.length = r.uniform(1, 2000);
    p.shaft.calamus_length = r.uniform(0, 0.9) * p.shaft.length;
    p.shaft.bend_deg = r.uniform(-90, 90);
    p.shaft.arch_deg = r.uniform(-90, 90);
    p.shaft.radius_base = r.uniform(1e-4, 20);
    p.shaft.radius_tip = r.uniform(1e-4, 20);
    p.shaft.control_points = 4 + int(r.uniform() * 60);
    for (VaneParams* v : {&p.left, &p.right}) {
      v->barbs = 2 + int(r.uniform() * 150);
      std::vector<glm::dvec2> w{{0, r.uniform(0, 2 * p.shaft.length)}}, a{{0, r.uniform(5, 90)}};
      const int knots = int(r.uniform() * 4);
      for (int k = 1; k <= knots; ++k) {
        w.push_back({double(k) / (knots + 1), r.uniform(0, 2 * p.shaft.length)});
        a.push_back({double(k) / (knots + 1), r.uniform(5, 90)});
      }
      w.push_back({1, r.uniform(0, 2 * p.shaft.length)});
      a.push_back({1, r.uniform(5, 90)});
      if (w[1].y == 0) w[1].y = 1;
      v->width = Profile(w);
      v->angle_deg = Profile(a);
      v->barb_bend_deg = r.uniform(0, 80);
    }
    p.barb.control_points = 4 + int(r.uniform() * 20);
    p.surface = {r.uniform(-1, 1), r.uniform(-180, 180), 4 + int(r.uniform() * 40), 2 + int(r.uniform() * 10)};
    p.afterfeather = {r.uniform() < 0.5, r.uniform(0, 1),       r.uniform(0, 50),
                      r.uniform(0, 50),  r.uniform(0, 20),      r.uniform(0.001, 5),
                      r.uniform(0.01, 1)};
    p.splits = {int(r.uniform() * 10), std::nullopt, r.uniform(0, 50), r.uniform(0.01, 1)};
    p.jitter = {r.uniform(0, 30), r.uniform(0, 0.9)};
    ASSERT_NO_THROW(validate(p)) << trial;
    const FeatherBuild b = build_feather_detailed(p, trial);
    EXPECT_NO_THROW(validate_feather(b.feather)) << trial;
    EXPECT_EQ(b.feather.count(VaneSide::Left), std::size_t(p.left.barbs));
    EXPECT_EQ(b.feather.count(VaneSide::Right), std::size_t(p.right.barbs));
    const BSpline3 shaft = spline_of(*b.feather.shaft());
    for (std::size_t k = 0; k < b.paths.size(); ++k) {
      const Curve& c = b.feather.curves[k + 1];
      ASSERT_LT(closest_point(shaft, spline_of(c).eval(0)).distance, 1e-6 * p.shaft.length + 1e-3) << trial;
      if (k > 0 && b.paths[k - 1].side == b.paths[k].side) {
        for (std::size_t j = 0; j < b.paths[k].uv.size(); ++j)
          ASSERT_GT(b.paths[k].uv[j].x, b.paths[k - 1].uv[j].x) << trial << " barb " << k;
      }
    }
  }
}
