// Explicit mode (DESIGN §4, explicit_geometry.h): rami and barbules as real round
// curves, checked against the substructure technique they are the reference for —
// coverage of a ribbon, pointwise hit-or-miss and structure type against G_b, barbule
// tangents against Algorithm 2's frames, curve counts, degenerate parameters, and the
// CLI path (`--shading explicit`, `--stats`, `--aov structure`).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

#include "cli_run.h"
#include "one_barb.h"
#include "plumage/common/bspline.h"
#include "plumage/common/constants.h"
#include "plumage/common/curve_format.h"
#include "plumage/common/error.h"
#include "plumage/common/frame.h"
#include "plumage/renderer/explicit_geometry.h"
#include "plumage/renderer/fibre_frame.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/shading_mode.h"
#include "plumage/renderer/substructure.h"
#include "render_test_feather.h"

using namespace plumage;

namespace {


SubstructureParams params(int n, double theta_deg, double r_r, double r_b, double width, double phi_deg = 0,
                          double hooked = 0) {
  return test::substructure_params(n, theta_deg, r_r, r_b, width, phi_deg, hooked);
}
using test::down_at;
using test::one_barb;

// test::one_barb's curve starts at x0 and is kLength long.
constexpr double kX0 = -4.0 + 8.0 / 7.0;
constexpr double kLength = 8.0 * 5.0 / 7.0;

double angle_deg(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180 / kPi;
}

// The B-spline of fibre `f`: position and tangent at segment `seg`, local u.
struct CurveEval {
  glm::dvec3 p, dp;
};
CurveEval eval_fibre(const ExplicitBarbs& ex, const ExplicitFibre& f, std::size_t seg, double u) {
  const auto b = CubicBSplineBasis::eval(u);
  const auto db = CubicBSplineBasis::deriv(u);
  CurveEval e{glm::dvec3(0), glm::dvec3(0)};
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 cp(ex.control_points[f.first_cp + seg + std::size_t(i)]);
    e.p += b[i] * cp;
    e.dp += db[i] * cp;
  }
  return e;
}

struct Agreement {
  long compared = 0, agree = 0, hits = 0, structure_agree = 0;
};

// Top-down rays at random points (s, w) of the middle of the barb's ribbon: does
// explicit mode hit geometry exactly where G_b says the ribbon is not empty, and the
// same structure? Points within `band` (mm) of an edge of G_b's shapes, or of the
// ribbon's outer edge where barbules end in round caps, are left out.
Agreement pointwise(const SubstructureParams& p, VaneSide side, double band, int n) {
  const Feather f = one_barb(p, side);
  const Scene scene(f, SceneOptions{ShadingMode::Explicit, {}});
  const BarbSubstructure sub(p, side);
  const double half = 0.5 * p.ribbon_width;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> us(0.3 * kLength, 0.7 * kLength), uw(-half, half);
  Agreement a;
  for (int i = 0; i < n; ++i) {
    const double s = us(rng), w = uw(rng);
    const Structure gb = sub.classify(s, w, kLength).structure;
    bool edge = std::fabs(std::fabs(w) - half) < std::max(band, double(p.barbule_radius));
    for (const glm::dvec2 d : {glm::dvec2(band, 0), glm::dvec2(-band, 0), glm::dvec2(0, band), glm::dvec2(0, -band)})
      edge = edge || sub.classify(s + d.x, w + d.y, kLength).structure != gb;
    if (edge) continue;
    SurfaceHit h;
    const bool hit = scene.intersect(down_at(kX0 + s, w), h);
    ++a.compared;
    a.agree += hit == (gb != Structure::Empty);
    if (hit && gb != Structure::Empty) {
      ++a.hits;
      a.structure_agree += scene.explicit_fibre(h).structure == gb;
    }
  }
  return a;
}

std::string temp_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(getpid()));
  std::filesystem::create_directories(d);
  return d.string();
}

}  // namespace

TEST(ShadingMode, ParsesExplicit) {
  EXPECT_EQ(parse_shading_mode("explicit"), ShadingMode::Explicit);
  EXPECT_STREQ(to_string(ShadingMode::Explicit), "explicit");
  EXPECT_EQ(parse_shading_mode(to_string(ShadingMode::Substructure)), ShadingMode::Substructure);
  EXPECT_EQ(parse_shading_mode(to_string(ShadingMode::Hair)), ShadingMode::Hair);
  try {
    parse_shading_mode("explict");
    FAIL() << "a misspelt mode must throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'explicit'"), std::string::npos) << e.what();
  }
}

// The limit the two modes should meet: no lift, no hook. Every sampled point away
// from an edge agrees (>= 99 %, expected 100 %), on both vanes, for steep, shallow and
// perpendicular barbules.
TEST(ExplicitScene, HitsExactlyWhereGbIsNotEmpty) {
  for (VaneSide side : {VaneSide::Right, VaneSide::Left})
    for (const SubstructureParams& p : {params(40, 45, 0.04, 0.01, 0.4), params(25, 20, 0.02, 0.006, 0.3),
                                        params(60, 90, 0.03, 0.008, 0.35)}) {
      const Agreement a = pointwise(p, side, 0.25 * p.barbule_radius, 60000);
      const std::string what = std::string(to_string(side)) + " theta " + std::to_string(p.elevation_deg);
      ASSERT_GT(a.compared, 30000) << what;
      EXPECT_GE(double(a.agree) / a.compared, 0.99) << what;
      ASSERT_GT(a.hits, 1000) << what;
      EXPECT_GE(double(a.structure_agree) / a.hits, 0.99) << what;
    }
}

// With the presets' lift (phi_b 10°) and hooks (30 %) the explicit barbules leave
// G_b's straight footprint where they hook; agreement drops but stays high. The
// figure is measured, not assumed: it is the pointwise accuracy of the technique.
TEST(ExplicitScene, PresetLiftAndHookStillMostlyAgree) {
  const SubstructureParams p = params(40, 45, 0.04, 0.008, 0.4, 10, 0.3);
  const Agreement a = pointwise(p, VaneSide::Right, 0.25 * p.barbule_radius, 60000);
  EXPECT_GE(double(a.agree) / a.compared, 0.95);
  EXPECT_LT(double(a.agree) / a.compared, 0.999) << "the hooks should move some barbule area";
}

// Coverage of the ribbon from a top-down orthographic cast: the explicit geometry,
// the substructure ribbon and BarbSubstructure::covered_fraction agree within 1 %
// (relative) without lift and hook, and within 5 % with the presets' lift and hook.
TEST(ExplicitScene, CoverageMatchesSubstructureAndAnalyticFraction) {
  struct Case {
    SubstructureParams p;
    double tol;
  };
  for (const Case& c : {Case{params(40, 45, 0.04, 0.01, 0.4), 0.01}, Case{params(25, 30, 0.02, 0.006, 0.3), 0.01},
                        Case{params(40, 45, 0.04, 0.008, 0.4, 10, 0.3), 0.05}}) {
    const Feather f = one_barb(c.p);
    const Scene ex(f, SceneOptions{ShadingMode::Explicit, {}});
    const Scene sub(f, SceneOptions{ShadingMode::Substructure, {}});
    const double half = 0.5 * c.p.ribbon_width, period = kLength / c.p.barbules_per_side;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> us(0.5 * kLength - 10 * period, 0.5 * kLength + 10 * period),
        uw(-half, half);
    const int n = 200000;
    long hits_ex = 0, hits_sub = 0;
    for (int i = 0; i < n; ++i) {
      const Ray r = down_at(kX0 + us(rng), uw(rng));
      SurfaceHit h;
      hits_ex += ex.intersect(r, h);
      hits_sub += sub.intersect(r, h);
    }
    const double analytic = BarbSubstructure(c.p, VaneSide::Right).covered_fraction(kLength);
    EXPECT_NEAR(double(hits_ex) / n / analytic, 1.0, c.tol) << "explicit vs analytic, hook " << c.p.hooked_fraction;
    EXPECT_NEAR(double(hits_ex) / double(hits_sub), 1.0, c.tol) << "explicit vs substructure";
  }
}

// Each barbule leaves the ramus edge at s_k = (k + 1/2) L/N, along Algorithm 2's t_b
// (lift included), and its hook turns as BarbSubstructure::frame says, on a curved,
// cupped barb. Structure labels follow the vane's distal side.
TEST(ExplicitGeometry, BarbulesFollowAlgorithm2Frames) {
  for (VaneSide side : {VaneSide::Right, VaneSide::Left}) {
    const SubstructureParams p = params(12, 40, 0.04, 0.008, 0.36, 10, 0.3);
    const BarbSubstructure vane(p, side);
    Curve barb;
    barb.kind = CurveKind::Barb;
    barb.side = side;
    for (int i = 0; i < 7; ++i) {
      const float a = 0.25f * float(i);
      barb.points.push_back({{3.0f * std::sin(a), 3.0f * (1 - std::cos(a)), 0.1f * a * a}, 0.05f,
                             glm::normalize(glm::vec3(0.1f * a, -0.2f, 1.0f))});
    }
    ExplicitBarbs ex;
    add_explicit_barb(barb, 7, vane, ex);
    ASSERT_EQ(ex.fibres.size(), 1u + 2u * 12u);
    EXPECT_EQ(ex.fibres[0].structure, Structure::Ramus);

    std::vector<glm::dvec3> pts, nrm;
    for (const ControlPoint& cp : barb.points) {
      pts.emplace_back(cp.p);
      nrm.emplace_back(cp.n);
    }
    const BSpline3 spline(pts), normals(nrm);
    const ArcLengthTable table(spline);
    const double L = table.length();
    std::size_t fi = 1;
    for (int k = 0; k < 12; ++k) {
      const double t = table.t_at((k + 0.5) * L / 12);
      const Frame bf = frame_from_tangent_normal(glm::vec3(spline.deriv(t)), glm::vec3(normals.eval(t)));
      for (int side_i = 0; side_i < 2; ++side_i, ++fi) {
        const ExplicitFibre& f = ex.fibres[fi];
        EXPECT_EQ(f.barb, 7u);
        // The barbule's line crosses the ramus edge (|w| = r_r) at s_k; it starts inside the ramus.
        const glm::dvec3 base = eval_fibre(ex, f, 0, 0).p - spline.eval(t);
        const double w0 = glm::dot(base, glm::dvec3(bf.b));
        EXPECT_LT(std::fabs(w0), p.ramus_radius) << "starts inside the ramus";
        const double w = w0 > 0 ? 1 : -1;
        const bool distal = w * vane.distal_sign() > 0;
        ASSERT_EQ(f.structure, distal ? Structure::Distal : Structure::Proximal);
        StructureHit hit;
        hit.structure = f.structure;
        const glm::dvec3 tb(vane.frame(bf, hit, w).t);
        const glm::dvec3 at_edge = base + (w * p.ramus_radius - w0) / glm::dot(tb, glm::dvec3(bf.b)) * tb;
        EXPECT_NEAR(glm::dot(at_edge, glm::dvec3(bf.t)), 0.0, 1e-5) << "crosses the ramus edge at s_k";
        EXPECT_LT(angle_deg(eval_fibre(ex, f, 0, 0.5).dp, tb), 0.5) << "straight part along t_b";
        // The end: W/2 from the centreline across the vane.
        const glm::dvec3 end = eval_fibre(ex, f, f.segments() - 1, 1.0).p;
        EXPECT_NEAR(std::fabs(glm::dot(end - spline.eval(t), glm::dvec3(bf.b))), 0.5 * p.ribbon_width, 2e-3);
        if (!distal) {
          EXPECT_EQ(f.segments(), 1u) << "proximal barbules have no hook";
          continue;
        }
        ASSERT_EQ(f.segments(), std::size_t(1 + kHookSegments));
        // The curve passes the hook's interior points with the tangent the hook has there.
        for (int j = 1; j < kHookSegments; ++j) {
          hit.hook = float(j) / kHookSegments;
          const glm::dvec3 tj(vane.frame(bf, hit, w).t);
          EXPECT_LT(angle_deg(eval_fibre(ex, f, std::size_t(j + 1), 0).dp, tj), 2.0) << "hook " << hit.hook;
        }
      }
    }
  }
}

TEST(ExplicitGeometry, CurveCountsAndBytes) {
  const Feather f = [] {
    Feather t = test::make_test_feather(20.0f, 1.0f);
    t.left = params(30, 45, 0.04, 0.008, 0.4, 10, 0.3);
    t.right = params(50, 45, 0.04, 0.008, 0.4, 10, 0.3);
    return t;
  }();
  const std::size_t left = f.count(VaneSide::Left), right = f.count(VaneSide::Right);
  EXPECT_EQ(explicit_curve_count(f), left * 61 + right * 101);
  const Scene scene(f, SceneOptions{ShadingMode::Explicit, {}});
  EXPECT_EQ(scene.explicit_curves(), explicit_curve_count(f));
  // Control points: ramus as the barb, 4 per proximal, 4 + kHookSegments per distal barbule.
  std::size_t cps = 0, segs = 0;
  for (const Curve& c : f.curves)
    if (c.kind == CurveKind::Barb) {
      const std::size_t n = std::size_t(f.substructure(c.side).barbules_per_side);
      cps += c.points.size() + n * 4 + n * (4 + kHookSegments);
      segs += c.points.size() - 3 + n * 1 + n * (1 + kHookSegments);
    }
  EXPECT_EQ(scene.explicit_bytes(), cps * 16 + segs * 4);
}

// N = 0, r_b = 0, theta_b at its minimum and at 90°, hooked fraction 0 and 1: finite
// control points, a scene that builds, and finite round-fibre frames at every hit.
TEST(ExplicitScene, DegenerateParametersGiveNoNaN) {
  const double min_theta = BarbSubstructure::kMinElevationDeg;
  for (const SubstructureParams& p :
       {params(0, 45, 0.04, 0.01, 0.4), params(40, 45, 0.04, 0, 0.4), params(40, min_theta, 0.04, 0.01, 0.4, 10, 0.3),
        params(40, 90, 0.04, 0.01, 0.4, 89.9, 1), params(40, 45, 0.04, 0.01, 0.4, -30, 1),
        params(40, 45, 0.2, 0.01, 0.4, 0, 0.5), params(1, 45, 0.04, 0.3, 0.4, 0, 1)}) {
    const Feather f = one_barb(p);
    ExplicitBarbs ex;
    add_explicit_barb(f.curves[0], 0, BarbSubstructure(p, VaneSide::Right), ex);
    const bool barbules = p.barbules_per_side > 0 && p.barbule_radius > 0 && p.ramus_radius < 0.5f * p.ribbon_width;
    EXPECT_EQ(ex.fibres.size(), barbules ? 1u + 2u * std::size_t(p.barbules_per_side) : 1u);
    for (const glm::vec4& cp : ex.control_points)
      ASSERT_TRUE(std::isfinite(cp.x) && std::isfinite(cp.y) && std::isfinite(cp.z) && std::isfinite(cp.w))
          << p.elevation_deg << " " << p.hooked_fraction;
    const Scene scene(f, SceneOptions{ShadingMode::Explicit, {}});
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(-3, 3), uy(-0.5, 0.5);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
      SurfaceHit h;
      const Ray r = down_at(ux(rng), uy(rng));
      if (!scene.intersect(r, h)) continue;
      ++hits;
      const CurvePoint cp = scene.curve_point(h);
      const FibreFrame ff = round_fibre_frame(cp.dp, -r.d, cp.p, cp.radius, h.p);
      ASSERT_TRUE(std::isfinite(ff.h) && std::isfinite(ff.frame.t.x) && std::isfinite(ff.frame.b.y));
    }
    EXPECT_GT(hits, 0);
  }
}

// A top-down ray onto the ramus at w = r_r / 2 lands on a round curve of radius r_r,
// so the round-fibre frame gives h = 1/2 (Embree's v is 0 on round curves).
TEST(ExplicitScene, RoundFibreOffsetFromTheHit) {
  const SubstructureParams p = params(40, 45, 0.04, 0.01, 0.4);
  const Scene scene(one_barb(p), SceneOptions{ShadingMode::Explicit, {}});
  for (double w : {-0.02, 0.02, 0.03}) {
    SurfaceHit h;
    const Ray r = down_at(0.0, w);
    ASSERT_TRUE(scene.intersect(r, h));
    EXPECT_EQ(h.kind, HitKind::Barb);
    EXPECT_EQ(h.curve, 0u);
    EXPECT_EQ(scene.explicit_fibre(h).structure, Structure::Ramus);
    const CurvePoint cp = scene.curve_point(h);
    EXPECT_NEAR(cp.radius, p.ramus_radius, 1e-6);
    EXPECT_NEAR(h.p.z, std::sqrt(0.04 * 0.04 - w * w), 1e-4) << "a round ramus, not a ribbon";
    EXPECT_NEAR(std::fabs(round_fibre_frame(cp.dp, -r.d, cp.p, cp.radius, h.p).h), w / 0.04 * (w > 0 ? 1 : -1), 1e-3);
  }
}

TEST(ExplicitScene, BadParametersNameTheMode) {
  Feather f = one_barb(params(40, 0.5, 0.04, 0.01, 0.4));
  try {
    Scene s(f, SceneOptions{ShadingMode::Explicit, {}});
    FAIL() << "theta_b below the minimum must throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--shading explicit"), std::string::npos) << e.what();
  }
  f = one_barb(params(40, 45, 0.04, 0.01, 0.4));
  f.curves[0].side = VaneSide::None;
  EXPECT_THROW(Scene(f, SceneOptions{ShadingMode::Explicit, {}}), Error);
}

TEST(ExplicitCli, RenderWithStatsAndStructureAov) {
  const std::string dir = temp_dir("plumage_explicit_cli");
  Feather f = test::make_test_feather(12.0f, 1.0f);
  f.left = f.right = params(20, 45, 0.04, 0.008, 0.4, 10, 0.3);
  write_fcurves(dir + "/f.fcurves", f);
  auto r = test::plumage_cli("-q --stats render " + dir + "/f.fcurves --shading explicit --spp 1 --resolution 32x32 -o " +
                             dir + "/e.png");
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/e.png"));
  EXPECT_NE(r.output.find("Curves built (rami and barbules)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(std::to_string(explicit_curve_count(f))), std::string::npos) << r.output;
  r = test::plumage_cli("render " + dir + "/f.fcurves --shading explicit --aov structure --resolution 32x32 -o " + dir +
                        "/s.png");
  EXPECT_EQ(r.rc, 0) << r.output;
  r = test::plumage_cli("render " + dir + "/f.fcurves --shading explicit --barbule-elevation 0.2 -o " + dir + "/bad.png");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.output.find("--barbule-elevation"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.png"));
  std::filesystem::remove_all(dir);
}

// `plumage bench --reference-mode explicit`: every mode against one explicit
// reference, no slope check (errors level off at the model error by design).
TEST(ExplicitCli, BenchAgainstTheExplicitReference) {
  const std::string dir = temp_dir("plumage_explicit_bench");
  Feather f = test::make_test_feather(12.0f, 1.0f);
  f.left = f.right = params(20, 45, 0.04, 0.008, 0.4, 10, 0.3);
  write_fcurves(dir + "/f.fcurves", f);
  const std::string common = "bench --quiet " + dir + "/f.fcurves --resolution 8x12 --spp 1,2 --reference-spp 8 " +
                             "--modes hair,substructure --csv " + dir + "/l.csv --plot " + dir + "/l.png";
  auto r = test::plumage_cli(common + " --reference-mode explicit --zoom 3,6,2");
  ASSERT_EQ(r.rc, 0) << r.output;
  std::ifstream csv(dir + "/l.csv");
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) rows += line.rfind("hair,", 0) == 0 || line.rfind("substructure,", 0) == 0;
  EXPECT_EQ(rows, 4);
  r = test::plumage_cli(common + " --reference-mode explicit --zoom 3,6");
  EXPECT_EQ(r.rc, 2);  // a usage error
  EXPECT_NE(r.output.find("--zoom: '3,6'"), std::string::npos) << r.output;
  r = test::plumage_cli(common + " --reference-mode explict");
  EXPECT_EQ(r.rc, 2);  // a usage error, caught before anything renders
  EXPECT_NE(r.output.find("--reference-mode: 'explict' is not one of: hair, substructure, explicit"), std::string::npos)
      << r.output;
  std::filesystem::remove_all(dir);
}
