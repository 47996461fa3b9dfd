// Variance allocation of samples over pixels (render.h, docs/skip-work.md): the
// counts follow the pilot's noise and cost, a pixel's own figures never change its
// count (what keeps the estimate unbiased), the image mean agrees with uniform
// allocation, and on a feather whose noise sits in a few pixels it reaches lower
// error for the same number of samples.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "plumage/common/error.h"
#include "plumage/renderer/render.h"
#include "render_test_feather.h"

using namespace plumage;
using test::mean_channel;

namespace {

double rmse(const Image& a, const Image& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) s += double(a.pixels[i] - b.pixels[i]) * (a.pixels[i] - b.pixels[i]);
  return std::sqrt(s / double(a.pixels.size()));
}

}  // namespace

TEST(SampleAllocation, CountsFollowNoiseAndCostAndKeepTheBudget) {
  const int W = 12, H = 8, spp = 64, pilot = 16;
  std::vector<double> var(W * H, 0.01), cost(W * H, 4.0);
  // A noisy block on the left, an expensive one on the right.
  for (int y = 2; y < 6; ++y)
    for (int x = 1; x < 4; ++x) var[y * W + x] = 1.0;
  for (int y = 2; y < 6; ++y)
    for (int x = 8; x < 11; ++x) cost[y * W + x] = 400.0;
  const std::vector<int> n = allocate_samples(var, cost, W, H, spp, pilot);
  ASSERT_EQ(n.size(), std::size_t(W * H));
  for (int v : n) EXPECT_GE(v, pilot);
  const double total = std::accumulate(n.begin(), n.end(), 0.0);
  EXPECT_NEAR(total / (W * H), spp, 0.05 * spp) << "the budget is spp per pixel on average";
  // Noise draws samples; cost (sigma / sqrt(cost)) repels them.
  EXPECT_GT(n[4 * W + 2], 3 * n[0]);
  EXPECT_LT(n[4 * W + 9], n[0]);
  // No noise anywhere: everyone keeps spp.
  const std::vector<double> flat(W * H, 0.0);
  for (int v : allocate_samples(flat, cost, W, H, spp, pilot)) EXPECT_EQ(v, spp);
}

TEST(SampleAllocation, APixelsOwnPilotNeverChangesItsCount) {
  // The unbiasedness argument: n_i is a function of the other pixels' pilots only.
  const int W = 9, H = 7, spp = 32, pilot = 8;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> var(W * H), cost(W * H);
  for (int i = 0; i < W * H; ++i) {
    var[i] = u(rng) * u(rng);
    cost[i] = 1 + 10 * u(rng);
  }
  const std::vector<int> base = allocate_samples(var, cost, W, H, spp, pilot);
  for (int i : {0, 4, 31, W * H - 1}) {
    std::vector<double> v2 = var, c2 = cost;
    v2[i] *= 50;
    c2[i] *= 0.1;
    const std::vector<int> changed = allocate_samples(v2, c2, W, H, spp, pilot);
    EXPECT_EQ(changed[i], base[i]) << "pixel " << i;
    // ... while its neighbours do react (the test can tell).
    const int x = i % W, y = i / W, j = (y > 0 ? y - 1 : y + 1) * W + x;
    EXPECT_NE(changed[j], base[j]) << "neighbour of pixel " << i;
  }
}

TEST(SampleAllocation, ParsesAndNamesTheChoices) {
  EXPECT_EQ(parse_sample_allocation("uniform"), SampleAllocation::Uniform);
  EXPECT_EQ(parse_sample_allocation("variance"), SampleAllocation::Variance);
  EXPECT_STREQ(to_string(SampleAllocation::Variance), "variance");
  EXPECT_THROW(parse_sample_allocation("adaptive"), Error);
}

// The test feather alone under one small bright light and a sky: the noise lives on
// the fibres; the sky seen around them has none.
TEST(SampleAllocation, UnbiasedAndLowerErrorForTheSameSamples) {
  const Scene scene(test::make_test_feather(30.0f, 0.6f, 0.06f), SceneOptions{});
  LightSet lights;
  lights.add(SphereLight{{20, 10, 40}, 2.0f, glm::vec3(60.0f)});
  lights.set_environment(EnvironmentLight(glm::vec3(0.2f)));
  const FibreMaterial material(HairParams{}, AlbedoMap(glm::vec3(0.6f, 0.4f, 0.3f)));
  const PathIntegrator integrator(scene, lights, material, IntegratorSettings{});
  const Camera camera(CameraSpec{}, 24, 32, scene.feather_bounds());
  RenderSettings rs;
  rs.progress = false;
  rs.allocation = SampleAllocation::Uniform;
  rs.spp = 1024;
  rs.seed = 99;
  const Image reference = render(camera, integrator, rs).developed(0);
  double err[2] = {0, 0}, mean[2] = {0, 0};
  rs.spp = 32;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    rs.seed = seed;
    int k = 0;
    for (SampleAllocation a : {SampleAllocation::Uniform, SampleAllocation::Variance}) {
      rs.allocation = a;
      const Image img = render(camera, integrator, rs).developed(0);
      err[k] += rmse(img, reference) / 4;
      mean[k] += mean_channel(img, 1) / 4;
      ++k;
    }
  }
  const double ref_mean = mean_channel(reference, 1);
  EXPECT_NEAR(mean[0], ref_mean, 0.01 * ref_mean);
  EXPECT_NEAR(mean[1], ref_mean, 0.01 * ref_mean) << "variance allocation must not shift the mean";
  EXPECT_LT(err[1], 0.9 * err[0]) << "uniform " << err[0] << ", variance " << err[1];
  RecordProperty("rmse_uniform_over_variance", std::to_string(err[0] / err[1]));
}
