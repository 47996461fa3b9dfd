// Lights: sphere-light sampling matches its pdf, the environment map's sampling
// pdf is a density, the dome rig file and --lights are read strictly, and
// missing files give a plumage::Error naming them.
#include <unistd.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "plumage/common/constants.h"
#include "plumage/common/error.h"
#include "plumage/common/image.h"
#include "plumage/renderer/dome_rig.h"
#include "plumage/renderer/light_set.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {
fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("plumage_render_lights_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}
}  // namespace

TEST(RenderLights, SphereSamplesHitTheSphereWithConstantPdf) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  for (float dist : {3.0f, 50.0f, 1e4f}) {
    const SphereLight l{{0, 0, dist}, 1.0f, glm::vec3(1)};
    const glm::vec3 p(0.3f, -0.2f, 0);
    double solid_angle = 0;
    for (int i = 0; i < 20000; ++i) {
      const auto s = sample_sphere_light(l, p, {u(rng), u(rng)});
      ASSERT_TRUE(s);
      const auto t = intersect_sphere(l, p, s->wi);
      ASSERT_TRUE(t) << "sampled direction misses the sphere";
      EXPECT_NEAR(*t, s->dist, 1e-3f * dist);
      EXPECT_FLOAT_EQ(s->pdf, sphere_light_pdf(l, p));
      solid_angle += 1.0 / s->pdf / 20000;
    }
    // The cone's solid angle 2 pi (1 - cos theta_max).
    const double d = glm::length(l.centre - p), st2 = 1.0 / (d * d);
    EXPECT_NEAR(solid_angle, 2 * kPiF * st2 / (1 + std::sqrt(1 - st2)), 1e-3 * solid_angle);
  }
  EXPECT_FALSE(sample_sphere_light({{0, 0, 0}, 1.0f, glm::vec3(1)}, {0.1f, 0, 0}, {0.5f, 0.5f}));
}

TEST(RenderLights, EnvironmentMapPdfIsADensityMatchingItsSamples) {
  // A lat-long map with one bright patch: sampling must favour it and the pdf
  // must integrate to one over the sphere.
  Image img(32, 16, 3, 0.1f);
  for (int y = 3; y < 6; ++y)
    for (int x = 20; x < 24; ++x) img.set_rgb(x, y, glm::vec3(50.0f));
  const fs::path path = temp_dir() / "env.exr";
  write_image(path, img);
  const EnvironmentLight env(path);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  double integral = 0, mean_ratio = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    // Importance-sampled estimate of the integral of luminance over the sphere.
    const EnvSample s = env.sample({u(rng), u(rng)});
    ASSERT_GT(s.pdf, 0);
    ASSERT_NEAR(s.pdf, env.pdf(s.wi), 1e-3f * s.pdf);
    mean_ratio += s.Le.y / s.pdf / n;
  }
  // Midpoint quadrature of the pdf over the sphere, 8x8 points per pixel.
  const int nt = 16 * 8, np = 32 * 8;
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      const float t = kPiF * (i + 0.5f) / nt, phi = 2 * kPiF * (j + 0.5f) / np;
      const glm::vec3 d{std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t)};
      integral += env.pdf(d) * std::sin(t) * (kPiF / nt) * (2 * kPiF / np);
    }
  EXPECT_NEAR(integral, 1.0, 0.005);
  // Exact integral of the piecewise-constant map: sum L * dphi * (cos t0 - cos t1).
  double exact = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      exact += img.rgb(x, y).y * (2 * kPiF / 32) * (std::cos(kPiF * y / 16) - std::cos(kPiF * (y + 1) / 16));
  EXPECT_NEAR(mean_ratio, exact, 0.01 * exact);
}

TEST(RenderLights, MissingOrBadEnvironmentMapNamesTheFile) {
  const fs::path missing = temp_dir() / "no_such_env.exr";
  try {
    EnvironmentLight env(missing);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().file, missing.string());
  }
  Image bad(4, 2, 3, 1.0f);
  bad.set_rgb(1, 1, glm::vec3(-1.0f));
  const fs::path neg = temp_dir() / "negative_env.exr";
  write_image(neg, bad);
  EXPECT_THROW(EnvironmentLight{neg}, Error);
  EXPECT_THROW(EnvironmentLight{glm::vec3(-1.0f)}, Error);
}

TEST(RenderLights, Dome25RigHas25LedsOnTheUpperHemisphere) {
  const DomeRig rig = read_dome_rig(fs::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  ASSERT_EQ(rig.leds.size(), 25u);
  for (const glm::vec3& p : rig.leds) {
    EXPECT_GT(p.z, 0.0f);
    EXPECT_NEAR(glm::length(p), 300.0f, 0.01f);
  }
  const auto lights = dome_lights(rig, parse_light_selection("1,5,12", 25), {1, 2, 3});
  ASSERT_EQ(lights.size(), 3u);
  EXPECT_EQ(lights[0].centre, rig.leds[0] + glm::vec3(1, 2, 3));
  EXPECT_EQ(lights[2].centre, rig.leds[11] + glm::vec3(1, 2, 3));
  // Radiant intensity I = L pi r^2 along any direction.
  EXPECT_NEAR(lights[0].radiance.x * kPiF * rig.led_radius * rig.led_radius, rig.intensity.x, 1e-2f * rig.intensity.x);
}

// intersect_spheres skips segments that stay below the lowest LED; its answer must
// be the brute-force nearest sphere hit before tmax for every ray, upward and
// downward, short and open, from below, among and above the LEDs.
TEST(RenderLights, SphereHitsMatchBruteForceOverRandomSegments) {
  const DomeRig rig = read_dome_rig(fs::path(PLUMAGE_DATA_DIR) / "rigs/dome25.json");
  LightSet lights;
  std::vector<SphereLight> spheres = dome_lights(rig, parse_light_selection("all", 25), {0, 0, 0});
  for (const SphereLight& l : spheres) lights.add(l);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> U(-1.0f, 1.0f);
  int hits = 0, skipped_short = 0;
  for (int k = 0; k < 200000; ++k) {
    const glm::vec3 o(400 * U(rng), 400 * U(rng), 350 * U(rng));
    // Half the rays aim near an LED (they are small), half anywhere.
    const SphereLight& aim = spheres[std::size_t(k) % spheres.size()];
    const glm::vec3 d = k % 2 == 0 ? glm::normalize(aim.centre + 2 * aim.radius * glm::vec3(U(rng), U(rng), U(rng)) - o)
                                   : glm::normalize(glm::vec3(U(rng), U(rng), U(rng)) + glm::vec3(0, 0, 1e-3f));
    const float tmax = k % 3 == 0 ? std::numeric_limits<float>::infinity() : 600 * (U(rng) + 1);
    std::optional<float> best;
    std::size_t best_i = 0;
    for (std::size_t i = 0; i < spheres.size(); ++i) {
      const auto t = intersect_sphere(spheres[i], o, d);
      if (t && *t < tmax && (!best || *t < *best)) best = t, best_i = i;
    }
    const auto got = lights.intersect_spheres(o, d, tmax);
    ASSERT_EQ(bool(got), bool(best)) << "ray " << k;
    if (got) {
      ++hits;
      EXPECT_EQ(got->light, best_i);
      EXPECT_EQ(got->t, *best);
    } else if (d.z > 0 && std::isfinite(tmax)) {
      ++skipped_short;
    }
  }
  // The sample reaches both sides of the early-out.
  EXPECT_GT(hits, 1000);
  EXPECT_GT(skipped_short, 10000);
}

TEST(RenderLights, RigFileErrorsNameThePlace) {
  try {
    parse_dome_rig("{\n  \"leds\": [\n    {\"position\": [1, 2, ]}\n  ]\n}\n", "rig.json");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().file, "rig.json");
    EXPECT_EQ(e.where().line, 3);
    EXPECT_GT(e.where().column, 0);
  }
  EXPECT_THROW(parse_dome_rig("{\"leds\": []}", "r.json"), Error);
  EXPECT_THROW(parse_dome_rig("{\"leds\": [{\"position\": [0, 0, 1]}], \"led_radius\": -2}", "r.json"), Error);
  EXPECT_THROW(parse_dome_rig("{\"leds\": [{\"position\": [0, 0]}]}", "r.json"), Error);
  EXPECT_THROW(read_dome_rig(temp_dir() / "missing_rig.json"), Error);
}

TEST(RenderLights, LightSelectionIsStrict) {
  EXPECT_EQ(parse_light_selection("all", 3), (std::vector<int>{0, 1, 2}));
  EXPECT_TRUE(parse_light_selection("none", 3).empty());
  EXPECT_EQ(parse_light_selection("3,1,1", 5), (std::vector<int>{0, 2}));
  EXPECT_EQ(parse_light_selection("2-4,1", 5), (std::vector<int>{0, 1, 2, 3}));
  for (const char* bad : {"0", "26", "1,,2", "x", "4-2", "1.5", "-3"})
    EXPECT_THROW(parse_light_selection(bad, 25), Error) << bad;
}

TEST(RenderLights, PickPmfSumsToOneAndKeepsEveryLight) {
  const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
  const std::vector<std::vector<float>> cases{
      {1, 2, 3, 4},        {0, 0, 5},        {1e-30f, 1e30f, 1},  {-1, nan, 2, 0},
      {7},                 {0, 0, 0},        {inf, 1, 1},         {1e30f, 1e30f, 1e30f, 1e30f},
      {1e-45f, 0, 1e-45f}, {-inf, nan, -0.0f}};
  for (const auto& w : cases) {
    std::vector<float> pmf(w.size(), -1.0f);
    light_pick_pmf(w, pmf);
    double sum = 0;
    for (float p : pmf) {
      EXPECT_GE(p, kUniformPickShare / float(w.size()) * (1 - 1e-5f));
      EXPECT_TRUE(std::isfinite(p));
      sum += p;
    }
    EXPECT_NEAR(sum, 1.0, 1e-5) << "case of " << w.size() << " lights starting " << w[0];
  }
  // Proportional to the estimates beyond the uniform floor.
  std::vector<float> pmf(3);
  light_pick_pmf(std::vector<float>{1, 3, 0}, pmf);
  const float floor = kUniformPickShare / 3;
  EXPECT_NEAR(pmf[0], floor + 0.25f * (1 - kUniformPickShare), 1e-6f);
  EXPECT_NEAR(pmf[1], floor + 0.75f * (1 - kUniformPickShare), 1e-6f);
  EXPECT_NEAR(pmf[2], floor, 1e-6f);
}

TEST(RenderLights, PickFromPmfFollowsThePmf) {
  const std::vector<float> pmf{0.1f, 0.0f, 0.6f, 0.3f};
  std::vector<int> hits(pmf.size(), 0);
  const int n = 10000;
  for (int k = 0; k < n; ++k) ++hits[pick_from_pmf(pmf, (k + 0.5f) / n)];
  for (std::size_t i = 0; i < pmf.size(); ++i) EXPECT_NEAR(hits[i] / double(n), pmf[i], 2.0 / n) << "light " << i;
  // u beyond a cdf that rounding left short of 1 still lands on a light with p > 0.
  EXPECT_EQ(pick_from_pmf(std::vector<float>{0.5f, 0.49999f, 0.0f}, 0.999999f), 1u);
}

TEST(RenderLights, ProxiesPointAtTheLightsWithTheirStrength) {
  LightSet lights;
  lights.add(SphereLight{{0, 0, 10}, 1.0f, glm::vec3(2.0f)});
  lights.add(DirectionalLight{{1, 0, 0}, glm::vec3(0.5f)});
  lights.set_environment(EnvironmentLight(glm::vec3(0.25f)));
  ASSERT_EQ(lights.count(), 3u);
  EXPECT_EQ(lights.environment_index(), 2u);
  LightProxies px;
  lights.proxies(glm::vec3(0), px);
  ASSERT_EQ(px.size(), 3u);
  EXPECT_NEAR(px.wi(0).z, 1.0f, 1e-6f);
  // Le x solid angle of the cone, 2 pi (1 - cos theta_max).
  const float omega = 2 * kPiF * (1 - std::sqrt(1 - 0.01f));
  EXPECT_NEAR(px.strength(0).x, 2.0f * omega, 1e-3f * 2.0f * omega);
  EXPECT_NEAR(px.wi(1).x, 1.0f, 1e-6f);
  EXPECT_NEAR(px.strength(1).y, 0.5f, 1e-6f);
  EXPECT_EQ(px.environment, 2u);
  EXPECT_NEAR(px.strength(2).z, kPiF * 0.25f, 1e-4f);
  // Inside a sphere the light surrounds the point: half the sphere of directions.
  lights.proxies(glm::vec3(0, 0, 9.5f), px);
  EXPECT_NEAR(px.strength(0).x, 2.0f * 2 * kPiF, 1e-4f);
  EXPECT_NEAR(px.wi(0).z, 1.0f, 1e-6f);
  // Off axis and far: the cone's solid angle falls as pi r^2 / d^2, the direction
  // points at the centre.
  lights.proxies(glm::vec3(300, 400, 10), px);
  EXPECT_NEAR(px.wi(0).x, -0.6f, 1e-6f);
  EXPECT_NEAR(px.wi(0).y, -0.8f, 1e-6f);
  EXPECT_NEAR(px.strength(0).x, 2.0f * kPiF / 250000.0f, 1e-3f * 2.0f * kPiF / 250000.0f);
  // Without an environment the index says so.
  LightSet bare;
  bare.add(SphereLight{{0, 0, 10}, 1.0f, glm::vec3(2.0f)});
  bare.proxies(glm::vec3(0), px);
  EXPECT_EQ(px.environment, 1u);
  EXPECT_EQ(parse_light_pick("estimate"), LightPick::Estimate);
  EXPECT_THROW(parse_light_pick("power"), Error);
}
