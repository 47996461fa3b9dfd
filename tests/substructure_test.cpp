// The substructure technique (Baron et al. 2021 §5.3, DESIGN §5): G_b against an
// independent drawing of the ramus and barbules, the barbule frames of Algorithm 2,
// parameter limits, and the technique inside Embree: gaps pass rays and shadows,
// the covered fraction of a ribbon, energy conservation, hair mode untouched.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "plumage/common/bspline.h"
#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/common/stats.h"
#include "plumage/renderer/path_integrator.h"
#include "plumage/renderer/render.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/substructure.h"
#include "furnace.h"
#include "one_barb.h"
#include "render_test_feather.h"

using namespace plumage;

namespace {


SubstructureParams params(int n, double theta_deg, double r_r, double r_b, double width, double phi_deg = 0,
                          double hooked = 0.3) {
  return test::substructure_params(n, theta_deg, r_r, r_b, width, phi_deg, hooked);
}
using test::down_at;
using test::one_barb;

// The explicit shapes of DESIGN §5 drawn as geometry, without G_b's periodic
// arithmetic: the ramus is the band |w| <= r_r; barbule k on side sigma is a
// straight strip of half-width r_b around the line leaving the ramus edge at
// (s_k, sigma r_r) in direction (+-cos theta, sigma sin theta), clipped to the
// band between the ramus and the ribbon's edge. `margin` is the distance to the
// nearest boundary, so pixels on an edge can be left out.
struct Drawn {
  Structure s;
  double margin;
};
Drawn draw_explicit(double s, double w, double L, const SubstructureParams& p, VaneSide side) {
  const double half = 0.5 * p.ribbon_width;
  const double aw = std::fabs(w);
  double margin = std::fabs(aw - half);
  if (aw > half) return {Structure::Empty, margin};
  margin = std::min(margin, std::fabs(aw - p.ramus_radius));
  if (aw <= p.ramus_radius) return {Structure::Ramus, margin};
  const double sigma = w > 0 ? 1 : -1;
  const bool distal = (side == VaneSide::Right) == (sigma > 0);
  const double th = p.elevation_deg * kPi / 180;
  const glm::dvec2 dir((distal ? 1 : -1) * std::cos(th), sigma * std::sin(th));
  const double period = L / p.barbules_per_side;
  const int extra = int(std::ceil(half / std::tan(th) / period)) + 2;
  Structure found = Structure::Empty;
  for (int k = -extra; k < p.barbules_per_side + extra; ++k) {
    const glm::dvec2 a((k + 0.5) * period, sigma * p.ramus_radius);
    const glm::dvec2 q = glm::dvec2(s, w) - a;
    const double dist = std::fabs(q.x * dir.y - q.y * dir.x);  // |cross|: distance to the line
    margin = std::min(margin, std::fabs(dist - p.barbule_radius));
    if (dist <= p.barbule_radius) found = distal ? Structure::Distal : Structure::Proximal;
  }
  return {found, margin};
}

Frame random_barb_frame(std::mt19937& rng) {
  std::normal_distribution<float> g;
  return frame_from_tangent_normal({g(rng), g(rng), g(rng)}, {g(rng), g(rng), g(rng)});
}

void expect_orthonormal_right_handed(const Frame& f, const std::string& what) {
  EXPECT_NEAR(glm::length(f.t), 1.0f, 1e-5f) << what;
  EXPECT_NEAR(glm::length(f.b), 1.0f, 1e-5f) << what;
  EXPECT_NEAR(glm::length(f.n), 1.0f, 1e-5f) << what;
  EXPECT_NEAR(glm::dot(f.t, f.b), 0.0f, 1e-5f) << what;
  EXPECT_NEAR(glm::dot(f.t, f.n), 0.0f, 1e-5f) << what;
  EXPECT_NEAR(glm::dot(f.b, f.n), 0.0f, 1e-5f) << what;
  EXPECT_NEAR(glm::dot(glm::cross(f.n, f.t), f.b), 1.0f, 1e-5f) << what << " (b = n x t)";
}

}  // namespace

TEST(Substructure, GeometricTermMatchesExplicitShapes) {
  const double L = 2.0;
  const SubstructureParams cases[] = {
      params(8, 45, 0.03, 0.01, 0.4), params(12, 30, 0.05, 0.008, 0.5), params(6, 70, 0.02, 0.02, 0.3),
      params(20, 15, 0.04, 0.005, 0.45), params(5, 90, 0.03, 0.015, 0.4)};
  for (const SubstructureParams& p : cases)
    for (VaneSide side : {VaneSide::Left, VaneSide::Right}) {
      const BarbSubstructure sub(p, side);
      const int ns = 1500, nw = 400;
      const double ds = L / ns, dw = p.ribbon_width / nw;
      const double edge = 2 * std::hypot(ds, dw);
      long compared = 0, agree = 0, seen[4] = {0, 0, 0, 0};
      for (int j = 0; j < nw; ++j)
        for (int i = 0; i < ns; ++i) {
          const double s = (i + 0.5) * ds, w = -0.5 * p.ribbon_width + (j + 0.5) * dw;
          const Drawn d = draw_explicit(s, w, L, p, side);
          if (d.margin < edge) continue;
          ++compared;
          const Structure g = sub.classify(s, w, L).structure;
          agree += g == d.s;
          ++seen[int(d.s)];
        }
      const std::string what = "N=" + std::to_string(p.barbules_per_side) + " theta=" + std::to_string(p.elevation_deg) +
                               (side == VaneSide::Left ? " left" : " right");
      ASSERT_GT(compared, ns * nw / 2) << what;
      EXPECT_GE(double(agree) / double(compared), 0.999) << what;
      // Every kind of structure was there to be compared.
      for (long k : seen) EXPECT_GT(k, 100) << what;
    }
}

TEST(Substructure, DistalSideDependsOnTheVane) {
  const SubstructureParams p = params(10, 45, 0.03, 0.02, 0.4);
  const BarbSubstructure left(p, VaneSide::Left), right(p, VaneSide::Right);
  // Right vane: +b points toward the feather's tip (DESIGN §3), so +w is distal.
  EXPECT_GT(right.distal_sign(), 0);
  EXPECT_LT(left.distal_sign(), 0);
  int distal_right = 0, distal_left = 0;
  for (int i = 0; i < 2000; ++i) {
    const double s = 2.0 * i / 2000.0;
    distal_right += right.classify(s, 0.1, 2.0).structure == Structure::Distal;
    distal_left += left.classify(s, -0.1, 2.0).structure == Structure::Distal;
    EXPECT_NE(right.classify(s, -0.1, 2.0).structure, Structure::Distal);
    EXPECT_NE(left.classify(s, 0.1, 2.0).structure, Structure::Distal);
  }
  EXPECT_GT(distal_right, 100);
  EXPECT_GT(distal_left, 100);
}

TEST(Substructure, HIsOffsetAcrossTheStructure) {
  const SubstructureParams p = params(10, 45, 0.05, 0.02, 0.4);
  const BarbSubstructure sub(p, VaneSide::Right);
  EXPECT_NEAR(sub.classify(1.0, 0.025, 2.0).h, 0.5f, 1e-6f);
  EXPECT_NEAR(sub.classify(1.0, -0.05, 2.0).h, -1.0f, 1e-6f);
  for (int i = 0; i < 5000; ++i) {
    const StructureHit h = sub.classify(2.0 * i / 5000.0, 0.12, 2.0);
    if (h.structure != Structure::Empty) {
      EXPECT_GE(h.h, -1.0f);
      EXPECT_LE(h.h, 1.0f);
    }
  }
}

TEST(Substructure, FramesOrthonormalAndRightHanded) {
  std::mt19937 rng(7);
  for (double theta : {1.0, 5.0, 30.0, 45.0, 60.0, 89.0, 90.0})
    for (double phi : {-80.0, -10.0, 0.0, 10.0, 45.0, 89.0})
      for (VaneSide side : {VaneSide::Left, VaneSide::Right}) {
        const BarbSubstructure sub(params(10, theta, 0.03, 0.01, 0.4, phi, 0.5), side);
        for (Structure st : {Structure::Ramus, Structure::Distal, Structure::Proximal})
          for (float hook : {0.0f, 0.3f, 1.0f})
            for (double w : {-0.1, 0.1}) {
              const Frame barb = random_barb_frame(rng);
              const Frame f = sub.frame(barb, {st, 0.0f, hook}, w);
              expect_orthonormal_right_handed(f, "theta " + std::to_string(theta) + " phi " + std::to_string(phi));
            }
      }
}

TEST(Substructure, BarbuleTangentFollowsElevationAndAzimuth) {
  const Frame barb{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const BarbSubstructure flat(params(10, 30, 0.03, 0.01, 0.4, 0, 0.0), VaneSide::Right);
  // Elevation: the angle from t in the vane plane, toward the barbule's side.
  const Frame d0 = flat.frame(barb, {Structure::Distal, 0, 0}, 0.1);
  EXPECT_NEAR(std::atan2(d0.t.y, d0.t.x) * 180 / kPi, 30.0, 1e-3);
  EXPECT_NEAR(std::atan2(flat.frame(barb, {Structure::Distal, 0, 0}, -0.1).t.y, d0.t.x) * 180 / kPi, -30.0, 1e-3);
  // Azimuth: a rotation about b by phi keeps the b component and lifts the t part toward n.
  const BarbSubstructure sub(params(10, 30, 0.03, 0.01, 0.4, 20, 0.0), VaneSide::Right);
  const Frame d = sub.frame(barb, {Structure::Distal, 0, 0}, 0.1);
  const double c30 = std::cos(kPi / 6), s30 = 0.5, c20 = std::cos(kPi / 9), s20 = std::sin(kPi / 9);
  EXPECT_NEAR(d.t.x, c30 * c20, 1e-5);
  EXPECT_NEAR(d.t.y, s30, 1e-5);
  EXPECT_NEAR(d.t.z, c30 * s20, 1e-5);
  // Proximal barbules point back toward the barb's root.
  const Frame pr = sub.frame(barb, {Structure::Proximal, 0, 0}, -0.1);
  EXPECT_LT(pr.t.x, 0);
  EXPECT_LT(pr.t.y, 0);
  // The ramus keeps the barb's frame.
  const Frame r = sub.frame(barb, {Structure::Ramus, 0, 0}, 0.0);
  EXPECT_EQ(r.t, barb.t);
}

TEST(Substructure, HookRotationIsContinuousWhereItStarts) {
  const double L = 2.0;
  const SubstructureParams p = params(10, 45, 0.05, 0.05, 0.45, 10, 0.4);
  const BarbSubstructure sub(p, VaneSide::Right);
  const Frame barb{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  // Walk out along a distal barbule's centreline (s shifts by d cot theta).
  const double band = 0.5 * p.ribbon_width - p.ramus_radius;
  const double d_start = (1.0 - p.hooked_fraction) * band;
  auto frame_at = [&](double d) {
    const double s = 0.5 * L / p.barbules_per_side + 0.2 + d;  // cot 45 = 1; base at a barbule
    const double s0 = std::round((s - d) / (L / p.barbules_per_side) - 0.5) * (L / p.barbules_per_side) +
                      0.5 * L / p.barbules_per_side + d;
    const StructureHit h = sub.classify(s0, p.ramus_radius + d, L);
    EXPECT_EQ(h.structure, Structure::Distal) << d;
    return std::pair{h, sub.frame(barb, h, p.ramus_radius + d)};
  };
  const auto [h_before, f_before] = frame_at(d_start - 1e-6);
  const auto [h_after, f_after] = frame_at(d_start + 1e-6);
  EXPECT_EQ(h_before.hook, 0.0f);
  EXPECT_LT(h_after.hook, 1e-4f);
  EXPECT_NEAR(glm::dot(f_before.t, f_after.t), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::dot(f_before.b, f_after.b), 1.0f, 1e-5f);
  // At the tip the hook has turned the barbule by pi/2 about n.
  const auto [h_tip, f_tip] = frame_at(band - 1e-9);
  EXPECT_NEAR(h_tip.hook, 1.0f, 1e-5f);
  // Only t's in-vane part turns: what is left of the dot product is the lift, squared.
  EXPECT_NEAR(glm::dot(f_before.t, f_tip.t), f_before.t.z * f_before.t.z, 1e-5f);
  EXPECT_NEAR(f_before.t.z, f_tip.t.z, 1e-5f);  // a turn about n keeps the lift
}

TEST(Substructure, ElevationLimitsAndBadParameters) {
  EXPECT_THROW(BarbSubstructure(params(10, 0.0, 0.03, 0.01, 0.4), VaneSide::Left), Error);
  EXPECT_THROW(BarbSubstructure(params(10, 0.5, 0.03, 0.01, 0.4), VaneSide::Left), Error);
  EXPECT_THROW(BarbSubstructure(params(10, 90.5, 0.03, 0.01, 0.4), VaneSide::Left), Error);
  EXPECT_THROW(BarbSubstructure(params(10, NAN, 0.03, 0.01, 0.4), VaneSide::Left), Error);
  EXPECT_THROW(BarbSubstructure(params(10, 45, 0.3, 0.01, 0.4), VaneSide::Left), Error);   // ramus wider than ribbon
  EXPECT_THROW(BarbSubstructure(params(10, 45, 0.03, 0.01, 0.0), VaneSide::Left), Error);  // no ribbon
  EXPECT_THROW(BarbSubstructure(params(-1, 45, 0.03, 0.01, 0.4), VaneSide::Left), Error);
  EXPECT_THROW(BarbSubstructure(params(10, 45, 0.03, 0.01, 0.4, 90), VaneSide::Left), Error);
  EXPECT_THROW(BarbSubstructure(params(10, 45, 0.03, 0.01, 0.4, 0, 1.5), VaneSide::Left), Error);
  EXPECT_THROW(BarbSubstructure(params(10, 45, 0.03, 0.01, 0.4), VaneSide::None), Error);
  try {
    BarbSubstructure(params(10, 0.2, 0.03, 0.01, 0.4), VaneSide::Left, "feather.fcurves");
    FAIL();
  } catch (const Error& e) {
    // The library names the setting, as the curve file does; only the CLI names flags.
    EXPECT_NE(std::string(e.what()).find("elevation: value 0.2 is outside [1, 90]"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("feather.fcurves"), std::string::npos) << e.what();
  }
  // At the limits the result is defined: theta 1 and 90 degrees classify finite points.
  for (double theta : {1.0, 90.0}) {
    const BarbSubstructure sub(params(50, theta, 0.03, 0.004, 0.4), VaneSide::Right);
    double covered = 0;
    const int n = 400000;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> us(0, 2.0), uw(-0.2, 0.2);
    for (int i = 0; i < n; ++i) {
      const StructureHit h = sub.classify(us(rng), uw(rng), 2.0);
      ASSERT_TRUE(std::isfinite(h.h));
      covered += h.structure != Structure::Empty;
    }
    EXPECT_NEAR(covered / n, sub.covered_fraction(2.0), 0.01) << theta;
  }
  // Extreme inputs: NaN and huge offsets are empty, not a crash.
  const BarbSubstructure sub(params(10, 45, 0.03, 0.01, 0.4), VaneSide::Right);
  EXPECT_EQ(sub.classify(NAN, 0.1, 2.0).structure, Structure::Empty);
  EXPECT_EQ(sub.classify(1.0, NAN, 2.0).structure, Structure::Empty);
  const Structure far = sub.classify(1e30, 0.1, 2.0).structure;
  EXPECT_TRUE(far == Structure::Empty || far == Structure::Distal);
  EXPECT_EQ(sub.classify(1.0, 0.1, 0.0).structure, Structure::Empty);
}

TEST(SubstructureScene, CoveredFractionOfARibbonMatchesAnalyticValue) {
  for (const SubstructureParams& p : {params(40, 45, 0.04, 0.01, 0.4), params(25, 30, 0.02, 0.006, 0.3)}) {
    const Feather f = one_barb(p);
    SceneOptions so;
    so.mode = ShadingMode::Substructure;
    const Scene scene(f, so);
    // The straight barb's arc length runs with x; sample whole barbule periods in the middle.
    const BSpline3 c([&] {
      std::vector<glm::dvec3> pts;
      for (const auto& cp : f.curves[0].points) pts.emplace_back(cp.p);
      return pts;
    }());
    const double L = arc_length(c);
    const double period = L / p.barbules_per_side;
    const double x0 = -10 * period, x1 = 10 * period, half = 0.5 * p.ribbon_width;
    // Uniform random rays: a regular grid would alias with the ramus' edges.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> ux(x0, x1), uy(-half, half);
    const int n = 320000;
    long hits = 0;
    for (int i = 0; i < n; ++i) {
      SurfaceHit h;
      hits += scene.intersect(down_at(float(ux(rng)), float(uy(rng))), h);
    }
    const double analytic = BarbSubstructure(p, VaneSide::Right).covered_fraction(L);
    EXPECT_NEAR(double(hits) / n / analytic, 1.0, 0.01);
  }
}

TEST(SubstructureScene, RayThroughAGapReturnsTheBackdropExactly) {
  const SubstructureParams p = params(10, 45, 0.04, 0.01, 0.4);
  const Feather f = one_barb(p);
  SceneOptions so;
  so.mode = ShadingMode::Substructure;
  so.backdrop = {true, glm::vec3(0.8f)};
  const Scene with_barb(f, so);
  // Find a gap and a ramus point on the ribbon, through the scene's own mapping.
  const StructureSample probe = [&] {
    SurfaceHit h;
    EXPECT_TRUE(with_barb.intersect(down_at(0, 0.1f), h, true));
    return with_barb.structure_at(h);
  }();
  ASSERT_NEAR(probe.w, 0.1, 1e-4);
  float gap_x = 0;
  bool found = false;
  for (int i = 0; i < 1000 && !found; ++i) {
    const float x = -0.2f + 0.4f * float(i) / 1000.0f;
    SurfaceHit h;
    if (!with_barb.intersect(down_at(x, 0.1f), h, true) || h.kind != HitKind::Barb) continue;
    const StructureSample ss = with_barb.structure_at(h);
    // Well inside a gap: empty here and 3 barbule radii either side along the barb.
    bool wide = ss.hit.structure == Structure::Empty;
    for (float dx : {-0.03f, 0.03f}) {
      SurfaceHit h2;
      wide = wide && with_barb.intersect(down_at(x + dx, 0.1f), h2, true) && h2.kind == HitKind::Barb &&
             with_barb.structure_at(h2).hit.structure == Structure::Empty;
    }
    if (wide) {
      gap_x = x;
      found = true;
    }
  }
  ASSERT_TRUE(found);

  SurfaceHit h;
  ASSERT_TRUE(with_barb.intersect(down_at(gap_x, 0.1f), h));
  EXPECT_EQ(h.kind, HitKind::Backdrop);
  EXPECT_FLOAT_EQ(h.p.z, with_barb.backdrop_z());

  // Lit straight from above, with direct light only: the pixel is exactly the
  // backdrop's radiance, as if the barb were not there (no shading, same samples).
  LightSet lights;
  lights.add(DirectionalLight{{0, 0, 1}, glm::vec3(2.0f)});
  HairParams hp;
  const FibreMaterial material(hp);
  const PathIntegrator integrator(with_barb, lights, material, IntegratorSettings{1, 3});
  PixelSampler sampler(SamplerKind::Independent, 5);
  sampler.start(0, 0, 0);
  sampler.next4();
  PathCounters counters;
  const glm::vec3 L = integrator.Li(down_at(gap_x, 0.1f), sampler, counters);
  const glm::vec3 expected = glm::vec3(0.8f) / float(std::numbers::pi) * 2.0f;
  EXPECT_FLOAT_EQ(L.x, expected.x);
  EXPECT_FLOAT_EQ(L.y, expected.y);
  EXPECT_FLOAT_EQ(L.z, expected.z);
  EXPECT_EQ(counters.rays, 2);  // the camera ray and the path's continuation: no re-trace at the gap
}

TEST(SubstructureScene, ShadowRaysPassGapsButNotTheRamus) {
  const SubstructureParams p = params(10, 45, 0.04, 0.01, 0.4);
  SceneOptions so;
  so.mode = ShadingMode::Substructure;
  const Scene scene(one_barb(p), so);
  int gaps = 0, blocked = 0;
  for (int i = 0; i < 400; ++i) {
    const float x = -0.5f + float(i) / 400.0f;
    for (float y : {0.0f, 0.15f}) {
      SurfaceHit h;
      ASSERT_TRUE(scene.intersect(down_at(x, y), h, true));
      const Structure st = scene.structure_at(h).hit.structure;
      // A shadow ray from below, up through the ribbon toward a light above.
      Ray up;
      up.o = {x, y, -5};
      up.d = {0, 0, 1};
      up.tfar = 20;
      const bool occ = scene.occluded(up);
      EXPECT_EQ(occ, st != Structure::Empty) << x << " " << y << " " << to_string(st);
      gaps += !occ;
      blocked += occ;
      if (y == 0.0f) {
        EXPECT_EQ(st, Structure::Ramus);
      }
    }
  }
  EXPECT_GT(gaps, 50);
  EXPECT_GT(blocked, 400);
}

TEST(SubstructureScene, GapRejectionsAreCounted) {
  SceneOptions so;
  so.mode = ShadingMode::Substructure;
  const Scene scene(one_barb(params(10, 45, 0.04, 0.01, 0.4)), so);
  const auto before = stats_snapshot()["Substructure/Candidate hits rejected in gaps"];
  int misses = 0;
  for (int i = 0; i < 200; ++i) {
    SurfaceHit h;
    misses += !scene.intersect(down_at(-0.5f + float(i) / 200.0f, 0.15f), h);
  }
  const auto after = stats_snapshot()["Substructure/Candidate hits rejected in gaps"];
  EXPECT_GT(misses, 10);
  EXPECT_GE(after - before, double(misses));
}

// With no absorption the hair BCSDF conserves energy, so under a uniform white
// environment a substructure feather can only pass on what it receives: every
// pixel's mean stays at most 1 (within the Monte Carlo error) and most light
// that enters the ribbons comes back out.
TEST(SubstructureScene, FurnaceNoMoreEnergyOutThanIn) {
  Feather f = test::make_test_feather(12.0f, 0.4f, 0.05f);
  f.left = f.right = params(30, 40, 0.04, 0.012, 0.3, 10, 0.3);
  SceneOptions so;
  so.mode = ShadingMode::Substructure;
  const Scene scene(f, so);
  const Camera camera = test::furnace_camera(scene);
  int on_barbs = 0;
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 12; ++x) {
      SurfaceHit h;
      on_barbs += scene.intersect(camera.generate(x + 0.5f, y + 0.5f), h) && h.kind == HitKind::Barb;
    }
  ASSERT_GT(on_barbs, 40) << "the view must show barbs for the test to mean anything";
  test::expect_furnace(scene, 0.9);
}

// Hair mode never runs substructure code: parameters that substructure mode
// rejects do not matter to it, and nothing is rejected in gaps.
TEST(SubstructureScene, HairModeIgnoresSubstructure) {
  Feather f = one_barb(params(10, 0.0, 0.0, 0.0, 0.0));  // unusable for substructure
  SceneOptions so;
  EXPECT_THROW(Scene(f, SceneOptions{ShadingMode::Substructure, {}}), Error);
  const Scene hair(f, so);
  const auto before = stats_snapshot()["Substructure/Candidate hits rejected in gaps"];
  int hits = 0;
  for (int i = 0; i < 100; ++i) {
    SurfaceHit h;
    hits += hair.intersect(down_at(-0.5f + float(i) / 100.0f, 0.0f), h);
  }
  EXPECT_EQ(hits, 100);
  EXPECT_EQ(stats_snapshot()["Substructure/Candidate hits rejected in gaps"], before);
}

TEST(SubstructureScene, BarbWithoutVaneIsAnError) {
  Feather f = one_barb(params(10, 45, 0.04, 0.01, 0.4));
  f.curves[0].side = VaneSide::None;
  f.left = f.right = params(10, 45, 0.04, 0.01, 0.4);
  EXPECT_THROW(Scene(f, SceneOptions{ShadingMode::Substructure, {}}), Error);
}

// Stress: extreme but valid parameters and inputs give a defined structure, h in
// [-1, 1], a hook in [0, 1] and an orthonormal frame; never NaN.
TEST(Substructure, StressExtremeInputs) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u01(0, 1);
  const Frame barb{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int k = 0; k < 200; ++k) {
    // Across the whole accepted range (substructure_problem): ribbon up to 10 mm,
    // barbules up to 1 mm thick.
    const double width = std::pow(10.0, -4 + 5 * u01(rng));
    const SubstructureParams p =
        params(int(std::pow(10.0, 5 * u01(rng))), 1 + 89 * u01(rng), width * 0.49 * u01(rng) + 1e-9,
               std::min(1.0, width * u01(rng)), width, -89 + 178 * u01(rng), u01(rng));
    const BarbSubstructure sub(p, k % 2 ? VaneSide::Left : VaneSide::Right);
    for (int i = 0; i < 200; ++i) {
      const double L = std::pow(10.0, -6 + 12 * u01(rng));
      const double s = (u01(rng) * 1.2 - 0.1) * L, w = (u01(rng) - 0.5) * width * 1.1;
      const StructureHit h = sub.classify(s, w, L);
      ASSERT_TRUE(std::isfinite(h.h));
      ASSERT_GE(h.h, -1.0f);
      ASSERT_LE(h.h, 1.0f);
      ASSERT_GE(h.hook, 0.0f);
      ASSERT_LE(h.hook, 1.0f);
      if (std::fabs(w) > 0.5 * width) {
        ASSERT_EQ(h.structure, Structure::Empty);
      }
      const Frame f = sub.frame(barb, h, w);
      ASSERT_NEAR(glm::dot(glm::cross(f.n, f.t), f.b), 1.0f, 1e-4f);
    }
  }
}
