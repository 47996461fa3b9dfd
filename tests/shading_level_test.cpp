// `--shading auto` (renderer/shading_level.h): a pixel's footprint, a feather's
// barbule period, the switch between them, and a scene whose near placement is
// shaded in substructure mode and whose far placement, the same feather, in
// farfield mode (apps/pipeline feather_scene.h, BuiltWorld).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include "plumage/pipeline/feather_scene.h"
#include "plumage/renderer/render.h"
#include "plumage/renderer/shading_level.h"
#include "one_barb.h"
#include "render_test_feather.h"

using namespace plumage;

namespace {

Bounds3f box(const glm::vec3& lo, const glm::vec3& hi) {
  Bounds3f b;
  b.extend(lo);
  b.extend(hi);
  return b;
}

CameraSpec looking_down(float height) {
  CameraSpec cs;
  cs.position = glm::vec3(0, 0, height);
  cs.look_at = glm::vec3(0);
  cs.fov_deg = 30;
  return cs;
}

// The test feather with sparse barbules (a period of about a millimetre), so that
// the switch falls at a depth a small image can show.
Feather sparse_feather() {
  Feather f = test::make_test_feather(30.0f, 0.6f, 0.05f);
  f.left = f.right = test::substructure_params(6, 45, 0.04, 0.006, 0.4, 10, 0.3);
  return f;
}

}  // namespace

TEST(ShadingLevel, PixelFootprintIsTheNearestDepthTimesThePixelsAngle) {
  const Bounds3f frame = box({-10, -10, -1}, {10, 10, 1});
  const Camera cam(looking_down(100), 200, 100, frame);
  const double per_pixel = 2 * std::tan(15 * std::numbers::pi / 180) / 100;
  // The nearest corner decides: depth 100 - 10.
  EXPECT_NEAR(cam.pixel_footprint(box({-5, -5, -10}, {5, 5, 10})), 90 * per_pixel, 1e-5);
  EXPECT_NEAR(cam.pixel_footprint(box({30, 40, -50}, {31, 41, -49})), 149 * per_pixel, 1e-4);
  // A box that reaches the eye's plane, or lies behind the camera: no footprint.
  EXPECT_EQ(cam.pixel_footprint(box({-5, -5, 50}, {5, 5, 120})), 0.0f);
  EXPECT_EQ(cam.pixel_footprint(box({-5, -5, 150}, {5, 5, 160})), 0.0f);
  // Orthographic: the visible height over the rows, everywhere.
  CameraSpec ortho = looking_down(100);
  ortho.projection = Projection::Orthographic;
  ortho.ortho_height = 50;
  const Camera flat(ortho, 200, 100, frame);
  EXPECT_FLOAT_EQ(flat.pixel_footprint(box({-5, -5, -10}, {5, 5, 10})), 0.5f);
  EXPECT_FLOAT_EQ(flat.pixel_footprint(box({-5, -5, -500}, {5, 5, -490})), 0.5f);
}

TEST(ShadingLevel, BarbulePeriodIsTheMedianBarbLengthOverN) {
  Feather f;
  f.curves.push_back(test::straight_curve(CurveKind::Shaft, {0, 0, 0}, 10, 0.3f));
  for (float half : {1.5f, 3.0f, 6.0f}) f.curves.push_back(test::straight_curve(CurveKind::Barb, {0, 1, 0}, half, 0.05f));
  f.right.barbules_per_side = 60;  // lengths 3, 6 and 12 mm: periods 0.05, 0.1, 0.2
  EXPECT_NEAR(barbule_period(f), 0.1f, 1e-6);
  // Barbs of a vane without barbules do not count.
  Curve left = test::straight_curve(CurveKind::Barb, {0, -1, 0}, 50, 0.05f);
  left.side = VaneSide::Left;
  f.curves.push_back(left);
  f.curves.push_back(left);
  EXPECT_NEAR(barbule_period(f), 0.1f, 1e-6);
  f.right.barbules_per_side = 0;
  EXPECT_EQ(barbule_period(f), 0.0f);
  f.left.barbules_per_side = 10;  // now only the two 100 mm left barbs count
  EXPECT_NEAR(barbule_period(f), 10.0f, 1e-4);
}

TEST(ShadingLevel, SwitchesToFarfieldWhereAPixelCoversABarbulePeriod) {
  EXPECT_EQ(shading_for_footprint(0.05f, 0.1f), ShadingMode::Substructure);
  EXPECT_EQ(shading_for_footprint(0.0f, 0.1f), ShadingMode::Substructure);
  EXPECT_EQ(shading_for_footprint(0.1f, 0.1f), ShadingMode::Farfield);
  EXPECT_EQ(shading_for_footprint(50.0f, 0.1f), ShadingMode::Farfield);
  EXPECT_EQ(shading_for_footprint(std::numeric_limits<float>::infinity(), 0.1f), ShadingMode::Farfield);
  EXPECT_EQ(shading_for_footprint(std::nanf(""), 0.1f), ShadingMode::Farfield);
  // No barbules: nothing for a table to average.
  EXPECT_EQ(shading_for_footprint(50.0f, 0.0f), ShadingMode::Substructure);
  // The period scales with the placement.
  const Feather f = sparse_feather();
  const float p = barbule_period(f);
  const Bounds3f b = box({-1, -1, -1}, {1, 1, 1});
  const Camera ortho = [&] {
    CameraSpec cs = looking_down(100);
    cs.projection = Projection::Orthographic;
    cs.ortho_height = 100 * p;  // a footprint of p at 100 rows
    return Camera(cs, 100, 100, b);
  }();
  EXPECT_EQ(shading_by_footprint(f, 1.0f, b, ortho), ShadingMode::Farfield);
  EXPECT_EQ(shading_by_footprint(f, 1.1f, b, ortho), ShadingMode::Substructure);
  EXPECT_EQ(shading_by_footprint(f, 0.9f, b, ortho), ShadingMode::Farfield);
}

// One feather placed twice: near the camera (each pixel smaller than a barbule
// period) and far from it. The near placement is shaded as the all-substructure
// world shades it and the far one as the all-farfield world does: on each half of
// the image the mixed world matches the matching uniform world much more closely
// than the other one (same seed, so the paths that meet one placement only agree).
TEST(ShadingLevel, AutoShadesNearPlacementsBySubstructureAndFarOnesByFarfield) {
  LoadedScene loaded;
  loaded.feathers.push_back(sparse_feather());
  loaded.folders.push_back(".");
  loaded.scene.feathers.push_back({"f", SceneFeatherSource::Fcurves, "f.fcurves", "", 1, 1});
  const int w = 64, h = 32;
  const float p = barbule_period(loaded.feathers[0]);
  ASSERT_GT(p, 0.3f);
  const double per_pixel = 2 * std::tan(15 * std::numbers::pi / 180) / h;
  const float switch_depth = float(p / per_pixel);  // where a pixel covers one period
  const float camera_z = 3 * switch_depth;
  // Near: its nearest point at 0.6 of the switch depth; far: at 1.6 of it. Each
  // centred on its half of the image (the feather runs along +Y from 0 to 30 mm).
  const auto place = [&](float depth, float side) {
    const float z = camera_z - depth;
    const float x = side * 0.5f * depth * std::tan(15 * std::numbers::pi_v<float> / 180) * float(w) / float(h);
    return glm::translate(glm::mat4(1.0f), glm::vec3(x, -15, z - 0.5f));
  };
  loaded.scene.placements.push_back({0, place(0.6f * switch_depth, -1), 1});
  loaded.scene.placements.push_back({0, place(1.6f * switch_depth, +1), 2});

  ViewSpec view;
  view.width = w, view.height = h;
  view.camera = looking_down(camera_z);
  view.camera.look_at = glm::vec3(0, 0, 0);
  SceneOptions options;
  options.backdrop.enabled = false;
  const BuiltWorld mixed(loaded, options, view, SceneShading::ByFootprint);
  ASSERT_EQ(mixed.placement_modes().size(), 2u);
  EXPECT_EQ(mixed.placement_modes()[0], ShadingMode::Substructure);
  EXPECT_EQ(mixed.placement_modes()[1], ShadingMode::Farfield);
  // One feather, two scenes: one per level in use.
  ASSERT_EQ(mixed.world().feathers().size(), 2u);
  EXPECT_EQ(mixed.world().feathers()[mixed.world().placed_feather(0)].scene->options().mode, ShadingMode::Substructure);
  EXPECT_EQ(mixed.world().feathers()[mixed.world().placed_feather(1)].scene->options().mode, ShadingMode::Farfield);

  options.mode = ShadingMode::Substructure;
  const BuiltWorld sub(loaded, options, view);
  options.mode = ShadingMode::Farfield;
  const BuiltWorld far(loaded, options, view);
  EXPECT_EQ(sub.world().feathers().size(), 1u);

  LightSet lights;
  lights.set_environment(EnvironmentLight(glm::vec3(0.8f)));
  lights.add(SphereLight{glm::vec3(30, 40, camera_z), 8.0f, glm::vec3(400.0f)});
  const Camera camera(view.camera, w, h, mixed.world().bounds());
  const auto image = [&](const World& world) {
    RenderSettings rs;
    rs.spp = 16;
    rs.seed = 3;
    rs.progress = false;
    rs.allocation = SampleAllocation::Uniform;
    return render(camera, PathIntegrator(world, lights, IntegratorSettings{}), rs).developed(0);
  };
  const Image m = image(mixed.world()), s = image(sub.world()), f = image(far.world());
  const auto rms = [&](const Image& a, const Image& b, int x0, int x1) {
    double sum = 0;
    for (int y = 0; y < h; ++y)
      for (int x = x0; x < x1; ++x)
        for (int c = 0; c < 3; ++c) sum += std::pow(double(a.at(x, y)[c]) - b.at(x, y)[c], 2);
    return std::sqrt(sum / (3.0 * h * (x1 - x0)));
  };
  const double near_same = rms(m, s, 0, w / 2), near_other = rms(m, f, 0, w / 2);
  const double far_same = rms(m, f, w / 2, w), far_other = rms(m, s, w / 2, w);
  EXPECT_LT(near_same, 0.25 * near_other) << near_same << " vs " << near_other;
  EXPECT_LT(far_same, 0.25 * far_other) << far_same << " vs " << far_other;
  EXPECT_GT(test::mean_channel(m, 1), 0.05);
}
