// Fibre absorption from the feather's albedo (constant or texture through the rect
// mapping), and the integrator's guard against non-finite samples.
#include <unistd.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/common/stats.h"
#include "plumage/renderer/render.h"
#include "render_test_feather.h"

using namespace plumage;
using test::mean_channel;
namespace fs = std::filesystem;

TEST(RenderMaterial, TextureMapsThroughTheRectTipUp) {
  const fs::path dir = fs::temp_directory_path() / ("plumage_render_material_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // 2x2 texture: top row red | green, bottom row blue | white (linear EXR).
  Image tex(2, 2, 3);
  tex.set_rgb(0, 0, {1, 0, 0});
  tex.set_rgb(1, 0, {0, 1, 0});
  tex.set_rgb(0, 1, {0, 0, 1});
  tex.set_rgb(1, 1, {1, 1, 1});
  write_image(dir / "albedo.exr", tex);
  Albedo a;
  a.texture = "albedo.exr";  // relative to the curve file's folder
  a.rect_min = {-10, 0};
  a.rect_max = {10, 60};
  const AlbedoMap map(a, dir);
  ASSERT_TRUE(map.textured());
  const float eps = 1e-4f;
  EXPECT_LT(glm::length(map.at({-10, 60}) - glm::vec3(1, 0, 0)), eps);  // top-left: x min, y max (tip)
  EXPECT_LT(glm::length(map.at({10, 60}) - glm::vec3(0, 1, 0)), eps);
  EXPECT_LT(glm::length(map.at({-10, 0}) - glm::vec3(0, 0, 1)), eps);
  EXPECT_LT(glm::length(map.at({10, 0}) - glm::vec3(1, 1, 1)), eps);
  EXPECT_LT(glm::length(map.at({-50, 100}) - glm::vec3(1, 0, 0)), eps);  // clamped outside
  EXPECT_LT(glm::length(map.at({0, 30}) - glm::vec3(0.5f, 0.5f, 0.5f)), eps);  // bilinear centre

  // Darker albedo -> more absorption, through the material.
  HairParams hp;
  const FibreMaterial m(hp, map);
  const glm::vec3 s_white = m.at({10, 0, 0}).sigma_a, s_red = m.at({-10, 60, 0}).sigma_a;
  EXPECT_LT(s_white.y, s_red.y);
  EXPECT_NEAR(s_red.x, s_white.x, 1e-4f);

  Albedo missing = a;
  missing.texture = "no_such_albedo.png";
  try {
    AlbedoMap bad(missing, dir);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(e.where().file.find("no_such_albedo.png"), std::string::npos);
  }
  Albedo empty_rect = a;
  empty_rect.rect_max = empty_rect.rect_min;
  EXPECT_THROW(AlbedoMap(empty_rect, dir), Error);
}

TEST(RenderMaterial, NonFiniteSamplesAreCountedAndDropped) {
  SceneOptions so;
  so.backdrop.enabled = true;
  const Scene scene(test::make_test_feather(20.0f, 1.0f, 0.05f), so);
  LightSet lights;
  lights.add(SphereLight{{0, 10, 30}, 2.0f, glm::vec3(std::numeric_limits<float>::infinity())});
  const FibreMaterial material(HairParams{}, AlbedoMap(glm::vec3(0.5f)));
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{});
  const Camera camera(CameraSpec{}, 8, 8, scene.feather_bounds());
  RenderSettings rs;
  rs.spp = 2;
  rs.progress = false;
  stats_reset();
  const Image img = render(camera, integrator, rs).developed(0);
  for (float v : img.pixels) ASSERT_TRUE(std::isfinite(v));
  EXPECT_GT(stats_snapshot()["Renderer/NaN or Inf samples dropped"], 0.0);
}

namespace {

// One layer of touching parallel barbs over a white card under a uniform sky (the
// diffuse light an albedo photo is taken in), seen from above: the layer's colour
// over the bare card's, per channel.
glm::vec3 layer_over_card(AlbedoMapping mapping, const glm::vec3& albedo) {
  Feather f;
  const float r = 0.1f;
  for (int k = -20; k <= 20; ++k) f.curves.push_back(test::straight_curve(CurveKind::Barb, {0, 2 * r * k, 0}, 8, r));
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.8f), 4.0f};
  const Scene scene(f, so);
  LightSet lights;
  lights.set_environment(EnvironmentLight(glm::vec3(1.0f)));
  const FibreMaterial material(HairParams{}, AlbedoMap(albedo), mapping);
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{});
  RenderSettings rs;
  rs.spp = 64;
  rs.progress = false;
  glm::vec3 out;
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.ortho_height = 2.0f;
  cs.up = {0, 1, 0};
  cs.position = {0, 0, 5};
  cs.look_at = {0, 0, 0};
  const Image layer = render(Camera(cs, 16, 16, scene.feather_bounds()), integrator, rs).developed(0);
  cs.position = {12, 12, 5};  // bare card beside the layer
  cs.look_at = {12, 12, 0};
  const Image card = render(Camera(cs, 16, 16, scene.feather_bounds()), integrator, rs).developed(0);
  for (int c = 0; c < 3; ++c) out[c] = float(mean_channel(layer, c) / mean_channel(card, c));
  return out;
}

}  // namespace

TEST(RenderMaterial, OneLayerOfFibresOverACardShowsItsAlbedo) {
  // The default mapping is calibrated on exactly this: a light pink vane photographed
  // on white paper must render pink, not as a grey haze. Within 15 % per channel
  // (Fresnel reflection and the fibres' rounded edges are not in the calibration).
  const glm::vec3 pink(0.95f, 0.5f, 0.55f), brown(0.35f, 0.22f, 0.12f);
  for (const glm::vec3& a : {pink, brown}) {
    const glm::vec3 seen = layer_over_card(AlbedoMapping::Layer, a);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(seen[c], a[c], 0.15f * a[c]) << "albedo channel " << c << " = " << a[c];
  }
  // Chiang et al.'s mapping, made for dense hair, leaves a single layer almost clear.
  const glm::vec3 chiang = layer_over_card(AlbedoMapping::Chiang2016, pink);
  EXPECT_GT(chiang.y, 0.8f);
}
