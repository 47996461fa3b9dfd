// The Embree scene: hits report the right curve and shading offset h, secondary
// rays see neighbouring barbs that Embree's near-origin culling would hide, and
// bad feathers are refused with a plumage::Error.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "plumage/common/error.h"
#include "plumage/renderer/fibre_frame.h"
#include "plumage/renderer/scene.h"
#include "plumage/renderer/shading_mode.h"
#include "render_test_feather.h"

using namespace plumage;
using plumage::test::straight_curve;

namespace {
Ray down_ray(float x, float y, float z = 10.0f) {
  Ray r;
  r.o = {x, y, z};
  r.d = {0, 0, -1};
  return r;
}
}  // namespace

TEST(RenderScene, FlatBarbHitGivesOffsetAlongFrameY) {
  Feather f;
  const float r = 0.2f;
  f.curves.push_back(straight_curve(CurveKind::Barb, {0, 0, 0}, 5, r));
  const Scene scene(f, {});
  for (float off : {-0.7f, -0.3f, 0.0f, 0.4f, 0.8f}) {
    SurfaceHit hit;
    ASSERT_TRUE(scene.intersect(down_ray(0.3f, off * r), hit)) << off;
    EXPECT_EQ(hit.kind, HitKind::Barb);
    EXPECT_EQ(hit.curve, 0u);
    const CurvePoint cp = scene.curve_point(hit);
    const FibreFrame ff = flat_fibre_frame(cp.dp, {0, 0, 1}, hit.v);
    // h measured along the frame's +y must equal the geometric offset.
    const float h_geom = glm::dot(hit.p - cp.p, ff.frame.b) / cp.radius;
    EXPECT_NEAR(ff.h, h_geom, 0.02f) << "offset " << off;
    EXPECT_NEAR(std::fabs(ff.h), std::fabs(off), 0.02f);
  }
}

TEST(RenderScene, RoundShaftHitGivesOffsetFromGeometry) {
  Feather f;
  const float r = 0.5f;
  f.curves.push_back(straight_curve(CurveKind::Shaft, {0, 0, 0}, 5, r));
  const Scene scene(f, {});
  for (float off : {-0.9f, -0.5f, 0.0f, 0.3f, 0.95f}) {
    SurfaceHit hit;
    ASSERT_TRUE(scene.intersect(down_ray(0.1f, off * r), hit)) << off;
    EXPECT_EQ(hit.kind, HitKind::Shaft);
    EXPECT_EQ(hit.v, 0.0f);  // why h cannot come from v for round curves
    const CurvePoint cp = scene.curve_point(hit);
    const FibreFrame ff = round_fibre_frame(cp.dp, {0, 0, 1}, cp.p, cp.radius, hit.p);
    // Seen from +Z with the tangent along +X, the frame's y is -Y x ... = +Y.
    EXPECT_NEAR(ff.frame.b.y, 1.0f, 1e-5f);
    EXPECT_NEAR(ff.h, off, 0.01f) << "offset " << off;
  }
}

// A down barb (docs/curve-format.md, "Down") is a round tube its fibres fill to the
// feather's down cover, in every mode: a ray through it meets it with probability
// 1 - (1 - cover)^2 (its entry and its exit), intersection and occlusion agree ray
// by ray, and a vane without pennaceous barbs needs no substructure parameters.
TEST(RenderScene, DownBarbsAreTubesTheirFibresFillToTheCover) {
  const float r = 0.5f;
  for (const float cover : {1.0f, 0.6f, 0.25f}) {
    Feather f;
    f.down_cover = cover;
    Curve c = straight_curve(CurveKind::Down, {0, 0, 0}, 5, r);
    c.side = VaneSide::Right;
    f.curves.push_back(c);
    for (const ShadingMode mode : {ShadingMode::Hair, ShadingMode::Substructure}) {
      SCOPED_TRACE("cover " + std::to_string(cover) + ", " + to_string(mode));
      SceneOptions options;
      options.mode = mode;
      const Scene scene(f, options);
      std::mt19937 rng(7);
      std::uniform_real_distribution<float> along(-1.5f, 1.5f), across(-0.3f * r, 0.3f * r);
      const int n = 4000;
      int hits = 0, disagree = 0;
      for (int i = 0; i < n; ++i) {
        const Ray ray = down_ray(along(rng), across(rng));
        SurfaceHit hit;
        const bool found = scene.intersect(ray, hit);
        if (found) {
          ++hits;
          EXPECT_EQ(hit.kind, HitKind::Down);
        }
        disagree += scene.occluded(ray) != found;
      }
      EXPECT_EQ(disagree, 0);
      const double p = 1.0 - (1.0 - cover) * (1.0 - cover);
      const double sigma = std::sqrt(p * (1.0 - p) / n);
      EXPECT_NEAR(double(hits) / n, p, 4.0 * sigma + 1e-9);
    }
  }
}

TEST(RenderScene, SecondaryRaysSeeTouchingBarbsDespiteNearOriginCulling) {
  // Barb B lies 1.5 radii under barb A: closer than Embree's 2r culling distance.
  Feather f;
  const float r = 0.1f;
  f.curves.push_back(straight_curve(CurveKind::Barb, {0, 0, 0}, 5, r));
  f.curves.push_back(straight_curve(CurveKind::Barb, {0, 0, -1.5f * r}, 5, r));
  const Scene scene(f, {});
  SurfaceHit a;
  ASSERT_TRUE(scene.intersect(down_ray(0.2f, 0.0f), a));
  ASSERT_EQ(a.curve, 0u);

  // The naive continuation from the hit point loses B (the premise of Scene::spawn).
  Ray naive;
  naive.o = a.p;
  naive.d = {0, 0, -1};
  SurfaceHit lost;
  EXPECT_FALSE(scene.intersect(naive, lost) && lost.curve == 1u)
      << "Embree no longer culls near-origin flat-curve hits; Scene::spawn's offset may be revisited";

  const Ray down = scene.spawn(a, {0, 0, -1});
  SurfaceHit b;
  ASSERT_TRUE(scene.intersect(down, b));
  EXPECT_EQ(b.curve, 1u);
  EXPECT_NEAR(b.p.z, -1.5f * r, 0.02f);
  EXPECT_TRUE(scene.occluded(scene.spawn(a, {0, 0, -1}, 1.0f)));
  // A shadow ray that stops short of B is not occluded.
  EXPECT_FALSE(scene.occluded(scene.spawn(a, {0, 0, -1}, 0.5f * r)));
  // Leaving A upward, nothing is hit: A itself is skipped.
  SurfaceHit none;
  EXPECT_FALSE(scene.intersect(scene.spawn(a, {0, 0, 1}), none));
  EXPECT_FALSE(scene.occluded(scene.spawn(a, {0, 0, 1})));
}

TEST(RenderScene, BackdropLiesUnderTheFeather) {
  SceneOptions so;
  so.backdrop.enabled = true;
  const Scene scene(test::make_test_feather(), so);
  EXPECT_LT(scene.backdrop_z(), scene.feather_bounds().lo.z);
  SurfaceHit hit;
  // Beside the feather, a downward ray meets the card.
  ASSERT_TRUE(scene.intersect(down_ray(40.0f, 5.0f, 50.0f), hit));
  EXPECT_EQ(hit.kind, HitKind::Backdrop);
  EXPECT_NEAR(hit.p.z, scene.backdrop_z(), 1e-4f);
  // From the card, a ray straight up escapes (the card does not re-hit itself).
  SurfaceHit up;
  EXPECT_FALSE(scene.intersect(scene.spawn(hit, {0, 0, 1}), up));
}

TEST(RenderScene, BackdropUnderTheVaneLiesOnItsBarbs) {
  // A rachis 1 mm thick beside barbs 0.2 mm wide (W) in the plane z = 0. Under the
  // feather the card lies four rachis radii under the rachis; under the vane, four
  // barb radii (2 W) under the barbs, whatever the rachis; a feather without barbs
  // falls back to its lowest point.
  Feather f;
  f.curves.push_back(straight_curve(CurveKind::Shaft, {0, 0, 0}, 20, 0.5f));
  for (float y : {-2.0f, -1.0f, 1.0f, 2.0f}) f.curves.push_back(straight_curve(CurveKind::Barb, {5, y, 0}, 4, 0.05f));
  f.left.ribbon_width = f.right.ribbon_width = 0.2f;
  SceneOptions so;
  so.backdrop.enabled = true;
  EXPECT_NEAR(Scene(f, so).backdrop_z(), -0.5f - 4 * 0.5f, 1e-5f);
  so.backdrop.placement = BackdropPlacement::Vane;
  const Scene vane(f, so);
  EXPECT_NEAR(vane.backdrop_z(), -0.1f - 4 * 0.1f, 1e-5f);
  SurfaceHit hit;
  ASSERT_TRUE(vane.intersect(down_ray(5.0f, 1.0f, 10.0f), hit));
  EXPECT_EQ(hit.kind, HitKind::Barb);
  ASSERT_TRUE(vane.intersect(down_ray(5.0f, 1.5f, 10.0f), hit));  // between barbs 1 mm apart
  EXPECT_EQ(hit.kind, HitKind::Backdrop);
  EXPECT_NEAR(hit.p.z, vane.backdrop_z(), 1e-4f);
  Feather bare;
  bare.curves.push_back(f.curves[0]);
  EXPECT_NEAR(Scene(bare, so).backdrop_z(), -0.5f - 4 * 0.5f, 1e-5f);
}

TEST(RenderScene, RefusesBadFeathers) {
  EXPECT_THROW(Scene(Feather{}, {}), Error);
  Feather short_curve;
  short_curve.curves.push_back(straight_curve(CurveKind::Barb, {0, 0, 0}, 1, 0.1f));
  short_curve.curves[0].points.pop_back();
  EXPECT_THROW(Scene(short_curve, {}), Error);
  Feather nan_curve;
  nan_curve.curves.push_back(straight_curve(CurveKind::Barb, {0, 0, 0}, 1, 0.1f));
  nan_curve.curves[0].points[1].p.x = std::nanf("");
  EXPECT_THROW(Scene(nan_curve, {}), Error);
  nan_curve.curves[0].points[1].p.x = 0;
  nan_curve.curves[0].points[2].radius = -1;
  EXPECT_THROW(Scene(nan_curve, {}), Error);
  SceneOptions sub;
  sub.mode = ShadingMode::Substructure;
  EXPECT_THROW(Scene(test::make_test_feather(), sub), Error);
}

TEST(RenderFibreFrame, OrthonormalAndFiniteForExtremeDirections) {
  std::mt19937 rng(7);
  std::normal_distribution<float> g;
  std::uniform_real_distribution<float> u(0, 1);
  for (int i = 0; i < 200000; ++i) {
    glm::vec3 t{g(rng), g(rng), g(rng)}, wo{g(rng), g(rng), g(rng)};
    if (i % 5 == 0) wo = glm::normalize(t) * (i % 2 ? 1.0f : -1.0f);  // along the fibre
    if (i % 7 == 0) t *= 1e-20f;                                     // degenerate tangent
    if (i % 11 == 0) t = {0, 0, 0};
    wo = safe_normalize(wo);
    const float v = i % 3 == 0 ? float(i % 2) : u(rng);
    const FibreFrame a = flat_fibre_frame(t, wo, v);
    const FibreFrame b = round_fibre_frame(t, wo, {0, 0, 0}, i % 13 ? 0.5f : 0.0f, {g(rng), g(rng), g(rng)});
    for (const FibreFrame& f : {a, b}) {
      ASSERT_TRUE(std::isfinite(f.h) && f.h >= -1 && f.h <= 1) << i;
      ASSERT_NEAR(glm::length(f.frame.t), 1.0f, 1e-4f) << i;
      ASSERT_NEAR(glm::length(f.frame.b), 1.0f, 1e-4f) << i;
      ASSERT_NEAR(glm::length(f.frame.n), 1.0f, 1e-4f) << i;
      ASSERT_NEAR(glm::dot(f.frame.t, f.frame.n), 0.0f, 1e-4f) << i;
      ASSERT_NEAR(glm::dot(f.frame.b, f.frame.n), 0.0f, 1e-4f) << i;
      ASSERT_NEAR(glm::dot(glm::cross(f.frame.n, f.frame.t), f.frame.b), 1.0f, 1e-4f) << i;
      // wo lies in the x-z half plane with z >= 0 (the BCSDF's convention).
      ASSERT_GE(glm::dot(wo, f.frame.n), -1e-4f) << i;
      ASSERT_NEAR(glm::dot(wo, f.frame.b), 0.0f, 1e-4f) << i;
    }
  }
}
