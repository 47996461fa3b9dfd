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
