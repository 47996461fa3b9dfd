// The path integrator against closed forms: a lambertian card under one sphere
// light (exact irradiance), a white furnace (every path returns the environment
// radiance), and thread-count independence of the image for a seed.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include <unistd.h>

#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/renderer/render.h"
#include "render_test_feather.h"

using namespace plumage;
using test::mean_channel;

namespace {

// Two tiny barbs at opposite corners: they set the card's size and stay out of the way.
Feather corner_barbs() {
  Feather f;
  f.curves.push_back(test::straight_curve(CurveKind::Barb, {-30, -30, 0}, 0.5f, 0.05f));
  f.curves.push_back(test::straight_curve(CurveKind::Barb, {30, 30, 0}, 0.5f, 0.05f));
  return f;
}

}  // namespace

TEST(RenderIntegrator, LambertianCardUnderSphereLightMatchesAnalyticIrradiance) {
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.5f, 0.25f, 1.0f)};
  const Scene scene(corner_barbs(), so);
  const glm::vec3 P(0, 0, scene.backdrop_z());
  // A sphere fully above the horizon: E = pi L (a/d)^2 cos(theta) exactly.
  SphereLight light{P + glm::vec3(30, 0, 40), 2.0f, glm::vec3(100.0f)};
  LightSet lights;
  lights.add(light);
  const float d = 50.0f, cos_t = 0.8f;
  const glm::vec3 expected = so.backdrop.albedo / 3.14159265f * (3.14159265f * 100.0f * (2.0f / d) * (2.0f / d) * cos_t);

  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.position = P + glm::vec3(0, 0, 20);
  cs.look_at = P;
  cs.ortho_height = 0.01f;
  const Camera camera(cs, 4, 4, scene.feather_bounds());
  const FibreMaterial material(HairParams{});
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{1, 3});
  RenderSettings rs;
  rs.spp = 256;
  rs.progress = false;
  const Image img = render(camera, integrator, rs).developed(0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean_channel(img, c), expected[c], 0.01 * expected[c]) << "channel " << c;
  // Exposure scales by 2^stops.
  EXPECT_NEAR(mean_channel(render(camera, integrator, rs).developed(1), 0), 2 * expected.x, 0.02 * expected.x);
}

TEST(RenderIntegrator, WhiteFurnaceReturnsEnvironmentRadiance) {
  SceneOptions so;
  so.backdrop = {true, glm::vec3(1.0f)};
  const Scene scene(test::make_test_feather(20.0f, 0.5f, 0.08f), so);
  LightSet lights;
  lights.set_environment(EnvironmentLight(glm::vec3(1.0f)));
  HairParams hp;
  hp.sigma_a = glm::vec3(0.0f);
  const FibreMaterial material(hp);
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{256, 3});
  const Camera camera(CameraSpec{}, 16, 16, scene.feather_bounds());
  RenderSettings rs;
  rs.spp = 32;
  rs.progress = false;
  const Image img = render(camera, integrator, rs).developed(0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean_channel(img, c), 1.0, 0.02) << "channel " << c;
  // Absorbing fibres and a grey card make it darker: the test can tell.
  SceneOptions grey = so;
  grey.backdrop.albedo = glm::vec3(0.5f);
  const Scene grey_scene(test::make_test_feather(20.0f, 0.5f, 0.08f), grey);
  const PathIntegrator grey_integrator(grey_scene, lights, material, IntegratorSettings{256, 3});
  EXPECT_LT(mean_channel(render(camera, grey_integrator, rs).developed(0), 0), 0.9);
}

TEST(RenderIntegrator, SameSeedSameImageWithOneOrTwoThreads) {
  SceneOptions so;
  so.backdrop.enabled = true;
  const Scene scene(test::make_test_feather(30.0f, 0.6f, 0.06f), so);
  LightSet lights;
  lights.add(SphereLight{{0, 15, 40}, 3.0f, glm::vec3(50.0f)});
  lights.set_environment(EnvironmentLight(glm::vec3(0.2f)));
  const FibreMaterial material(HairParams{}, AlbedoMap(glm::vec3(0.6f, 0.4f, 0.3f)));
  const Camera camera(CameraSpec{}, 24, 20, scene.feather_bounds());
  for (LightPick pick : {LightPick::Uniform, LightPick::Estimate, LightPick::All})
  for (SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Independent}) {
    IntegratorSettings is;
    is.light_pick = pick;
    const PathIntegrator integrator(scene, lights, material, is);
    RenderSettings rs;
    rs.spp = 4;
    rs.seed = 42;
    rs.sampler = kind;
    rs.progress = false;
    rs.tile_size = 8;
    rs.threads = 1;
    const Image one = render(camera, integrator, rs).developed(0);
    rs.threads = 2;
    const Image two = render(camera, integrator, rs).developed(0);
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(float)), 0)
        << to_string(kind) << ", " << to_string(pick);
    rs.seed = 43;
    const Image other = render(camera, integrator, rs).developed(0);
    EXPECT_NE(std::memcmp(one.pixels.data(), other.pixels.data(), one.pixels.size() * sizeof(float)), 0)
        << "a different seed must change the noise";
  }
}

TEST(RenderIntegrator, MisCombinesStrategiesWithoutBias) {
  // A large light, seen by both strategies often: light-only (max-depth 1, MIS) and
  // the same estimate at two sample counts must agree with the analytic value.
  SceneOptions so;
  so.backdrop = {true, glm::vec3(1.0f)};
  const Scene scene(corner_barbs(), so);
  const glm::vec3 P(0, 0, scene.backdrop_z());
  LightSet lights;
  lights.add(SphereLight{P + glm::vec3(0, 0, 10), 6.0f, glm::vec3(1.0f)});
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.position = P + glm::vec3(20, 0, 1);
  cs.look_at = P;
  cs.up = {0, 0, 1};
  cs.ortho_height = 0.01f;
  const Camera camera(cs, 4, 4, scene.feather_bounds());
  const FibreMaterial material(HairParams{});
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{1, 3});
  RenderSettings rs;
  rs.spp = 512;
  rs.progress = false;
  // Radiance of a white lambertian card under a sphere of radiance 1: (a/d)^2 cos = 0.36.
  EXPECT_NEAR(mean_channel(render(camera, integrator, rs).developed(0), 1), 0.36, 0.36 * 0.01);
}

TEST(RenderIntegrator, LightScattersBetweenBarbs) {
  // Two stacked barbs, the lower one shadowed by the upper one from a light above:
  // with direct light only the lower barb sees nothing through its neighbour's
  // shadow side; with more bounces light scattered by the upper barb reaches it.
  Feather f;
  const float r = 0.1f;
  f.curves.push_back(test::straight_curve(CurveKind::Barb, {0, 0, 0}, 5, r));
  f.curves.push_back(test::straight_curve(CurveKind::Barb, {0, 0, -1.5f * r}, 5, r));
  const Scene scene(f, {});
  LightSet lights;
  lights.add(DirectionalLight{{0, 0, 1}, glm::vec3(1.0f)});
  HairParams hp;
  hp.sigma_a = glm::vec3(0.0f);
  const FibreMaterial material(hp);
  // Look at the lower barb from below.
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.position = glm::vec3(0, 0, -10);
  cs.look_at = glm::vec3(0, 0, 0);
  cs.ortho_height = 0.5f * r;
  const Camera camera(cs, 4, 4, scene.feather_bounds());
  RenderSettings rs;
  rs.spp = 64;
  rs.progress = false;
  const PathIntegrator direct(scene, lights, material, IntegratorSettings{1, 3});
  const PathIntegrator multi(scene, lights, material, IntegratorSettings{8, 3});
  const double d = mean_channel(render(camera, direct, rs).developed(0), 0);
  const double m = mean_channel(render(camera, multi, rs).developed(0), 0);
  EXPECT_EQ(d, 0.0) << "the upper barb must shadow the lower one from a light straight above";
  EXPECT_GT(m, 0.01);
}

TEST(RenderIntegrator, EveryLightPickIsUnbiasedOnACardUnderUnequalLights) {
  // Three sphere lights of very different power and size, close enough that BCSDF
  // samples hit them often: light sampling with each pick strategy and the
  // MIS-weighted hits (which must use the same pick probability) add up to the
  // exact irradiance, sum of pi L (a/d)^2 cos(theta).
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.7f)};
  const Scene scene(corner_barbs(), so);
  const glm::vec3 P(0, 0, scene.backdrop_z());
  struct L {
    glm::vec3 offset;
    float radius, radiance;
  };
  const L specs[] = {{{30, 0, 40}, 2.0f, 100.0f}, {{0, -6, 8}, 4.0f, 0.5f}, {{-3, 4, 12}, 3.0f, 5.0f}};
  LightSet lights;
  double E = 0;
  for (const L& l : specs) {
    lights.add(SphereLight{P + l.offset, l.radius, glm::vec3(l.radiance)});
    const double d = glm::length(l.offset);
    E += 3.14159265 * l.radiance * (l.radius / d) * (l.radius / d) * (l.offset.z / d);
  }
  const double expected = 0.7 / 3.14159265 * E;
  CameraSpec cs;
  cs.projection = Projection::Orthographic;
  cs.position = P + glm::vec3(0, 0, 1);
  cs.look_at = P;
  cs.ortho_height = 0.01f;
  const Camera camera(cs, 4, 4, scene.feather_bounds());
  const FibreMaterial material(HairParams{});
  RenderSettings rs;
  rs.spp = 1024;
  rs.progress = false;
  // Several picks per vertex (stratified over the pmf) change MIS's light density
  // to picks x pmf: a weight that forgot it would over- or under-count the hits.
  for (LightPick pick : {LightPick::Uniform, LightPick::Estimate, LightPick::All})
    for (int picks : {1, 2, 4}) {
      IntegratorSettings is{1, 3};
      is.light_pick = pick;
      is.light_picks = picks;
      const PathIntegrator integrator(scene, lights, material, is);
      EXPECT_NEAR(mean_channel(render(camera, integrator, rs).developed(0), 0), expected, 0.01 * expected)
          << to_string(pick) << ", " << picks << " picks";
    }
  IntegratorSettings bad{1, 3};
  bad.light_picks = 0;
  EXPECT_THROW(PathIntegrator(scene, lights, material, bad), Error);
}

TEST(RenderIntegrator, LightPicksAgreeOnFibresUnderTheDomeAndAnEnvironment) {
  // Fibres over a card, lit by a ring of LEDs of unequal power, a directional light
  // and an environment, several bounces: the estimate and all-lights strategies
  // converge to what uniform choice gives (image means within 2 %).
  SceneOptions so;
  so.backdrop.enabled = true;
  const Scene scene(test::make_test_feather(30.0f, 0.6f, 0.06f), so);
  LightSet lights;
  for (int k = 0; k < 6; ++k) {
    const float a = 2 * 3.14159265f * k / 6;
    lights.add(SphereLight{{40 * std::cos(a), 40 * std::sin(a), 30}, 1.5f, glm::vec3(20.0f * float(k + 1))});
  }
  lights.add(DirectionalLight{glm::normalize(glm::vec3(1, 1, 2)), glm::vec3(0.3f)});
  lights.set_environment(EnvironmentLight(glm::vec3(0.1f)));
  const FibreMaterial material(HairParams{}, AlbedoMap(glm::vec3(0.6f, 0.4f, 0.3f)));
  const Camera camera(CameraSpec{}, 16, 16, scene.feather_bounds());
  RenderSettings rs;
  rs.spp = 256;
  rs.progress = false;
  double mean[4][3];
  int row = 0;
  const std::pair<LightPick, int> strategies[] = {
      {LightPick::Uniform, 1}, {LightPick::Estimate, 1}, {LightPick::All, 1}, {LightPick::Estimate, 4}};
  for (const auto& [pick, picks] : strategies) {
    IntegratorSettings is;
    is.light_pick = pick;
    is.light_picks = picks;
    const Image img = render(camera, PathIntegrator(scene, lights, material, is), rs).developed(0);
    for (int c = 0; c < 3; ++c) mean[row][c] = mean_channel(img, c);
    ++row;
  }
  for (int r = 1; r < 4; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[r][c], mean[0][c], 0.02 * mean[0][c]) << "strategy " << r << " channel " << c;
}

TEST(RenderIntegrator, ConstantEnvironmentIsLeftToBcsdfSamplingWithoutBias) {
  // Fibres over a grey card under a uniform sky of 0.7, several bounces: given as a
  // colour the sky is reached by BCSDF sampling alone (no shadow ray at a card or
  // fibre vertex); given as a 2 x 1 map of the same colour it is light-sampled
  // with MIS. Both must give the same image (means within 0.5 %; they agree to 0.04 %).
  SceneOptions so;
  so.backdrop = {true, glm::vec3(0.5f)};
  const Scene scene(test::make_test_feather(30.0f, 0.6f, 0.06f), so);
  const auto map = std::filesystem::temp_directory_path() / ("plumage_env_" + std::to_string(getpid()) + ".exr");
  write_image(map, Image(2, 1, 3, 0.7f));
  LightSet constant, image;
  constant.set_environment(EnvironmentLight(glm::vec3(0.7f)));
  image.set_environment(EnvironmentLight(map));
  std::filesystem::remove(map);
  ASSERT_EQ(constant.sampled_count(), 0u);
  ASSERT_EQ(image.sampled_count(), 1u);
  const FibreMaterial material(HairParams{}, AlbedoMap(glm::vec3(0.6f, 0.4f, 0.3f)));
  const Camera camera(CameraSpec{}, 16, 16, scene.feather_bounds());
  double mean[2][3];
  std::int64_t shadow_rays[2], hits[2];
  int row = 0;
  for (const LightSet* lights : {&constant, &image}) {
    const PathIntegrator integrator(scene, *lights, material, IntegratorSettings{16, 3});
    RenderSettings rs;
    rs.spp = 256;
    rs.progress = false;
    const Image img = render(camera, integrator, rs).developed(0);
    for (int c = 0; c < 3; ++c) mean[row][c] = mean_channel(img, c);
    PathCounters counters;
    PixelSampler sampler(SamplerKind::Independent, 3);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        sampler.start(x, y, 0);
        sampler.next4();
        integrator.Li(camera.generate(x + 0.5f, y + 0.5f), sampler, counters);
      }
    shadow_rays[row] = counters.shadow_rays;
    hits[row] = counters.hits;
    ++row;
  }
  EXPECT_EQ(shadow_rays[0], 0) << "a constant sky needs no shadow ray at a card or fibre";
  EXPECT_GT(hits[0], 256) << "the paths must scatter for the test to mean anything";
  EXPECT_GE(shadow_rays[1], hits[1] / 2) << "a sky map is light-sampled";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[0][c], mean[1][c], 0.005 * mean[1][c]) << "channel " << c;
}
